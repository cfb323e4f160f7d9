#pragma once
/// \file run_result.h
/// What one headless run ended with (run_session.h), and the exit code its outcome gives.

#include <optional>
#include <string>

#include "app/error_bar_run.h"
#include "core/model/simulation.h"

namespace ff::app {

struct RunResult {
  RunOutcome outcome;
  Metrics metrics;
  SolverTotals totals;
  std::string out_dir;
  std::string scene_name;
  int frames_rendered = 0;
  std::string movie;             ///< path of the movie written, "" if none
  int frames_exported = 0;
  double render_seconds = 0.0;   ///< wall time spent rendering frames (render thread)
  int modes = -1;                ///< modes the eigen-analysis found; -1: the run computes none
  int modes_animated = 0;        ///< of them, animated (frames/mode_NN/)
  ErrorBarReport error_bars;     ///< the metrics' error bars (on = false: not asked for)
  /// where the mesh is too coarse (core/shell/error_indicator.md), at the last state; empty for
  /// models that record no error indicator
  std::optional<FieldErrorEstimate> field_error;
};

/// Exit code for an outcome: 0 completed, 4 incomplete, 3 diverged, 130 interrupted, 1 failed.
inline int exit_code(const RunOutcome& o) {
  switch (o.status) {
    case RunStatus::completed: return 0;
    case RunStatus::incomplete: return 4;
    case RunStatus::diverged: return 3;
    case RunStatus::interrupted: return 130;
    case RunStatus::failed: return 1;
  }
  return 1;
}

}  // namespace ff::app
