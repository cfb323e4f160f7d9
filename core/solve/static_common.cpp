#include "core/solve/static_common.h"

#include "core/frame/text.h"
#include "core/solve/solver_ranks.h"

#include <cstdio>

namespace ff {

std::string_view to_string(StaticStatus status) {
  switch (status) {
    case StaticStatus::completed: return "completed";
    case StaticStatus::incomplete: return "incomplete";
    case StaticStatus::diverged: return "diverged";
    case StaticStatus::interrupted: return "interrupted";
  }
  return "unknown";
}

std::string_view to_string(StaticStop stop) {
  switch (stop) {
    case StaticStop::none: return "none";
    case StaticStop::lambda_reached: return "lambda_reached";
    case StaticStop::displacement_limit: return "displacement_limit";
    case StaticStop::max_steps: return "max_steps";
    case StaticStop::step_too_small: return "step_too_small";
    case StaticStop::load_factor_bound: return "load_factor_bound";
    case StaticStop::limit_point: return "limit_point";
    case StaticStop::invalid_settings: return "invalid_settings";
    case StaticStop::stop_requested: return "stop_requested";
  }
  return "unknown";
}

std::string_view to_string(StaticEvent::Kind kind) {
  switch (kind) {
    case StaticEvent::Kind::limit_point: return "limit_point";
    case StaticEvent::Kind::bifurcation: return "bifurcation";
    case StaticEvent::Kind::turn_back: return "turn_back";
    case StaticEvent::Kind::unloaded: return "unloaded";
    case StaticEvent::Kind::loop: return "loop";
    case StaticEvent::Kind::first_step_cut_back: return "first_step_cut_back";
  }
  return "unknown";
}

StaticAttempt rejected_attempt(const AttemptOutcome& outcome, int step, double lambda, double dlambda, std::string why) {
  StaticAttempt a;
  a.step = step;
  a.lambda = lambda;
  a.dlambda = dlambda;
  a.iterations = outcome.iterations;
  a.factorizations = outcome.factorizations;
  a.residual_norm = outcome.residual_norm;
  a.increment_norm = outcome.increment_norm;
  a.why = std::move(why);
  return a;
}

StaticEvent first_step_cut_back(int attempts, double lambda, double fraction) {
  const int cuts = attempts - 1;
  return {StaticEvent::Kind::first_step_cut_back, 1, lambda,
          "the first step converged only after " + std::to_string(cuts) + " cut-back" + (cuts > 1 ? "s" : "") +
              ", at " + significant(fraction) + " of the initial step's length (λ = " + significant(lambda) +
              "): the initial step is longer than the path allows at its start"};
}

StaticStepInfo step_info(const AttemptOutcome& outcome, int step, double lambda, double dlambda, int attempts,
                         double step_norm) {
  StaticStepInfo info;
  info.step = step;
  info.lambda = lambda;
  info.dlambda = dlambda;
  info.iterations = outcome.iterations;
  info.attempts = attempts;
  info.factorizations = outcome.factorizations;
  info.tangent_refactored = outcome.factorizations > 0;
  info.residual_norm = outcome.residual_norm;
  info.increment_norm = outcome.increment_norm;
  info.step_norm = step_norm;
  return info;
}

bool stop_requested(const std::atomic<bool>* stop) { return stop && stop->load(std::memory_order_relaxed); }

TangentInParts::TangentInParts(StaticProblem& problem, SparseLinearSolver& solver) : problem_(problem) {
  if (solver.ranks() < 2) return;
  held_ = problem_.assemble_tangent_in_parts(true);
  // refused only by a solver of one rank (excluded above); were it refused, the tangent stays whole
  if (held_ && !solver.hold_positions_over_ranks(*held_)) {
    problem_.assemble_tangent_in_parts(false);
    held_ = nullptr;
  }
}

TangentInParts::~TangentInParts() {
  if (held_) problem_.assemble_tangent_in_parts(false);
}

StaticKernel::StaticKernel(StaticProblem& problem, const StaticConvergence& convergence)
    : problem_(problem),
      convergence_(convergence),
      n_(problem.size()),
      linear_(convergence.linear_backend),
      tangent_parts_(problem, linear_) {
  w2_.resize(n_);
  for (int i = 0; i < n_; ++i) {
    const double s = problem_.dof_scale(i);
    w2_[i] = s * s;
  }
  iw2_ = w2_.cwiseInverse();
  r_.setZero(n_);
  f_.setZero(n_);
}

double StaticKernel::dot_u(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
  return (a.array() * b.array() * w2_.array()).sum();
}

double StaticKernel::dot_r(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const {
  return (a.array() * b.array() * iw2_.array()).sum();
}

bool StaticKernel::evaluate(double lambda, bool with_tangent) {
  problem_.evaluate(lambda, r_, with_tangent ? &tangent_ : nullptr, &f_);
  evaluated_ = true;
  evaluated_lambda_ = lambda;
  if (with_tangent) {
    factorization_current_ = factorization_current_ && tangent_current_ && tangent_lambda_ == lambda;
    tangent_current_ = true;
    tangent_lambda_ = lambda;
    estimate_round_off();
  }
  if (r_.size() != n_ || f_.size() != n_) {
    failure_ = "the problem returned vectors of the wrong size";
    return false;
  }
  if (!r_.allFinite()) {
    failure_ = "non-finite residual at λ = " + significant(lambda);
    return false;
  }
  if (!f_.allFinite()) {
    failure_ = "non-finite load vector at λ = " + significant(lambda);
    return false;
  }
  return true;
}

bool StaticKernel::refresh_tangent(double lambda) {
  if (factorization_current_ && tangent_current_ && tangent_lambda_ == lambda) return true;
  if (!(tangent_current_ && tangent_lambda_ == lambda) && !evaluate(lambda, true)) return false;
  tangent_.makeCompressed();
  // the symmetric part where it is as good as K (eq. 7.1) and the backend gains from it
  const bool exploits_symmetry =
      linear_.backend() == LinearBackend::mumps || linear_backend_is_symmetric(linear_.backend());
  const LinearStatus s = exploits_symmetry && problem_.tangent_symmetric_at_equilibrium()
                             ? linear_.factorize_symmetric_part(tangent_)
                             : linear_.factorize(tangent_);
  if (!s) {
    factorized_ = factorization_current_ = false;
    failure_ = "tangent factorization failed: " + s.message;
    return false;
  }
  factorized_ = factorization_current_ = true;
  updates_since_factorization_ = 0;
  ++factorizations_;
  return true;
}

bool StaticKernel::wants_new_tangent(int k, double residual_norm, double previous_residual_norm) {
  const bool fresh = convergence_.tangent == TangentPolicy::every_iteration || !factorized_ ||
                     (k > 0 && residual_norm > convergence_.refactor_contraction * previous_residual_norm) ||
                     iterations_on_factorization_ >= convergence_.refactor_iterations;
  iterations_on_factorization_ = fresh ? 1 : iterations_on_factorization_ + 1;
  return fresh;
}

bool StaticKernel::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
  const LinearStatus s = linear_.solve(b, x);
  if (!s) {
    failure_ = "linear solve failed: " + s.message;
    return false;
  }
  return true;
}

void StaticKernel::update(const Eigen::VectorXd& delta) {
  problem_.update(delta);
  tangent_current_ = evaluated_ = factorization_current_ = false;
  if (updates_since_factorization_ >= 0) ++updates_since_factorization_;
}

void StaticKernel::save() { problem_.save_state(); }

void StaticKernel::restore() {
  problem_.restore_state();
  tangent_current_ = evaluated_ = factorization_current_ = false;
  updates_since_factorization_ = -1;
}

// eq. (3'): r_i changes by sum_j K_ij e_j for state errors e_j; independent one-ulp errors
// e_j ~ eps m_j (m_j the coordinate's magnitude) give rho_i = eps sqrt(sum_j (K_ij m_j)^2)
void StaticKernel::estimate_round_off() {
  if (convergence_.round_off_factor <= 0.0 || tangent_.nonZeros() == 0) return;
  magnitude_.resize(n_);
  for (int j = 0; j < n_; ++j) magnitude_[j] = problem_.state_magnitude(j);
  if (magnitude_.maxCoeff() <= 0.0) return;
  // a sum over the entries: in parts over ranks each sums the entries it holds, and the parts are added
  double sum = 0.0;
  const int* outer = tangent_.outerIndexPtr();
  const int* row = tangent_.innerIndexPtr();
  const double* value = tangent_.valuePtr();
  if (const std::vector<int>* held = tangent_parts_.held()) {
    for (int j = 0, q = 0; q < static_cast<int>(held->size()); ++q) {
      const int p = (*held)[q];
      while (outer[j + 1] <= p) ++j;
      const double v = value[p] * magnitude_[j];
      sum += v * v * iw2_[row[p]];
    }
    sum_over_ranks(&sum, 1);
  } else {
    Eigen::VectorXd acc = Eigen::VectorXd::Zero(n_);
    for (int j = 0; j < n_; ++j)
      for (int p = outer[j]; p < outer[j + 1]; ++p) {
        const double v = value[p] * magnitude_[j];
        acc[row[p]] += v * v;
      }
    sum = (acc.array() * iw2_.array()).sum();
  }
  round_off_ = std::numeric_limits<double>::epsilon() * std::sqrt(sum);
}

double StaticKernel::residual_limit() const {
  return convergence_.residual_tolerance * norm_r(f_) + convergence_.residual_floor +
         convergence_.round_off_factor * round_off_;
}

bool StaticKernel::increment_converged(double increment_norm, double previous_increment_norm, double step_norm) const {
  // eq. (4): the error left after δ_k is about θ/(1-θ) ||δ_k|| with θ = ||δ_k|| / ||δ_{k-1}||
  // (a contracting iteration); without a clear contraction, ||δ_k|| itself
  const double theta = previous_increment_norm > 0.0 ? increment_norm / previous_increment_norm : 1.0;
  const double error = theta < 0.5 ? increment_norm * theta / (1.0 - theta) : increment_norm;
  return error <= convergence_.increment_tolerance * step_norm + convergence_.increment_floor;
}

bool StaticKernel::converged(double residual_norm, double increment_norm, double previous_increment_norm,
                             double step_norm) const {
  return residual_norm <= residual_limit() && increment_converged(increment_norm, previous_increment_norm, step_norm);
}

std::string DivergenceMonitor::check(int k, double rn, double converged_level) {
  std::string why;
  // residuals already below the convergence limit neither diverge nor count as increases
  if (rn <= converged_level) {
    smallest_ = std::min(smallest_, converged_level);
    previous_ = converged_level;
    increases_ = 0;
    return why;
  }
  if (k > 0 && rn > convergence_.divergence_ratio * smallest_)
    why = "residual grew to " + significant(rn) + ", more than " + significant(convergence_.divergence_ratio) +
          "× its smallest value " + significant(smallest_) + " in this attempt";
  increases_ = rn > previous_ ? increases_ + 1 : 0;
  if (why.empty() && increases_ >= convergence_.max_residual_increases)
    why = "residual increased in " + std::to_string(increases_) + " consecutive iterations (now " + significant(rn) + ")";
  smallest_ = std::min(smallest_, rn);
  previous_ = rn;
  return why;
}

// eq. (6): K δ = −r at fixed λ, until eqs. (3)–(4) hold
AttemptOutcome newton_at_fixed_load(StaticKernel& kernel, double lambda, Eigen::VectorXd& step,
                                   const std::atomic<bool>* stop, bool hold_determinant_sign) {
  const StaticConvergence& c = kernel.convergence();
  AttemptOutcome out;
  DivergenceMonitor monitor(c);
  Eigen::VectorXd delta(kernel.size()), rhs;
  double previous = std::numeric_limits<double>::infinity();
  const int start_factorizations = kernel.factorizations();
  int start_sign = kernel.determinant_sign();  // of a factorization kept from before, if any
  for (int k = 0;; ++k) {
    if (stop_requested(stop)) {
      out.interrupted = true;
      out.failure = "stop requested";
      break;
    }
    const bool full = c.tangent == TangentPolicy::every_iteration;
    // eq. (4''): the first correction from a converged state takes the factorization of the
    // correction that converged it; eq. (4'''): K of an iterate that will likely be converged is
    // not assembled (refresh_tangent assembles it if the residual test fails after all)
    const bool last_correction = full && k == 0 && kernel.factorization_of_last_correction();
    const bool expect_converged =
        k > 0 && kernel.increment_converged(out.increment_norm, out.previous_increment_norm, kernel.norm_u(step));
    if (!kernel.evaluate(lambda, full && !last_correction && !expect_converged)) {
      out.failure = kernel.failure() + " (iteration " + std::to_string(k) + ")";
      break;
    }
    out.residual_norm = kernel.norm_r(kernel.residual());
    // at least one correction, so that both criteria are measured
    if (k > 0 && kernel.converged(out.residual_norm, out.increment_norm, out.previous_increment_norm, kernel.norm_u(step))) {
      out.converged = true;
      break;
    }
    if (k >= c.max_iterations) {
      out.failure = "no convergence in " + std::to_string(c.max_iterations) + " iterations at λ = " + significant(lambda) +
                    " (residual " + significant(out.residual_norm) + " vs limit " + significant(kernel.residual_limit()) +
                    ", increment " + significant(out.increment_norm) + ")";
      break;
    }
    if (std::string why = monitor.check(k, out.residual_norm, kernel.residual_limit()); !why.empty()) {
      out.failure = "diverging at λ = " + significant(lambda) + ": " + why;
      break;
    }
    if (!last_correction && kernel.wants_new_tangent(k, out.residual_norm, previous)) {
      if (!kernel.refresh_tangent(lambda)) {
        out.failure = kernel.failure() + " (iteration " + std::to_string(k) + ", λ = " + significant(lambda) + ")";
        break;
      }
      // eq. (7): a stable path keeps the sign of det K; iterates across a limit point change it
      const int sign = kernel.determinant_sign();
      if (start_sign == 0) start_sign = sign;
      if (hold_determinant_sign && sign != start_sign) {
        out.crossed_limit = true;
        out.failure = "det K changed sign at iteration " + std::to_string(k) + " for λ = " + significant(lambda) +
                      " (the iterates crossed a limit or bifurcation point)";
        break;
      }
    }
    rhs = -kernel.residual();
    if (!kernel.solve(rhs, delta)) {
      out.failure = kernel.failure();
      break;
    }
    kernel.update(delta);
    step += delta;
    out.previous_increment_norm = out.increment_norm;
    out.increment_norm = kernel.norm_u(delta);
    if (k == 0) out.first_increment_norm = out.increment_norm;
    out.iterations = k + 1;
    previous = out.residual_norm;
  }
  out.factorizations = kernel.factorizations() - start_factorizations;
  return out;
}

}  // namespace ff
