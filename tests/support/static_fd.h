#pragma once
/// Central differences of a static problem's residual along its own update() (the derivative
/// every analytic tangent of core/solve/static_problem.h must match), for tangent tests.
#include <Eigen/Dense>

#include "core/solve/static_problem.h"

namespace ff::test {

/// Column k = (r(q ⊕ h e_k, λ) − r(q ⊕ −h e_k, λ)) / 2h; the problem's state is restored after
/// each column (its saved state is overwritten).
inline Eigen::MatrixXd central_difference_tangent(StaticProblem& p, double lambda, double h) {
  const int n = p.size();
  Eigen::MatrixXd k_fd(n, n);
  Eigen::VectorXd rp, rm, step = Eigen::VectorXd::Zero(n);
  p.save_state();
  for (int k = 0; k < n; ++k) {
    step[k] = h;
    p.update(step);
    p.evaluate(lambda, rp, nullptr, nullptr);
    p.restore_state();
    step[k] = -h;
    p.update(step);
    p.evaluate(lambda, rm, nullptr, nullptr);
    p.restore_state();
    step[k] = 0.0;
    k_fd.col(k) = (rp - rm) / (2 * h);
  }
  return k_fd;
}

}  // namespace ff::test
