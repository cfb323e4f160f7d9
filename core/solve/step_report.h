#pragma once
/// \file step_report.h
/// What one step of a time integrator did (Newmark, Lie-group generalized-α): the one report of
/// the solvers, turned into the run loop's StepStats (core/frame/frame.h) by stats().

#include <string>

#include "core/frame/frame.h"

namespace ff {

struct StepReport {
  bool converged = false;
  int iterations = 0;      ///< Newton corrections, cut-back sub-steps included (NOI)
  int matrix_updates = 0;  ///< iteration-matrix factorizations (NOU)
  int substeps = 1;        ///< sub-steps the step was taken in (1: no cut-back)
  int fallbacks = 0;       ///< attempts on a stale matrix retried with full updates
  double residual_norm = 0.0;
  double increment_norm = 0.0;
  std::string failure;     ///< why the step failed (empty when converged)

  StepStats stats(double dt) const { return {dt, iterations, matrix_updates, residual_norm, increment_norm, converged}; }
};

}  // namespace ff
