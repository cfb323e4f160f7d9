#pragma once
/// A solver-only run (no files, no frames) with its wall time split into set-up and stepping,
/// shared by `bench` and `study`.
#include <atomic>
#include <string>
#include <vector>

#include "core/model/simulation.h"

namespace ff::app {

struct TimedRun {
  double setup_s = 0.0;  ///< scene parsing + model construction (shape functions, matrices)
  double run_s = 0.0;    ///< time stepping incl. frame assembly
  RunOutcome outcome;
  Metrics metrics;
  std::vector<std::pair<std::string, std::string>> metrics_unreached;  ///< asked for, no value: why
  SolverTotals totals;
  double total_s() const { return setup_s + run_s; }
};

TimedRun timed_run(const std::string& scene_path, const std::vector<std::string>& overrides,
                   const std::atomic<bool>& stop);
/// Median over `repeat` runs of total_s() (metrics from the first run); setup_s/run_s medians too.
TimedRun timed_run_median(const std::string& scene_path, const std::vector<std::string>& overrides, int repeat,
                          const std::atomic<bool>& stop);
double metric(const Metrics& m, const std::string& name);  ///< NaN when absent

}  // namespace ff::app
