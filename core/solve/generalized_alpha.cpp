#include "core/solve/generalized_alpha.h"

#include "core/solve/solver_ranks.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

namespace ff {

namespace {
int value_index(const SparseMatrixD& A, int row, int col) {
  const int* inner = A.innerIndexPtr();
  const int* begin = inner + A.outerIndexPtr()[col];
  const int* end = inner + A.outerIndexPtr()[col + 1];
  const int* it = std::lower_bound(begin, end, row);
  return (it != end && *it == row) ? static_cast<int>(it - inner) : -1;
}
bool finite(const Eigen::VectorXd& x) { return x.allFinite(); }
std::string num(double x) {  // short, exact enough for a message: 3.2e-07, 0.0125
  char b[32];
  std::snprintf(b, sizeof b, "%.3g", x);
  return b;
}
}  // namespace

GeneralizedAlpha::GeneralizedAlpha(DynamicProblem& problem, GeneralizedAlphaSettings settings)
    : problem_(problem), settings_(settings), solver_(settings.backend) {
  const double r = std::clamp(settings_.rho_inf, 0.0, 1.0);  // (G2)
  am_ = (2 * r - 1) / (r + 1);
  af_ = r / (r + 1);
  gamma_ = 0.5 + af_ - am_;
  beta_ = 0.25 * (gamma_ + 0.5) * (gamma_ + 0.5);
  local_error_coefficient_ = beta_ + 0.5 * (am_ - af_) - 1.0 / 6.0;  // (G13)
  const int n = problem_.size(), m = problem_.constraint_count();
  local_error_.setZero(n);
  v_.setZero(n);
  vdot_.setZero(n);
  a_.setZero(n);
  lambda_.setZero(m);
  corrections_.reserve(static_cast<std::size_t>(std::max(settings_.max_iterations, 1)));
  // over ranks each assembles and hands MUMPS its part of S (core/solve/distributed.md §5)
  if (solver_.ranks() > 1) s_held_ = problem_.assemble_matrix_in_parts(true);
}

GeneralizedAlpha::~GeneralizedAlpha() {
  if (s_held_) problem_.assemble_matrix_in_parts(false);
}

const Eigen::VectorXd& GeneralizedAlpha::diagonal_of_S() {
  const int n = problem_.size();
  if (static_cast<int>(s_diagonal_.size()) != n) {
    std::vector<char> held;
    if (s_held_) {
      held.assign(static_cast<std::size_t>(S_.nonZeros()), 0);
      for (int p : *s_held_) held[p] = 1;
    }
    s_diagonal_.assign(n, -1);
    for (int i = 0; i < n; ++i) {
      const int p = value_index(S_, i, i);
      if (p >= 0 && (!s_held_ || held[p])) s_diagonal_[i] = p;
    }
  }
  diagonal_.setZero(n);
  for (int i = 0; i < n; ++i)
    if (s_diagonal_[i] >= 0) diagonal_[i] = S_.valuePtr()[s_diagonal_[i]];
  if (s_held_) sum_over_ranks(diagonal_.data(), static_cast<std::size_t>(n));  // each entry held by one rank
  return diagonal_;
}

void GeneralizedAlpha::build_augmented_pattern() {
  const int n = problem_.size(), m = problem_.constraint_count();
  std::vector<Eigen::Triplet<double>> t;
  t.reserve(S_.nonZeros() + 2 * B_.nonZeros());
  for (int c = 0; c < S_.outerSize(); ++c)
    for (SparseMatrixD::InnerIterator it(S_, c); it; ++it) t.emplace_back(static_cast<int>(it.row()), c, 1.0);
  for (int c = 0; c < B_.outerSize(); ++c)
    for (SparseMatrixD::InnerIterator it(B_, c); it; ++it) {
      t.emplace_back(n + static_cast<int>(it.row()), c, 1.0);
      t.emplace_back(c, n + static_cast<int>(it.row()), 1.0);
    }
  A_.resize(n + m, n + m);
  A_.setFromTriplets(t.begin(), t.end());
  A_.makeCompressed();
  s_map_.clear();
  b_map_.clear();
  bt_map_.clear();
  for (int c = 0; c < S_.outerSize(); ++c)
    for (SparseMatrixD::InnerIterator it(S_, c); it; ++it) s_map_.push_back(value_index(A_, static_cast<int>(it.row()), c));
  for (int c = 0; c < B_.outerSize(); ++c)
    for (SparseMatrixD::InnerIterator it(B_, c); it; ++it) {
      b_map_.push_back(value_index(A_, n + static_cast<int>(it.row()), c));
      bt_map_.push_back(value_index(A_, c, n + static_cast<int>(it.row())));
    }
  if (!s_held_) return;
  // in parts: this rank hands MUMPS its held entries of S, rank 0 also the constraint rows and
  // columns (B is whole on every rank and small)
  std::vector<int> held;
  held.reserve(s_held_->size() + (linear_solver_rank() == 0 ? 2 * b_map_.size() : 0));
  for (int p : *s_held_) held.push_back(s_map_[p]);
  if (linear_solver_rank() == 0) {
    held.insert(held.end(), b_map_.begin(), b_map_.end());
    held.insert(held.end(), bt_map_.begin(), bt_map_.end());
  }
  std::sort(held.begin(), held.end());
  solver_.hold_positions_over_ranks(std::move(held));
}

// A = [S kGᵀ; kB 0] (G7), (G9) from the current S_ and B_ (and G), then its factorization
bool GeneralizedAlpha::update_matrix(std::string& why) {
  if (static_cast<int>(s_map_.size()) != S_.nonZeros() || static_cast<int>(b_map_.size()) != B_.nonZeros() ||
      A_.rows() != problem_.size() + problem_.constraint_count())
    build_augmented_pattern();
  double* a = A_.valuePtr();
  std::fill(a, a + A_.nonZeros(), 0.0);
  for (std::size_t i = 0; i < s_map_.size(); ++i) a[s_map_[i]] += S_.valuePtr()[i];
  // rows kB = k ∂Φ/∂x, columns kGᵀ = k ∂r/∂λ (G7), (G9): G = B unless the problem says otherwise
  const SparseMatrixD* G = problem_.constraint_force_directions();
  const double* g = G && G->nonZeros() == B_.nonZeros() ? G->valuePtr() : B_.valuePtr();
  for (std::size_t i = 0; i < b_map_.size(); ++i) {
    a[b_map_[i]] += constraint_scale_ * B_.valuePtr()[i];
    a[bt_map_[i]] += constraint_scale_ * g[i];
  }
  const LinearStatus st = solver_.factorize(A_);
  if (!st) {
    why = "iteration matrix: " + st.message;
    return false;
  }
  have_matrix_ = true;
  ++nou_;
  return true;
}

std::string GeneralizedAlpha::initialize(double t0, const Eigen::VectorXd& v0) {
  t_ = t0;
  v_ = v0;
  const int n = problem_.size(), m = problem_.constraint_count();
  Eigen::VectorXd r, phi, zero_n = Eigen::VectorXd::Zero(n), zero_m = Eigen::VectorXd::Zero(m);
  problem_.configure(zero_n);
  const IterationWeights mass_only{1.0, 0.0, 0.0};
  problem_.evaluate(t0, v_, zero_n, zero_m, r, phi, &mass_only, &S_, &B_);
  if (!finite(r)) return "the initial state gives a non-finite residual";
  // unknowns without inertia (the drilling rotation of a 6-DoF shell node moves no mass) have no
  // initial acceleration of their own: a unit-scale diagonal gives them v̇0 = −r_i / mean(M_ii),
  // which is 0 in a stress-free reference state
  const Eigen::VectorXd& diagonal = diagonal_of_S();
  double diag_max = 0.0, diag_sum = 0.0;
  for (int i = 0; i < n; ++i) diag_max = std::max(diag_max, std::abs(diagonal[i])), diag_sum += std::abs(diagonal[i]);
  for (int i = 0; i < n; ++i)
    if (std::abs(diagonal[i]) <= 1e-12 * diag_max) S_.coeffRef(i, i) = diag_sum / n;
  // [M Bᵀ; B 0][v̇0; λ0] = [−g; 0] with unit row scale, then the counters start from zero
  constraint_scale_ = 1.0;
  std::string why;
  if (!update_matrix(why)) return "initial accelerations: " + why;
  nou_ = 0;
  Eigen::VectorXd rhs(n + m), x;
  rhs << -r, Eigen::VectorXd::Zero(m);
  const LinearStatus st = solver_.solve(rhs, x);
  if (!st) return "initial accelerations: " + st.message;
  vdot_ = x.head(n);
  a_ = vdot_;
  lambda_ = x.tail(m);
  have_matrix_ = false;  // the mass-only matrix is not an iteration matrix
  refresh_at_next_step_ = false;
  constraint_scale_ = 0.0;
  return {};
}

std::string GeneralizedAlpha::find_static_equilibrium(double t0, int& iterations) {
  // (G11): the iteration matrix with weights (mass 0, damping 0, stiffness 1) is the static
  // tangent in the step, constraint rows scaled as in (G7); a fresh matrix at every correction
  const int n = problem_.size(), m = problem_.constraint_count();
  const IterationWeights static_weights{0.0, 0.0, 1.0};
  const Eigen::VectorXd zero_n = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd x = zero_n, lam = Eigen::VectorXd::Zero(m), r, phi, rhs(n + m), dx;
  iterations = 0;
  constraint_scale_ = 0.0;
  for (int it = 1; it <= settings_.max_iterations; ++it) {
    problem_.configure(x);
    problem_.evaluate(t0, zero_n, zero_n, lam, r, phi, &static_weights, &S_, &B_);
    if (!finite(r) || !finite(phi)) return "non-finite residual at iteration " + std::to_string(it);
    if (constraint_scale_ == 0.0) {
      const Eigen::VectorXd& diagonal = diagonal_of_S();
      double sum = 0.0;
      for (int i = 0; i < n; ++i) sum += std::abs(diagonal[i]);
      constraint_scale_ = n > 0 && sum > 0 ? sum / n : 1.0;
    }
    std::string why;
    if (!update_matrix(why)) {
      problem_.rollback();
      return why + (why.find("singular") != std::string::npos
                        ? " (a mechanism: some part is held against rigid motion only by its inertia)"
                        : "");
    }
    rhs << -r, -constraint_scale_ * phi;
    const LinearStatus st = solver_.solve(rhs, dx);
    ++iterations;
    if (!st) {
      problem_.rollback();
      return "linear solve: " + st.message;
    }
    x += dx.head(n);
    lam += constraint_scale_ * dx.tail(m);
    if (dx.head(n).norm() <= settings_.tolerance) {
      problem_.configure(x);
      problem_.commit();
      lambda_ = lam;
      have_matrix_ = false;  // a static matrix is not an iteration matrix of a step
      constraint_scale_ = 0.0;
      nou_ = 0;
      return {};
    }
  }
  problem_.rollback();
  return "no static equilibrium within " + std::to_string(settings_.max_iterations) + " Newton corrections";
}

std::string GeneralizedAlpha::restart() {
  const long long nou = nou_;
  const Eigen::VectorXd v = v_;
  std::string why = initialize(t_, v);
  nou_ = nou;
  return why;
}

GeneralizedAlpha::Attempt GeneralizedAlpha::attempt(double h, bool force_full) {
  const int n = problem_.size(), m = problem_.constraint_count();
  const double bp = (1 - am_) / (h * h * beta_ * (1 - af_)), gp = gamma_ / (h * beta_);  // (G6)
  const IterationWeights w{bp, gp, 1.0};
  // predictor (§3)
  Eigen::VectorXd vd = Eigen::VectorXd::Zero(n);
  Eigen::VectorXd a1 = (af_ * vdot_ - am_ * a_) / (1 - am_);
  Eigen::VectorXd v1 = v_ + h * (1 - gamma_) * a_ + h * gamma_ * a1;                   // (G4)
  Eigen::VectorXd x = h * (v_ + h * (0.5 - beta_) * a_ + h * beta_ * a1);               // (G3)
  if (settings_.predictor == AccelerationPredictor::previous) {  // (G3'): v̇_{n+1} = v̇_n, x and v along (G6)
    vd = vdot_;
    x += vd / bp;
    v1 += (gp / bp) * vd;
  }
  Eigen::VectorXd lam = lambda_, r, phi, rhs(n + m), dx;
  Attempt out{false, 0, 0, 0.0, 0.0, {}};
  if (have_matrix_ && std::abs(matrix_h_ - h) > 1e-12 * h) force_full = true;  // β', γ' changed
  corrections_.clear();
  for (int it = 1; it <= settings_.max_iterations; ++it) {
    problem_.configure(x);
    // lazy (G10): a matrix whose last correction shrank the one before by less than refresh_ratio
    // has aged; it is refreshed here and kept for the following steps
    const std::size_t k = corrections_.size();
    // (G10') it has aged already when the last step's kept matrix ended on too slow a contraction
    const bool aged = settings_.policy == MatrixPolicy::lazy &&
                      ((k >= 2 && corrections_[k - 1] > settings_.refresh_ratio * corrections_[k - 2]) ||
                       (it == 1 && refresh_at_next_step_));
    const bool update = force_full || !have_matrix_ || settings_.policy == MatrixPolicy::full || aged ||
                        (settings_.policy == MatrixPolicy::nni && it >= settings_.nni_threshold);
    problem_.evaluate(t_ + h, v1, vd, lam, r, phi, update ? &w : nullptr, update ? &S_ : nullptr, update ? &B_ : nullptr);
    out.residual_norm = std::sqrt(r.squaredNorm() + phi.squaredNorm());
    if (!finite(r) || !finite(phi)) {
      out.failure = "non-finite residual at iteration " + std::to_string(it);
      return out;
    }
    if (update) {
      if (constraint_scale_ == 0.0) {  // (G7): constraint rows scaled to the mean |S_ii| of the first matrix
        const Eigen::VectorXd& diagonal = diagonal_of_S();
        double sum = 0.0;
        for (int i = 0; i < n; ++i) sum += std::abs(diagonal[i]);
        constraint_scale_ = n > 0 && sum > 0 ? sum / n : 1.0;
      }
      std::string why;
      if (!update_matrix(why)) {
        out.failure = why;
        return out;
      }
      matrix_h_ = h;
      ++out.updates;
    }
    rhs << -r, -constraint_scale_ * phi;
    const LinearStatus st = solver_.solve(rhs, dx);
    ++out.iterations;
    if (!st) {
      out.failure = "linear solve: " + st.message;
      return out;
    }
    const auto dq = dx.head(n);
    x += dq;
    v1 += gp * dq;
    vd += bp * dq;
    lam += constraint_scale_ * dx.tail(m);
    out.increment_norm = dq.norm();
    corrections_.push_back(out.increment_norm);
    if (!std::isfinite(out.increment_norm)) {
      out.failure = "non-finite Newton correction at iteration " + std::to_string(it);
      return out;
    }
    if (out.increment_norm < settings_.tolerance) {
      // (G10'): the last two corrections of a kept matrix contract by about the spectral radius of
      // I − A_kept⁻¹ A, the measure of how far it has aged
      refresh_at_next_step_ = out.updates == 0 && k >= 1 &&
                              out.increment_norm > settings_.step_refresh_ratio * corrections_[k - 1];
      problem_.configure(x);
      problem_.commit();
      t_ += h;
      a1 += (1 - af_) / (1 - am_) * vd;  // a_{n+1} (G5)
      local_error_ += (h * h * local_error_coefficient_) * (a1 - a_);  // (G12)
      a_ = a1;
      v_ = v1;
      vdot_ = vd;
      lambda_ = lam;
      out.converged = true;
      return out;
    }
  }
  out.failure = "no convergence in " + std::to_string(settings_.max_iterations) + " iterations (|dx| = " +
                num(out.increment_norm) + " against the tolerance " + num(settings_.tolerance) + ")";
  return out;
}

StepReport GeneralizedAlpha::step(double h) {
  StepReport rep;
  auto account = [&](const Attempt& a) {
    rep.iterations += a.iterations;
    rep.matrix_updates += a.updates;
    rep.increment_norm = a.increment_norm;
    rep.residual_norm = a.residual_norm;
    noi_ += a.iterations;
  };
  Attempt a = attempt(h, false);
  account(a);
  if (!a.converged && settings_.policy != MatrixPolicy::full) {  // stale matrix: once more with fresh ones
    problem_.rollback();
    ++rep.fallbacks;
    ++fallbacks_;
    a = attempt(h, true);
    account(a);
  }
  if (a.converged) {
    rep.converged = true;
    return rep;
  }
  problem_.rollback();
  // cut-backs: two half steps, recursively, up to max_cutbacks halvings
  std::string failure = a.failure;
  const GeneralizedAlphaSettings saved = settings_;
  if (settings_.max_cutbacks > 0) {
    --settings_.max_cutbacks;
    StepReport first = step(0.5 * h), second;
    if (first.converged) second = step(0.5 * h);
    settings_.max_cutbacks = saved.max_cutbacks;
    rep.iterations += first.iterations + second.iterations;
    rep.matrix_updates += first.matrix_updates + second.matrix_updates;
    rep.fallbacks += first.fallbacks + second.fallbacks;
    rep.substeps = first.substeps + second.substeps;
    if (first.converged && second.converged) {
      rep.converged = true;
      rep.increment_norm = second.increment_norm;
      rep.residual_norm = second.residual_norm;
      return rep;
    }
    // a converged first half stays: the run stops at the last state that converged
    failure = first.converged ? second.failure : first.failure;
  }
  rep.failure = "step at t = " + num(t_) + " s with h = " + num(h) + " s: " + failure;
  return rep;
}

}  // namespace ff
