#include "app/gui/sim_worker.h"
#include "app/io/mesh_import.h"
#include "core/frame/text.h"
#include "core/model/run_loop.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <exception>

namespace ff::app::gui {
namespace {
}  // namespace

const char* to_string(WorkerState s) {
  switch (s) {
    case WorkerState::paused: return "paused";
    case WorkerState::running: return "running";
    case WorkerState::stepping: return "stepping";
    case WorkerState::finished: return "finished";
    case WorkerState::failed: return "failed";
  }
  return "?";
}

SimWorker::SimWorker(scene::LoadedScene scene, std::string scene_text, std::string opened_text, std::string opened_from,
                     std::function<void()> on_change)
    : scene_(std::move(scene)), on_change_(std::move(on_change)) {
  status_.scene_path = scene_.path;
  status_.scene_text = std::move(scene_text);
  status_.opened_text = std::move(opened_text);
  status_.opened_from = std::move(opened_from);
  find_selections(status_.scene_text, scene_.path, &status_.selections, &status_.patch_edges);
  start_generation();
  thread_ = std::thread([this] { main(); });
}

SimWorker::~SimWorker() {
  push(Command::make(Command::Kind::quit));
  stop_ = true;
  if (thread_.joinable()) thread_.join();
}

std::uint64_t SimWorker::push(Command c) {
  std::lock_guard lock(mutex_);
  c.seq = next_seq_++;
  queue_.push_back(std::move(c));
  cv_.notify_all();
  return c.seq;
}

std::uint64_t SimWorker::run() { return push(Command::make(Command::Kind::run)); }
std::uint64_t SimWorker::pause() { return push(Command::make(Command::Kind::pause)); }
std::uint64_t SimWorker::step(long long n) { return push(Command::make(Command::Kind::step, "", "", n)); }
std::uint64_t SimWorker::reset() { return push(Command::make(Command::Kind::reset)); }
std::uint64_t SimWorker::set(const std::string& key, const std::string& value) {
  return push(Command::make(Command::Kind::set, key, value));
}
std::uint64_t SimWorker::edit(const std::string& what, DraftOp op) {
  Command c = Command::make(Command::Kind::edit, what);
  c.op = std::move(op);
  return push(std::move(c));
}
std::uint64_t SimWorker::load_text(const std::string& text, const std::string& path, const std::string& opened_from) {
  Command c = Command::make(Command::Kind::load_text, path, text);
  c.c = opened_from;
  return push(std::move(c));
}
std::uint64_t SimWorker::probe(int node) { return push(Command::make(Command::Kind::probe, "", "", node)); }
std::uint64_t SimWorker::pace(double steps_per_second) {
  return push(Command::make(Command::Kind::pace, "", "", 0, steps_per_second));
}

WorkerUpdate SimWorker::take() {
  std::lock_guard lock(mutex_);
  WorkerUpdate u;
  u.status = status_;
  u.frame = std::move(frame_);
  u.samples = std::move(samples_);
  frame_.reset();
  samples_.clear();
  return u;
}

void SimWorker::find_selections(const std::string& text, const std::string& path,
                                std::shared_ptr<const std::vector<scene::EntrySelection>>* selections,
                                std::shared_ptr<const std::vector<std::pair<std::string, std::string>>>* patch_edges) {
  // a model without a shell structure has none; one whose selections cannot be worked out shows
  // no highlights (the scene itself was accepted)
  try {
    auto sel = scene::scene_selections_of_text(text, path, {}, io::scene_context());
    if (!sel) return;
    std::vector<std::pair<std::string, std::string>> edges;
    for (const mesh::Patch& p : sel->mesh.patches)
      for (const std::string& e : p.edge_names)
        if (!e.empty()) edges.emplace_back(p.name, e);
    *patch_edges = std::make_shared<const std::vector<std::pair<std::string, std::string>>>(std::move(edges));
    *selections = std::make_shared<const std::vector<scene::EntrySelection>>(std::move(sel->entries));
  } catch (const std::exception&) {
  }
}

// ---- worker thread ------------------------------------------------------------------------------

void SimWorker::start_generation() {
  const Simulation& sim = *scene_.simulation;
  ++status_.generation;
  status_.info = std::make_shared<const RunInfo>(sim.info());
  status_.scene_name = scene_.name;
  status_.scene_path = scene_.path;
  status_.output = scene_.output;
  status_.end_time = sim.end_time();
  status_.steps_per_frame = std::max<long long>(1, sim.output_every());
  status_.outcome.reset();
  status_.metrics.clear();
  status_.modes.reset();
  if (probe_node_ >= static_cast<int>(status_.info->mesh.point_count())) probe_node_ = -1;
  status_.probe_node = probe_node_;
  status_.state = running_ ? WorkerState::running : WorkerState::paused;
  frame_.reset();
  samples_.clear();
  last_published_.reset();
  show_reached_state_ = false;
  steps_left_ = 0;
  finished_ = false;
  changed();
}

void SimWorker::changed() {
  ++status_.revision;
  if (on_change_) on_change_();
}

void SimWorker::set_message(std::string text, bool error) {
  status_.message = std::move(text);
  status_.message_is_error = error;
  ++status_.message_seq;
  changed();
}

bool SimWorker::settled() const { return !pending_ && steps_left_ == 0; }

void SimWorker::main() {
  const RunLoop::Publish publish = [this](Frame&& f) { on_frame(std::move(f)); };
  while (true) {
    stop_ = false;
    RunLoop loop(*scene_.simulation);
    loop_ = &loop;
    // the loop steps only while running or stepping: pausing is not stepping (no wait inside a
    // solver callback); commands are applied between steps, on this thread
    auto guarded = [&](auto&& body) {
      try {
        return body();
      } catch (const std::exception& e) {
        failure_ = std::string("solver error: ") + e.what();
        return false;
      }
    };
    failure_.clear();
    bool going = guarded([&] { return loop.start(publish); });
    while (going) {
      {
        std::unique_lock lock(mutex_);
        serve(lock);
        if (quit_ || pending_) break;
      }
      going = guarded([&] { return loop.advance(publish, stop_); });
      if (going && steps_left_ > 0) {
        std::unique_lock lock(mutex_);
        // Step counts solver steps: the last one shows its state even between output frames
        if (--steps_left_ == 0) {
          lock.unlock();
          loop.publish_pending(publish);
        }
      }
    }
    std::unique_lock lock(mutex_);
    loop_ = nullptr;
    if (!quit_ && !pending_) {
      // the run ended by itself: completed, diverged or failed; wait for what comes next
      RunOutcome outcome = loop.outcome();
      if (!failure_.empty()) outcome.status = RunStatus::failed, outcome.reason = failure_;
      finished_ = true;
      running_ = false;
      steps_left_ = 0;
      status_.outcome = outcome;
      try {
        status_.metrics = scene_.simulation->metrics();
      } catch (const std::exception&) {
        status_.metrics.clear();  // a run that failed early may have nothing to measure
      }
      if (const ModeSet* modes = scene_.simulation->modes()) status_.modes = std::make_shared<const ModeSet>(*modes);
      status_.state = outcome.status == RunStatus::failed ? WorkerState::failed : WorkerState::finished;
      changed();
      while (!quit_ && !pending_) {
        if (status_.settled_seq != handled_seq_) status_.settled_seq = handled_seq_, changed();
        cv_.wait(lock, [&] { return !queue_.empty(); });
        while (!queue_.empty() && !quit_ && !pending_) {
          const Command c = queue_.front();
          queue_.pop_front();
          handle(c, lock);
        }
      }
    }
    if (quit_) return;
    scene_ = std::move(*pending_);
    pending_.reset();
    status_.scene_text = std::move(pending_text_);
    status_.opened_text = std::move(pending_opened_text_);
    status_.opened_from = std::move(pending_opened_from_);
    status_.selections = std::move(pending_selections_);
    status_.patch_edges = std::move(pending_patch_edges_);
    start_generation();
  }
}

Sample SimWorker::sample_of(const Frame& f, int node) const {
  Sample s;
  s.step = f.step;
  s.time = f.time;
  s.load_factor = f.load_factor;
  s.probes = f.probes;
  s.stats = f.stats;
  if (node >= 0 && 3 * static_cast<std::size_t>(node) + 2 < f.points.size()) {
    const std::size_t i = 3 * static_cast<std::size_t>(node);
    const auto& ref = scene_.simulation->info().mesh.reference_points;
    s.node = node;
    s.has_deflection = f.base_points.size() == f.points.size();
    double u2 = 0, d2 = 0;
    for (int k = 0; k < 3; ++k) {
      s.node_position[k] = f.points[i + k];
      if (i + k < ref.size()) u2 += std::pow(f.points[i + k] - ref[i + k], 2);
      if (s.has_deflection) d2 += std::pow(f.points[i + k] - f.base_points[i + k], 2);
    }
    s.node_displacement = std::sqrt(u2);
    s.node_deflection = std::sqrt(d2);
  }
  return s;
}

void SimWorker::on_frame(Frame&& f) {
  Sample s = sample_of(f, probe_node_);
  // kept for answering a probe: the state only, not the fields or the step log
  Frame kept;
  kept.step = f.step;
  kept.time = f.time;
  kept.load_factor = f.load_factor;
  kept.points = f.points;
  kept.base_points = f.base_points;
  kept.probes = f.probes;
  kept.stats = f.stats;
  std::lock_guard lock(mutex_);
  last_published_ = std::move(kept);
  frame_ = std::move(f);
  samples_.push_back(std::move(s));
  changed();
}

void SimWorker::serve(std::unique_lock<std::mutex>& lock) {
  while (true) {
    // commands after a rebuild wait for the new run (a step queued behind a set steps the new model)
    while (!queue_.empty() && !quit_ && !pending_) {
      const Command c = queue_.front();
      queue_.pop_front();
      handle(c, lock);
    }
    if (quit_ || pending_) return;  // main() ends this run and swaps in the new scene
    if (show_reached_state_) {
      // paused between output frames: publish the state reached before saying the pause took effect
      show_reached_state_ = false;
      if (!running_ && steps_left_ == 0 && loop_) {
        lock.unlock();
        loop_->publish_pending([this](Frame&& f) { on_frame(std::move(f)); });
        lock.lock();
        continue;
      }
    }
    const WorkerState state = running_ ? WorkerState::running : steps_left_ > 0 ? WorkerState::stepping : WorkerState::paused;
    const std::uint64_t settled_seq = settled() ? handled_seq_ : status_.settled_seq;
    if (state != status_.state || settled_seq != status_.settled_seq) {
      status_.state = state, status_.settled_seq = settled_seq;
      changed();
    }
    if (steps_left_ > 0) return;
    if (running_) {
      if (pace_ <= 0) return;
      // paced: hold the solver until the next step is due, but wake for commands
      const auto due = last_release_ + std::chrono::duration_cast<std::chrono::steady_clock::duration>(
                                           std::chrono::duration<double>(1.0 / pace_));
      if (cv_.wait_until(lock, due, [&] { return !queue_.empty(); })) continue;
      last_release_ = std::chrono::steady_clock::now();
      return;
    }
    cv_.wait(lock, [&] { return !queue_.empty(); });
  }
}

void SimWorker::handle(const Command& c, std::unique_lock<std::mutex>& lock) {
  // the text in effect once the commands before this one have: a built edit waits in pending_
  const std::string path = pending_ ? pending_->path : status_.scene_path;
  const std::string text = pending_ ? pending_text_ : status_.scene_text;
  const std::string opened_text = pending_ ? pending_opened_text_ : status_.opened_text;
  const std::string opened_from = pending_ ? pending_opened_from_ : status_.opened_from;
  // builds a scene text off the lock; on success it waits in pending_ for the run to stop
  const auto rebuild = [&](const std::string& new_path, const std::string& new_text, const std::string& what,
                           const std::string& new_opened_text, const std::string& new_opened_from) {
    lock.unlock();
    std::optional<scene::LoadedScene> built;
    std::string error;
    std::shared_ptr<const std::vector<scene::EntrySelection>> selections;
    std::shared_ptr<const std::vector<std::pair<std::string, std::string>>> patch_edges;
    try {
      built = scene::load_scene_text(new_text, new_path, {}, io::scene_context());
    } catch (const std::exception& e) {
      error = e.what();
    }
    if (built) find_selections(new_text, new_path, &selections, &patch_edges);
    lock.lock();
    if (!built) {
      set_message(what + " refused:\n" + error, true);
      return false;
    }
    pending_ = std::move(built);
    pending_text_ = new_text;
    pending_opened_text_ = new_opened_text;
    pending_opened_from_ = new_opened_from;
    pending_selections_ = std::move(selections);
    pending_patch_edges_ = std::move(patch_edges);
    return true;
  };
  const auto rebuild_edit = [&](const std::string& new_text, const std::string& what) {
    return rebuild(path, new_text, what, opened_text, opened_from);
  };
  // a set-up edit composed off the lock from the text in effect; its refusal says why
  const auto compose = [&](const DraftOp& op, const std::string& what) -> std::optional<DraftEdit> {
    lock.unlock();
    std::optional<DraftEdit> e;
    std::string error;
    try {
      e = op(text, path);
    } catch (const std::exception& ex) {
      error = ex.what();
    }
    lock.lock();
    if (!e) set_message(what + " refused:\n" + error, true);
    return e;
  };
  const auto restarted = [&](const std::string& what, const std::string& note) {
    if (finished_) running_ = false;
    set_message(what + (note.empty() ? "" : " (" + note + ")") + "; restarted at t = 0", false);
  };

  switch (c.kind) {
    case Command::Kind::run:
      if (finished_) {
        if (rebuild_edit(text, "restart")) running_ = true;
      } else {
        running_ = true;
        steps_left_ = 0;
        last_release_ = std::chrono::steady_clock::now();
      }
      break;
    case Command::Kind::pause:
      if (running_ || steps_left_ > 0) show_reached_state_ = !finished_;
      running_ = false;
      steps_left_ = 0;
      break;
    case Command::Kind::step:
      if (finished_) {
        set_message("the run has ended; reset to start again", false);
      } else {
        running_ = false;
        steps_left_ += std::max<long long>(c.n, 1);
      }
      break;
    case Command::Kind::reset:
      if (rebuild_edit(text, "reset")) running_ = false;
      break;
    case Command::Kind::set: {
      const std::string what = "set " + c.a + " = " + c.b;
      // a key the schema declares live changes the running model from its next step, once the run
      // has left t = 0 (before, it is the scene's own value); the run goes on, and the text gets a
      // [[timeline]] entry at the time it took effect. Anything else rebuilds.
      const double now = scene_.simulation->time();
      const bool live_now = !finished_ && !pending_ && now > 0 && scene_.schema &&
                            scene_.schema->find_key(c.a) && scene_.schema->find_key(c.a)->live;
      if (live_now) {
        const std::optional<DraftEdit> e =
            compose([&](const std::string& t, const std::string& p) { return with_live_edit(t, p, c.a, c.b, now); }, what);
        if (!e) break;
        if (const std::string why = scene::change_live(scene_, c.a, c.b); !why.empty()) {
          set_message(what + " refused:\n" + why, true);
          break;
        }
        status_.scene_text = e->text;
        set_message(what + " live from t = " + significant(now) + ": the run goes on with it (" + e->note + ")",
                    false);
        break;
      }
      const std::optional<DraftEdit> e =
          compose([&](const std::string& t, const std::string& p) { return with_key_set(t, p, c.a, c.b); }, what);
      if (e && rebuild_edit(e->text, what)) restarted(what, e->note);
      break;
    }
    case Command::Kind::edit: {
      const std::optional<DraftEdit> e = compose(c.op, c.a);
      if (e && rebuild_edit(e->text, c.a)) restarted(c.a, e->note);
      break;
    }
    case Command::Kind::load_text:
      if (rebuild(c.a, c.b, "open " + (c.c.empty() ? std::string("a new problem") : c.c), c.b, c.c)) {
        running_ = false;
        probe_node_ = -1;
        set_message("opened " + (c.c.empty() ? std::string("a new problem") : c.c), false);
      }
      break;
    case Command::Kind::probe: {
      const int n = static_cast<int>(scene_.simulation->info().mesh.point_count());
      if (c.n >= 0 && c.n < n) {
        probe_node_ = static_cast<int>(c.n);
        status_.probe_node = probe_node_;
        // answered at once from the state on show, so the window never shows the node without
        // its values (paused, finished or between frames of a run)
        if (last_published_) {
          Sample s = sample_of(*last_published_, probe_node_);
          s.probe_answer = true;
          samples_.push_back(std::move(s));
        }
      } else if (c.n < 0) {
        probe_node_ = -1;
        status_.probe_node = -1;
      } else {
        set_message("probe " + std::to_string(c.n) + " refused: the mesh has nodes 0 to " + std::to_string(n - 1),
                    true);
      }
      break;
    }
    case Command::Kind::pace:
      pace_ = std::max(0.0, c.x);
      status_.pace = pace_;
      break;
    case Command::Kind::quit:
      quit_ = true;
      break;
  }
  handled_seq_ = c.seq;
  changed();
}

}  // namespace ff::app::gui
