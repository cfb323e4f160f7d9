#include "core/model/run_loop.h"

#include <cmath>
#include <sstream>

namespace ff {

namespace {
double seconds_since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}
}  // namespace

std::string Simulation::end_description() const {
  std::ostringstream s;
  s << "ends at t = " << end_time() << ' ' << info().time_unit;
  return s.str();
}

RunOutcome Simulation::run(const std::function<void(Frame&&)>& publish, const std::atomic<bool>& stop) {
  return RunLoop(*this).run(publish, stop);
}

RunOutcome RunLoop::run(const Publish& publish, const std::atomic<bool>& stop) {
  if (start(publish, &stop))
    while (advance(publish, stop)) {
    }
  return outcome_;
}

bool RunLoop::start(const Publish& publish, const std::atomic<bool>* stop) {
  wall0_ = std::chrono::steady_clock::now();
  if (std::string why = sim_.start(); !why.empty()) {
    finish(publish, stop && stop->load() ? RunStatus::interrupted : sim_.start_failure_status(), std::move(why));
    return false;
  }
  Frame f = sim_.frame();
  f.step = 0;
  f.stats = sim_.start_stats();
  sim_.on_publish(f);
  publish(std::move(f));
  return true;
}

void RunLoop::publish_state(const Publish& publish) {
  Frame f = sim_.frame();
  f.step = step_;
  f.stats = log_.back().stats;
  if (sim_.logs_skipped_steps()) {
    f.stats.iterations = iterations_;  // NOI and NOU of all steps since the previous frame
    f.stats.jacobian_updates = updates_;
    f.step_log.swap(log_);
  } else if (log_.size() > 1) {  // rejected attempts before the step: the frame carries every row
    f.step_log.swap(log_);
  }
  log_.clear();
  iterations_ = updates_ = 0;
  sim_.on_publish(f);
  publish(std::move(f));
}

// a run that ends, however, still publishes its last converged state, so nothing computed is lost
void RunLoop::finish(const Publish& publish, RunStatus status, std::string reason) {
  if (!log_.empty()) publish_state(publish);
  outcome_.status = status;
  outcome_.reason = std::move(reason);
  outcome_.stop_time = sim_.time();
  outcome_.steps = step_;
  outcome_.cutbacks = sim_.totals().cutbacks;
  outcome_.wall_time_s = seconds_since(wall0_);
  finished_ = true;
}

bool RunLoop::advance(const Publish& publish, const std::atomic<bool>& stop) {
  if (finished_) return false;
  const double t = sim_.time(), dt = sim_.nominal_step(), end = sim_.end_time();
  const std::string unit = sim_.info().time_unit;
  auto when = [&](double at) {
    std::ostringstream s;
    s << (unit.empty() ? "λ = " : "t = ") << at << (unit.empty() ? "" : " " + unit);
    return s.str();
  };
  if (stop.load()) {
    finish(publish, RunStatus::interrupted, "interrupted by the user at " + when(t));
    return false;
  }
  // parameter changes due now: the integrator restarts from the current state, so the step after
  // the change carries none of the old load in its accelerations
  if (sim_.apply_changes(t))
    if (std::string why = sim_.restart(); !why.empty()) {
      finish(publish, RunStatus::failed, "restart after a timeline change at " + when(t) + ": " + why);
      return false;
    }
  // a change inside the regular step splits it at the change; the rest of the step follows, so
  // later steps stay on the grid of dt
  double h = dt;
  if (std::isfinite(dt)) {
    h = rest_ > 0 ? rest_ : std::min(dt, end - t);
    rest_ = 0.0;
    const double change = sim_.next_change(t);
    if (change < t + h - 1e-9 * dt) {
      rest_ = h - (change - t);
      h = change - t;
    }
  }
  StepDone d = sim_.step(h);
  const bool reached_end = std::isfinite(dt) && sim_.time() >= end - 1e-9 * dt;
  // attempts not accepted go into the convergence log ahead of the step they tried; when no step
  // came of them (the run ends on them) they have no frame and travel with the outcome
  if (d.accepted)
    for (StepRecord& r : d.rejected) {
      iterations_ += r.stats.iterations;
      updates_ += r.stats.jacobian_updates;
      log_.push_back(std::move(r));
    }
  else
    for (StepRecord& r : d.rejected) outcome_.trailing_attempts.push_back(std::move(r));
  if (d.accepted) {
    ++step_;
    log_.push_back({step_, sim_.time(), d.stats});
    iterations_ += d.stats.iterations;
    updates_ += d.stats.jacobian_updates;
    if (step_ % sim_.output_every() == 0 || d.finished || reached_end) publish_state(publish);
  }
  if (d.finished) {
    outcome_.events = std::move(d.events);
    finish(publish, d.status, std::move(d.reason));
    return false;
  }
  if (reached_end) {
    finish(publish, RunStatus::completed, {});
    return false;
  }
  return true;
}

}  // namespace ff
