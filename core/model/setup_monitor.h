#pragma once
/// \file setup_monitor.h
/// What long model set-up (matrix assembly, mesh generation) hears from the program around it:
/// a stop flag it polls (the app's signal handler sets it) and a sink for progress. Core never
/// prints; the app decides whether and how progress is shown.

#include <atomic>
#include <functional>
#include <stdexcept>
#include <string>

namespace ff {

/// Thrown by set-up that was asked to stop: nothing of the model was kept.
class SetupInterrupted : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct SetupMonitor {
  /// Set (by a signal) when the set-up should end; null: never asked.
  const std::atomic<bool>* stop = nullptr;
  /// Told the phase and the fraction of it done, at every poll (the sink rate-limits itself).
  std::function<void(const std::string& phase, double fraction)> progress;

  /// Reports `fraction` of `phase` and throws SetupInterrupted when the stop flag is set. Cheap
  /// enough to call per quadrature point: a stop is then seen within a fraction of a second.
  void poll(const std::string& phase, double fraction) const {
    if (progress) progress(phase, fraction);
    if (stop && stop->load(std::memory_order_relaxed))
      throw SetupInterrupted("interrupted by the user during set-up (" + phase + ")");
  }
};

}  // namespace ff
