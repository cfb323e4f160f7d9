#pragma once
/// \file newmark.h
/// Newmark time integration with Newton iterations on the accelerations
/// (core/hubbeam/hub_beam.md eqs. (25)-(27)). Divergence is reported, never thrown.

#include <Eigen/Dense>
#include <string>

#include "core/solve/second_order_system.h"
#include "core/solve/step_report.h"

namespace ff {

struct NewmarkSettings {
  double beta = 0.25;        ///< Newmark beta (0.25 = average acceleration; the hub-beam paper, Xie & Jian 2017: 0.75)
  double gamma = 0.5;        ///< Newmark gamma
  double tolerance = 1e-10;  ///< ||dx||_inf <= tolerance * (1 + ||x||_inf)
  int max_iterations = 25;   ///< Newton iterations per attempt
  int max_cutbacks = 0;      ///< times a failed step may be halved (each half again, recursively)
};

struct NewmarkState {
  double t = 0.0;
  Eigen::VectorXd x, v, a;
};


class NewmarkIntegrator {
 public:
  NewmarkIntegrator(const SecondOrderSystem& system, NewmarkSettings settings);
  /// Consistent initial accelerations: solves r(x0, v0, a0, t0) = 0 for a0 (linear in a).
  StepReport initialize(NewmarkState& state);
  /// Advances state by dt (halving on failure up to max_cutbacks levels). On failure the state
  /// is left at the last converged sub-step.
  StepReport step(NewmarkState& state, double dt);
  const NewmarkSettings& settings() const { return settings_; }

 private:
  StepReport attempt(NewmarkState& state, double dt);
  StepReport advance(NewmarkState& state, double dt, int depth);
  const SecondOrderSystem& sys_;
  NewmarkSettings settings_;
  // workspace reused across steps (no allocation per iteration once sized)
  Eigen::VectorXd r_, x_, v_, a_, da_;
  Eigen::MatrixXd j_;
};

}  // namespace ff
