// The GUI's solver thread: commands go in through the queue, copies come out through take().
// Paused at t = 0 after start; step N advances exactly N steps; set rebuilds and restarts; a
// refused edit leaves the model alone and says why; run goes to the end.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cmath>
#include <chrono>
#include <functional>
#include <thread>

#include "app/gui/sim_worker.h"
#include "core/scene/scene_edit.h"
#include "tests/support/plate_modes.h"

namespace ff::app::gui {
namespace {

const std::string kScene = std::string(FF_SOURCE_DIR) + "/assets/scenes/hub_beam_fem_tau1.toml";

/// A worker on the scene file `path` with `overrides` folded into its text, as the window starts one.
std::unique_ptr<SimWorker> worker_on(const std::string& path, const std::vector<std::string>& overrides = {},
                                     std::function<void()> wake = {}) {
  const std::string opened = scene::read_scene_text(path);
  const std::string text = scene::edited_scene_text(opened, path, overrides);
  return std::make_unique<SimWorker>(scene::load_scene_text(text, path), text, opened, path, std::move(wake));
}

scene::Document document_of(const WorkerStatus& s) {
  return scene::validate(scene::schema_for_text(s.scene_text), s.scene_text, s.scene_path);
}

/// Takes updates until `done` holds (10 s at most), keeping the samples and the newest frame.
struct Watcher {
  SimWorker& w;
  WorkerStatus status;
  std::vector<Sample> samples;
  std::optional<Frame> frame;
  bool until(const std::function<bool()>& done) {
    const auto t0 = std::chrono::steady_clock::now();
    while (std::chrono::steady_clock::now() - t0 < std::chrono::seconds(10)) {
      WorkerUpdate u = w.take();
      if (u.status.generation != status.generation) samples.clear();
      status = u.status;
      for (Sample& s : u.samples) samples.push_back(std::move(s));
      if (u.frame) frame = std::move(u.frame);
      if (done()) return true;
      std::this_thread::sleep_for(std::chrono::milliseconds(2));
    }
    return false;
  }
  bool settled(std::uint64_t seq) {
    return until([&] { return status.settled_seq >= seq; });
  }
};

// The modes of an eigen-analysis reach the window once its run has ended (the Modes list and the
// `mode N` action read WorkerStatus::modes), and not before
TEST(GuiSimWorker, ModesArriveWhenTheRunHasEnded) {
  scene::LoadedScene scene;
  scene.name = "ss_plate_modes";
  scene.path = "(test model)";
  scene.simulation = std::make_unique<ff::test::PlateModesSimulation>(true);
  SimWorker w(std::move(scene), "", "", "");
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.until([&] { return watch.frame.has_value(); }));
  EXPECT_EQ(watch.status.modes, nullptr) << "no modes before the run";
  w.run();
  ASSERT_TRUE(watch.until([&] { return watch.status.state == WorkerState::finished; }));
  ASSERT_NE(watch.status.modes, nullptr);
  const ModeSet expected = ff::test::plate_modes(ff::test::plate_info());
  ASSERT_EQ(watch.status.modes->modes.size(), expected.modes.size());
  EXPECT_EQ(watch.status.modes->modes[2].value, expected.modes[2].value);
  EXPECT_EQ(watch.status.modes->modes[2].displacement, expected.modes[2].displacement);
  EXPECT_EQ(watch.status.modes->analysis, "modal");
}

TEST(GuiSimWorker, StepsSetsAndRuns) {
  const auto worker = worker_on(kScene);
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.until([&] { return watch.frame.has_value(); }));
  EXPECT_EQ(watch.status.state, WorkerState::paused);
  EXPECT_EQ(watch.frame->step, 0);
  const std::uint64_t gen0 = watch.status.generation;

  // step 3: three more frames, then paused again
  ASSERT_TRUE(watch.settled(w.step(3)));
  ASSERT_TRUE(watch.frame.has_value());
  EXPECT_EQ(watch.frame->step, 3);
  EXPECT_NEAR(watch.frame->time, 0.15, 1e-12);
  EXPECT_EQ(watch.samples.size(), 4u);
  EXPECT_EQ(watch.status.state, WorkerState::paused);

  // probe a node: its displacement is recorded from the next frame on
  ASSERT_TRUE(watch.settled(w.probe(5)));
  EXPECT_EQ(watch.status.probe_node, 5);
  ASSERT_TRUE(watch.settled(w.step(1)));
  EXPECT_GT(watch.samples.back().node_displacement, 0.0);

  // a valid edit: new generation, back at t = 0 with the new step
  ASSERT_TRUE(watch.settled(w.set("solver.dt", "0.02")));
  EXPECT_EQ(watch.status.generation, gen0 + 1);
  EXPECT_EQ(document_of(watch.status).number("solver.dt"), 0.02);  // the text in effect has it
  ASSERT_TRUE(watch.settled(w.step(2)));
  EXPECT_NEAR(watch.frame->time, 0.04, 1e-12);

  // a refused edit: same generation, an error message naming the key
  const std::uint64_t msg = watch.status.message_seq;
  ASSERT_TRUE(watch.settled(w.set("solver.dt", "-1")));
  EXPECT_EQ(watch.status.generation, gen0 + 1);
  EXPECT_GT(watch.status.message_seq, msg);
  EXPECT_TRUE(watch.status.message_is_error);
  EXPECT_NE(watch.status.message.find("solver.dt"), std::string::npos) << watch.status.message;

  // run to the end
  w.run();
  ASSERT_TRUE(watch.until([&] { return watch.status.state == WorkerState::finished; }));
  ASSERT_TRUE(watch.status.outcome.has_value());
  EXPECT_EQ(watch.status.outcome->status, RunStatus::completed);
  EXPECT_NEAR(watch.samples.back().time, 10.0, 1e-9);
  EXPECT_EQ(static_cast<long long>(watch.samples.size()), 501);  // 10 s / 0.02 s + the initial state

  // reset: t = 0 again, paused
  ASSERT_TRUE(watch.settled(w.reset()));
  EXPECT_EQ(watch.status.state, WorkerState::paused);
  EXPECT_EQ(watch.frame->step, 0);
}

TEST(GuiSimWorker, StepQueuedBehindASetStepsTheNewModel) {
  const auto worker = worker_on(kScene);
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  w.set("solver.dt", "0.02");
  ASSERT_TRUE(watch.settled(w.step(2)));
  ASSERT_TRUE(watch.frame.has_value());
  EXPECT_EQ(watch.frame->step, 2);
  EXPECT_NEAR(watch.frame->time, 0.04, 1e-12);
  EXPECT_EQ(watch.status.state, WorkerState::paused);
}

TEST(GuiSimWorker, PausesWhileRunningAndQuitsPromptly) {
  const auto worker = worker_on(kScene, {"solver.end=1000"});
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.settled(w.pace(2000)));
  ASSERT_TRUE(watch.settled(w.run()));
  ASSERT_TRUE(watch.until([&] { return !watch.samples.empty() && watch.samples.back().step >= 20; }));
  ASSERT_TRUE(watch.settled(w.pause()));
  EXPECT_EQ(watch.status.state, WorkerState::paused);
  const std::int64_t at = watch.frame->step;
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  watch.until([] { return true; });
  EXPECT_EQ(watch.frame->step, at);  // nothing moves while paused
  // the destructor quits while paused
}

// A live key (scene::change_live) changes the running model: same generation, time goes on
// from where it was; the torque probe shows the new amplitude; the text in effect gets a
// [[timeline]] entry at the time the change took effect, so a reset (a run of the text) makes
// the same change at the same step.
TEST(GuiSimWorker, LiveKeyChangesTheRunWithoutRestart) {
  const auto worker = worker_on(kScene);
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.until([&] { return watch.frame.has_value(); }));
  const std::uint64_t gen0 = watch.status.generation;
  ASSERT_TRUE(watch.settled(w.step(4)));
  ASSERT_TRUE(watch.settled(w.set("torque.amplitude", "0")));
  EXPECT_EQ(watch.status.generation, gen0);  // not rebuilt
  EXPECT_NE(watch.status.message.find("live"), std::string::npos) << watch.status.message;
  const double changed_at = watch.frame->time;  // step 4
  {
    const scene::Document d = document_of(watch.status);
    ASSERT_EQ(d.count("timeline"), 1u);
    EXPECT_EQ(d.number("timeline.at", 0), changed_at);
    EXPECT_EQ(d.number("timeline.torque_scale", 0), 0.0);
    const scene::Document opened = scene::validate(scene::schema_for_text(watch.status.opened_text),
                                                   watch.status.opened_text, kScene);
    EXPECT_EQ(d.number("torque.amplitude"), opened.number("torque.amplitude"));  // the scene's own value stays
  }
  ASSERT_TRUE(watch.settled(w.step(2)));
  ASSERT_TRUE(watch.frame.has_value());
  EXPECT_EQ(watch.frame->step, 6);  // went on from step 4
  const RunInfo& info = *watch.status.info;
  std::size_t torque = info.probes.size();
  for (std::size_t k = 0; k < info.probes.size(); ++k)
    if (info.probes[k].name == "torque") torque = k;
  ASSERT_LT(torque, info.probes.size());
  EXPECT_EQ(watch.frame->probes[torque], 0.0);
  const std::vector<Sample> live_run = watch.samples;

  // the text reproduces the run: reset rebuilds from it, and the same steps give the same probes
  ASSERT_TRUE(watch.settled(w.reset()));
  EXPECT_EQ(watch.status.generation, gen0 + 1);
  ASSERT_TRUE(watch.settled(w.step(6)));
  ASSERT_EQ(watch.samples.size(), live_run.size());
  for (std::size_t i = 0; i < live_run.size(); ++i) {
    EXPECT_EQ(watch.samples[i].step, live_run[i].step);
    EXPECT_EQ(watch.samples[i].probes, live_run[i].probes) << "sample " << i;
  }
}

// A live key's value the schema refuses changes nothing: same generation, same edits, time where
// it was, and an error naming the key and what it expects.
TEST(GuiSimWorker, RefusedLiveValueLeavesTheRunAlone) {
  const auto worker = worker_on(kScene);
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.until([&] { return watch.frame.has_value(); }));
  const std::uint64_t gen0 = watch.status.generation;
  ASSERT_TRUE(watch.settled(w.step(2)));
  for (const char* bad : {"-1", "fast", "[1, 2]"}) {
    const std::uint64_t msg = watch.status.message_seq;
    ASSERT_TRUE(watch.settled(w.set("torque.amplitude", bad)));
    EXPECT_EQ(watch.status.generation, gen0) << bad;
    EXPECT_EQ(watch.status.scene_text, watch.status.opened_text) << bad;  // nothing written
    EXPECT_GT(watch.status.message_seq, msg) << bad;
    EXPECT_TRUE(watch.status.message_is_error) << bad;
    EXPECT_NE(watch.status.message.find("key 'torque.amplitude': expected a number in [0, 1e+100]"), std::string::npos)
        << watch.status.message;
  }
  ASSERT_TRUE(watch.settled(w.step(1)));
  EXPECT_EQ(watch.frame->step, 3);  // went on from step 2
}

// Step counts solver steps, not output frames: with a frame every 5 steps (a coarse double
// pendulum of shells), step 3 stops at solver step 3 and shows that state (a frame published
// between the output cadence), step 4 more at 7. It used to advance 3 frames, 15 steps.
TEST(GuiSimWorker, StepAdvancesSolverStepsNotFrames) {
  const std::vector<std::string> coarse = {"part[0].n1=4", "part[0].n2=4", "part[1].n1=4", "part[1].n2=4",
                                           "solver.output_every=5"};
  const auto worker = worker_on(std::string(FF_SOURCE_DIR) + "/assets/scenes/double_pendulum_shells.toml", coarse);
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.until([&] { return watch.frame.has_value(); }));
  EXPECT_EQ(watch.status.steps_per_frame, 5);
  ASSERT_TRUE(watch.settled(w.step(3)));
  EXPECT_EQ(watch.frame->step, 3);
  EXPECT_EQ(watch.status.state, WorkerState::paused);
  ASSERT_TRUE(watch.settled(w.step(4)));
  EXPECT_EQ(watch.frame->step, 7);
  // the news wakes the window: every change bumps the revision
  const std::uint64_t revision = watch.status.revision;
  ASSERT_TRUE(watch.settled(w.step(1)));
  EXPECT_EQ(watch.frame->step, 8);
  EXPECT_GT(watch.status.revision, revision);
}

// The worker calls its wake-up for every change, so a window may sleep until then.
TEST(GuiSimWorker, WakesTheWindowOnNews) {
  std::atomic<int> wakes{0};
  const auto worker = worker_on(kScene, {}, [&wakes] { ++wakes; });
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.until([&] { return watch.frame.has_value(); }));
  const int before = wakes.load();
  ASSERT_TRUE(watch.settled(w.step(2)));
  EXPECT_GE(wakes.load(), before + 2);  // two frames at least
}

// The probed node's position in a published frame.
std::array<double, 3> position_in(const Frame& f, int node) {
  const std::size_t i = 3 * static_cast<std::size_t>(node);
  return {f.points.at(i), f.points.at(i + 1), f.points.at(i + 2)};
}

// A probe while paused is answered at once from the state on show: the next take() has the
// node's current position (it used to show (0, 0, 0) until the next step).
TEST(GuiSimWorker, ProbeWhilePausedShowsTheCurrentStateAtOnce) {
  const auto worker = worker_on(kScene);
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.settled(w.step(4)));
  ASSERT_TRUE(watch.frame.has_value());
  ASSERT_EQ(watch.frame->step, 4);
  const Frame shown = *watch.frame;
  const std::size_t before = watch.samples.size();
  ASSERT_TRUE(watch.settled(w.probe(7)));
  ASSERT_EQ(watch.samples.size(), before + 1);  // the answer, no step taken
  const Sample& s = watch.samples.back();
  EXPECT_EQ(s.node, 7);
  EXPECT_TRUE(s.probe_answer);
  EXPECT_EQ(s.step, 4);
  EXPECT_EQ(s.node_position, position_in(shown, 7));
  const auto& ref = watch.status.info->mesh.reference_points;
  EXPECT_NEAR(s.node_displacement,
              std::hypot(shown.points[21] - ref[21], shown.points[22] - ref[22], shown.points[23] - ref[23]), 1e-12);
  EXPECT_GT(s.node_displacement, 0.0);
  EXPECT_EQ(watch.frame->step, 4);  // nothing moved
}

// After the run has ended, a probe gives the node's own final position, not the previously
// probed node's values under the new node's name.
TEST(GuiSimWorker, ProbeAfterTheRunEndedGivesThatNodesFinalState) {
  const auto worker = worker_on(kScene, {"solver.end=0.5"});
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.settled(w.probe(3)));
  w.run();
  ASSERT_TRUE(watch.until([&] { return watch.status.state == WorkerState::finished; }));
  ASSERT_TRUE(watch.frame.has_value());
  const Frame last = *watch.frame;
  EXPECT_EQ(watch.samples.back().node, 3);
  ASSERT_TRUE(watch.settled(w.probe(9)));
  const Sample& s = watch.samples.back();
  EXPECT_EQ(s.node, 9);
  EXPECT_EQ(s.step, last.step);
  EXPECT_EQ(s.node_position, position_in(last, 9));
  EXPECT_NE(position_in(last, 9), position_in(last, 3));
}

// A node's history starts where it was placed: samples before carry no node, and a new node
// starts a new history at the step it was placed.
TEST(GuiSimWorker, ProbeHistoryStartsWhereTheProbeWasPlaced) {
  const auto worker = worker_on(kScene);
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.settled(w.step(3)));
  ASSERT_TRUE(watch.settled(w.probe(5)));
  ASSERT_TRUE(watch.settled(w.step(2)));
  ASSERT_TRUE(watch.settled(w.probe(8)));
  ASSERT_TRUE(watch.settled(w.step(1)));
  std::vector<std::pair<std::int64_t, int>> seen;  // (step, node) of every sample
  for (const Sample& s : watch.samples) seen.emplace_back(s.step, s.node);
  const std::vector<std::pair<std::int64_t, int>> expected = {
      {0, -1}, {1, -1}, {2, -1}, {3, -1}, {3, 5}, {4, 5}, {5, 5}, {5, 8}, {6, 8}};
  EXPECT_EQ(seen, expected);
}

// A pause between output frames shows the state the solver reached (frames come every 5 steps
// here), so the view, the status line and a probe agree with the solver: a step after the pause
// is the next solver step.
TEST(GuiSimWorker, PauseBetweenFramesShowsTheStateReached) {
  const std::vector<std::string> coarse = {"part[0].n1=4", "part[0].n2=4", "part[1].n1=4", "part[1].n2=4",
                                           "solver.output_every=5"};
  const auto worker = worker_on(std::string(FF_SOURCE_DIR) + "/assets/scenes/double_pendulum_shells.toml", coarse);
  SimWorker& w = *worker;
  Watcher watch{w, {}, {}, {}};
  ASSERT_TRUE(watch.settled(w.step(3)));
  ASSERT_TRUE(watch.settled(w.pace(50)));  // a step every 20 ms
  ASSERT_TRUE(watch.settled(w.run()));
  ASSERT_TRUE(watch.until([&] { return watch.frame && watch.frame->step >= 10; }));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));  // a few steps past the frame
  ASSERT_TRUE(watch.settled(w.pause()));
  const std::int64_t at = watch.frame->step;
  ASSERT_TRUE(watch.settled(w.step(1)));
  EXPECT_EQ(watch.frame->step, at + 1);
}

}  // namespace
}  // namespace ff::app::gui
