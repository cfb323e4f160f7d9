#include "core/solve/newmark.h"

#include <cmath>
#include <sstream>

namespace ff {

NewmarkIntegrator::NewmarkIntegrator(const SecondOrderSystem& system, NewmarkSettings settings)
    : sys_(system), settings_(settings) {}

StepReport NewmarkIntegrator::initialize(NewmarkState& st) {
  StepReport rep;
  const int n = sys_.size();
  if (st.a.size() != n) st.a = Eigen::VectorXd::Zero(n);
  // r is linear in a: r(a) = r(0) + A a
  sys_.residual(st.x, st.v, st.a, st.t, r_);
  sys_.iteration_matrix(st.x, st.v, st.a, st.t, 1.0, 0.0, 0.0, j_);
  Eigen::PartialPivLU<Eigen::MatrixXd> lu(j_);
  st.a -= lu.solve(r_);
  sys_.residual(st.x, st.v, st.a, st.t, r_);
  rep.converged = st.a.allFinite();
  rep.residual_norm = r_.lpNorm<Eigen::Infinity>();
  rep.matrix_updates = 1;
  if (!rep.converged) rep.failure = "initial accelerations are not finite (singular mass matrix?)";
  return rep;
}

// hub_beam.md eqs. (25)-(26): one Newton solve for a_{n+1}
StepReport NewmarkIntegrator::attempt(NewmarkState& st, double h) {
  StepReport rep;
  const double b = settings_.beta, g = settings_.gamma, t1 = st.t + h;
  a_ = st.a;  // predictor: constant acceleration
  double first_residual = -1.0;
  for (int k = 1; k <= settings_.max_iterations; ++k) {
    x_ = st.x + h * st.v + (h * h) * ((0.5 - b) * st.a + b * a_);
    v_ = st.v + h * ((1.0 - g) * st.a + g * a_);
    sys_.residual(x_, v_, a_, t1, r_);
    rep.iterations = k;
    rep.residual_norm = r_.lpNorm<Eigen::Infinity>();
    if (!std::isfinite(rep.residual_norm)) {
      rep.failure = "non-finite residual at Newton iteration " + std::to_string(k);
      return rep;
    }
    if (first_residual < 0) first_residual = rep.residual_norm;
    sys_.iteration_matrix(x_, v_, a_, t1, 1.0, g * h, b * h * h, j_);
    ++rep.matrix_updates;
    Eigen::PartialPivLU<Eigen::MatrixXd> lu(j_);
    da_ = -lu.solve(r_);
    if (!da_.allFinite()) {
      rep.failure = "singular iteration matrix at Newton iteration " + std::to_string(k);
      return rep;
    }
    a_ += da_;
    rep.increment_norm = b * h * h * da_.lpNorm<Eigen::Infinity>();
    const double scale = 1.0 + x_.lpNorm<Eigen::Infinity>();
    if (rep.increment_norm <= settings_.tolerance * scale) {
      x_ = st.x + h * st.v + (h * h) * ((0.5 - b) * st.a + b * a_);
      v_ = st.v + h * ((1.0 - g) * st.a + g * a_);
      sys_.residual(x_, v_, a_, t1, r_);
      rep.residual_norm = r_.lpNorm<Eigen::Infinity>();
      st.x = x_;
      st.v = v_;
      st.a = a_;
      st.t = t1;
      rep.converged = true;
      return rep;
    }
    if (k >= 4 && rep.residual_norm > 1e6 * std::max(first_residual, 1e-300)) {
      rep.failure = "Newton residual grew by more than 1e6 (from " + std::to_string(first_residual) +
                    " to " + std::to_string(rep.residual_norm) + ")";
      return rep;
    }
  }
  std::ostringstream msg;
  msg << "Newton did not converge in " << settings_.max_iterations << " iterations (last increment "
      << rep.increment_norm << ", residual " << rep.residual_norm << ")";
  rep.failure = msg.str();
  return rep;
}

StepReport NewmarkIntegrator::advance(NewmarkState& st, double h, int depth) {
  const NewmarkState saved = st;
  StepReport rep = attempt(st, h);
  if (rep.converged || depth >= settings_.max_cutbacks) return rep;
  // cut back: two half steps from the saved state
  st = saved;
  StepReport a = advance(st, 0.5 * h, depth + 1);
  if (!a.converged) {
    a.iterations += rep.iterations;
    a.matrix_updates += rep.matrix_updates;
    return a;
  }
  StepReport b = advance(st, 0.5 * h, depth + 1);
  b.iterations += a.iterations + rep.iterations;
  b.matrix_updates += a.matrix_updates + rep.matrix_updates;
  b.substeps += a.substeps;
  return b;
}

StepReport NewmarkIntegrator::step(NewmarkState& st, double dt) {
  StepReport rep = advance(st, dt, 0);
  if (rep.converged) {
    const std::string why = sys_.check_state(st.x, st.v);
    if (!why.empty()) {
      rep.converged = false;
      rep.failure = why;
    }
  }
  return rep;
}

}  // namespace ff
