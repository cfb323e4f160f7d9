#pragma once
/// \file run_loop.h
/// The one run loop of every Simulation (core/model/simulation.h): the stop flag, the split of a
/// step at a [[timeline]] change (later steps stay on the grid of the regular step), the output
/// cadence with the log of the steps between frames, and the outcome. Steppable: start(), then
/// advance() until it returns false; a caller that pauses simply stops calling advance().
#include <atomic>
#include <chrono>
#include <functional>

#include "core/model/simulation.h"

namespace ff {

class RunLoop {
 public:
  using Publish = std::function<void(Frame&&)>;
  explicit RunLoop(Simulation& sim) : sim_(sim) {}

  /// Prepares the model and publishes the initial state; false when it cannot start (outcome:
  /// failed, with the reason; interrupted when `stop` was raised while a model that builds at its
  /// start, such as the hub-beam, was setting up).
  bool start(const Publish& publish, const std::atomic<bool>* stop = nullptr);
  /// One step of the model, publishing it by the cadence; false when the run has ended (outcome()).
  /// A raised `stop` ends the run as interrupted before the step.
  bool advance(const Publish& publish, const std::atomic<bool>& stop);
  /// Publishes the state now when steps were taken since the last frame (a caller that pauses
  /// between output frames, such as the GUI's Step, shows where it stopped).
  void publish_pending(const Publish& publish) {
    if (!log_.empty()) publish_state(publish);
  }
  bool finished() const { return finished_; }
  const RunOutcome& outcome() const { return outcome_; }
  /// start() and advance() until the end.
  RunOutcome run(const Publish& publish, const std::atomic<bool>& stop);

 private:
  void publish_state(const Publish& publish);
  void finish(const Publish& publish, RunStatus status, std::string reason);

  Simulation& sim_;
  RunOutcome outcome_;
  bool finished_ = false;
  std::int64_t step_ = 0;
  double rest_ = 0.0;                // of a regular step split by a timeline change
  std::vector<StepRecord> log_;      // steps since the last published frame
  std::int32_t iterations_ = 0, updates_ = 0;  // their sums
  std::chrono::steady_clock::time_point wall0_;
};

}  // namespace ff
