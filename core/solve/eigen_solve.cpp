#include "core/solve/eigen_solve.h"

#include <Spectra/SymGEigsShiftSolver.h>
#include <Spectra/SymGEigsSolver.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numeric>
#include <stdexcept>

namespace ff {

namespace {

using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

// y = A⁻¹ x with a factorized solver; a failed solve gives NaN, which stops Spectra (the caller's
// status says why)
void solve_into(const SparseLinearSolver& solver, const double* x, double* y, Eigen::Index n) {
  Eigen::VectorXd b = Eigen::Map<const Eigen::VectorXd>(x, n), sol;
  Eigen::Map<Eigen::VectorXd> yv(y, n);
  if (solver.solve(b, sol))
    yv = sol;
  else
    yv.setConstant(std::numeric_limits<double>::quiet_NaN());
}

// y = A x for a sparse symmetric A stored whole (both triangles)
class ProductOp {
 public:
  using Scalar = double;
  explicit ProductOp(const SparseMatrixD& a, double sign = 1.0) : a_(a), sign_(sign) {}
  Eigen::Index rows() const { return a_.rows(); }
  Eigen::Index cols() const { return a_.cols(); }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<const Eigen::VectorXd> xv(x, a_.cols());
    Eigen::Map<Eigen::VectorXd> yv(y, a_.rows());
    yv.noalias() = sign_ * (a_ * xv);
  }

 private:
  const SparseMatrixD& a_;
  double sign_;
};

// y = (K − σM)⁻¹ x through one factorization per shift (Spectra's shift-invert operator)
class ShiftSolveOp {
 public:
  using Scalar = double;
  ShiftSolveOp(const SparseMatrixD& k, const SparseMatrixD& m, LinearBackend backend, EigenSolveResult& out)
      : k_(k), m_(m), solver_(backend), out_(out) {}
  Eigen::Index rows() const { return k_.rows(); }
  Eigen::Index cols() const { return k_.cols(); }
  void set_shift(double sigma) {
    const Clock::time_point t0 = Clock::now();
    SparseMatrixD shifted = k_ - sigma * m_;
    shifted.makeCompressed();
    status_ = solver_.factorize(shifted);
    ++out_.factorizations;
    out_.factorization_seconds += seconds_since(t0);
  }
  const LinearStatus& status() const { return status_; }
  void perform_op(const double* x, double* y) const { solve_into(solver_, x, y, k_.rows()); }

 private:
  const SparseMatrixD& k_;
  const SparseMatrixD& m_;
  SparseLinearSolver solver_;
  LinearStatus status_;
  EigenSolveResult& out_;
};

// y = top of [K − σM, Bᵀ; B, 0]⁻¹ [x; 0]: the shift-invert operator restricted to the constraints
class BorderedShiftSolveOp {
 public:
  using Scalar = double;
  BorderedShiftSolveOp(const SparseMatrixD& k, const SparseMatrixD& m, const SparseMatrixD& b, LinearBackend backend,
                       EigenSolveResult& out)
      : k_(k), m_(m), b_(b), solver_(backend), out_(out) {}
  Eigen::Index rows() const { return k_.rows(); }
  Eigen::Index cols() const { return k_.cols(); }
  void set_shift(double sigma) {
    const Clock::time_point t0 = Clock::now();
    const Eigen::Index n = k_.rows(), c = b_.rows();
    std::vector<Eigen::Triplet<double>> t;
    t.reserve(k_.nonZeros() + m_.nonZeros() + 2 * b_.nonZeros());
    for (const SparseMatrixD* a : {&k_, &m_}) {
      const double f = a == &k_ ? 1.0 : -sigma;
      for (int j = 0; j < a->outerSize(); ++j)
        for (SparseMatrixD::InnerIterator it(*a, j); it; ++it) t.emplace_back(it.row(), it.col(), f * it.value());
    }
    for (int j = 0; j < b_.outerSize(); ++j)
      for (SparseMatrixD::InnerIterator it(b_, j); it; ++it) {
        t.emplace_back(n + it.row(), it.col(), it.value());
        t.emplace_back(it.col(), n + it.row(), it.value());
      }
    SparseMatrixD bordered(n + c, n + c);
    bordered.setFromTriplets(t.begin(), t.end());
    bordered.makeCompressed();
    status_ = solver_.factorize(bordered);
    ++out_.factorizations;
    out_.factorization_seconds += seconds_since(t0);
  }
  const LinearStatus& status() const { return status_; }
  void perform_op(const double* x, double* y) const {
    const Eigen::Index n = k_.rows();
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(n + b_.rows()), sol;
    rhs.head(n) = Eigen::Map<const Eigen::VectorXd>(x, n);
    const LinearStatus s = solver_.solve(rhs, sol);
    Eigen::Map<Eigen::VectorXd> yv(y, n);
    if (s)
      yv = sol.head(n);
    else
      yv.setConstant(std::numeric_limits<double>::quiet_NaN());
  }

 private:
  const SparseMatrixD& k_;
  const SparseMatrixD& m_;
  const SparseMatrixD& b_;
  SparseLinearSolver solver_;
  LinearStatus status_;
  EigenSolveResult& out_;
};

// Spectra's regular-inverse B operator: y = K₀ x and y = K₀⁻¹ x with one factorization
class FactorizedOp {
 public:
  using Scalar = double;
  FactorizedOp(const SparseMatrixD& k, LinearBackend backend, EigenSolveResult& out) : k_(k), solver_(backend) {
    const Clock::time_point t0 = Clock::now();
    SparseMatrixD copy = k;
    copy.makeCompressed();
    status_ = solver_.factorize(copy);
    ++out.factorizations;
    out.factorization_seconds += seconds_since(t0);
  }
  const LinearStatus& status() const { return status_; }
  int determinant_sign() const { return solver_.determinant_sign(); }
  Eigen::Index rows() const { return k_.rows(); }
  Eigen::Index cols() const { return k_.cols(); }
  void perform_op(const double* x, double* y) const {
    Eigen::Map<const Eigen::VectorXd> xv(x, k_.cols());
    Eigen::Map<Eigen::VectorXd> yv(y, k_.rows());
    yv.noalias() = k_ * xv;
  }
  void solve(const double* x, double* y) const { solve_into(solver_, x, y, k_.rows()); }

 private:
  const SparseMatrixD& k_;
  SparseLinearSolver solver_;
  LinearStatus status_;
};

std::string info_text(Spectra::CompInfo info) {
  switch (info) {
    case Spectra::CompInfo::Successful: return "";
    case Spectra::CompInfo::NotComputed: return "the eigen-solver did not run";
    case Spectra::CompInfo::NotConverging: return "the Lanczos iteration did not converge within its restarts";
    case Spectra::CompInfo::NumericalIssue: return "the Lanczos iteration met a numerical issue";
  }
  return "the eigen-solver failed";
}

// columns of V reordered by ascending values
void sort_ascending(std::vector<double>& values, Eigen::MatrixXd& vectors) {
  std::vector<int> order(values.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](int a, int b) { return values[a] < values[b]; });
  std::vector<double> v(values.size());
  Eigen::MatrixXd m(vectors.rows(), vectors.cols());
  for (std::size_t k = 0; k < order.size(); ++k) v[k] = values[order[k]], m.col(k) = vectors.col(order[k]);
  values = std::move(v);
  vectors = std::move(m);
}

// A shift-invert operator with the pairs already found taken out (deflation in the M inner
// product, shell_eigen.md (E2'')): Spectra hands it z = M x, and y = op(z) − Φ diag(ν) Φᵀ z with
// ν_i = 1/(ω_i² − σ) maps every found mode to zero and leaves every other one as it was (the found
// modes are M-orthonormal). Its shift is the one `op` is factorized for already.
template <class Op>
class DeflatedShiftSolveOp {
 public:
  using Scalar = double;
  DeflatedShiftSolveOp(const Op& op, const Eigen::MatrixXd& found, Eigen::VectorXd nu)
      : op_(op), found_(found), nu_(std::move(nu)) {}
  Eigen::Index rows() const { return op_.rows(); }
  Eigen::Index cols() const { return op_.cols(); }
  void set_shift(double) {}
  void perform_op(const double* x, double* y) const {
    op_.perform_op(x, y);
    Eigen::Map<const Eigen::VectorXd> xv(x, op_.cols());
    Eigen::Map<Eigen::VectorXd> yv(y, op_.rows());
    yv.noalias() -= found_ * (nu_.asDiagonal() * (found_.transpose() * xv));
  }

 private:
  const Op& op_;
  const Eigen::MatrixXd& found_;
  Eigen::VectorXd nu_;
};

// Lanczos can miss copies of a repeated eigenvalue (a free structure's six rigid-body modes share
// ω² = 0: in exact arithmetic a Krylov space holds one vector of an eigenspace, and only round-off
// brings the others in; a different elimination order of the same matrix lost one of six). So the
// found pairs are checked: Lanczos on the deflated operator for the lowest mode not found yet; while
// it lies below the highest found, it replaces that one, and the check runs again.
template <class Op>
void recover_missed_modes(const Op& op, const SparseMatrixD& M, double shift, const EigenSolveSettings& settings,
                          int free_unknowns, EigenSolveResult& out) {
  const int basis = std::min(20, free_unknowns - 1);
  if (basis < 2 || out.values.empty()) return;
  ProductOp mass(M);
  for (int pass = 0; pass < settings.count; ++pass) {
    Eigen::VectorXd nu(out.values.size());
    for (std::size_t i = 0; i < out.values.size(); ++i) nu[i] = 1.0 / (out.values[i] - shift);
    const Eigen::MatrixXd found = out.vectors;
    DeflatedShiftSolveOp<Op> deflated(op, found, nu);
    Spectra::SymGEigsShiftSolver<DeflatedShiftSolveOp<Op>, ProductOp, Spectra::GEigsMode::ShiftInvert> check(
        deflated, mass, 1, basis, shift);
    try {
      check.init();
      check.compute(Spectra::SortRule::LargestMagn, settings.max_restarts, settings.tolerance);
    } catch (const std::exception&) {
      return;  // the modes found stand; the check could not run
    }
    out.operator_applications += static_cast<int>(check.num_operations());
    if (check.info() != Spectra::CompInfo::Successful) return;
    const double value = check.eigenvalues()[0];
    const Eigen::VectorXd vector = check.eigenvectors().col(0);
    // below the highest found, and a new direction (not a found mode left over by the deflation)
    if (!(value < out.values.back()) || !vector.allFinite() || (found.transpose() * (M * vector)).cwiseAbs().maxCoeff() > 1e-6)
      return;
    out.values.back() = value;
    out.vectors.col(out.vectors.cols() - 1) = vector;
    ++out.recovered;
    sort_ascending(out.values, out.vectors);
  }
}

// The Lanczos run of a shift-invert solver whose operator is factorized (its constructor did it),
// its checks, and the recovery of missed copies (E2''): into `out`, or out.error
template <class Solver, class Op>
void shift_invert_lanczos(Solver& solver, const Op& op, const SparseMatrixD& M, double shift,
                          const EigenSolveSettings& settings, int free_unknowns, const std::string& solve_name,
                          EigenSolveResult& out) {
  const Clock::time_point t0 = Clock::now();
  try {  // Spectra reports a failed inner decomposition by throwing
    solver.init();
    solver.compute(Spectra::SortRule::LargestMagn, settings.max_restarts, settings.tolerance);
  } catch (const std::exception& e) {
    out.error = std::string("the Lanczos iteration failed: ") + e.what() + " (" + solve_name +
                " gave no finite answer, or the problem is not symmetric definite)";
    return;
  }
  out.operator_applications = static_cast<int>(solver.num_operations());
  out.restarts = static_cast<int>(solver.num_iterations());
  if (solver.info() != Spectra::CompInfo::Successful) {
    out.error = info_text(solver.info());
    return;
  }
  const Eigen::VectorXd values = solver.eigenvalues();
  out.values.assign(values.data(), values.data() + values.size());
  out.vectors = solver.eigenvectors();
  if (!out.vectors.allFinite()) {
    out.error = "the eigenvectors are not finite (" + solve_name + " failed)";
    return;
  }
  sort_ascending(out.values, out.vectors);
  recover_missed_modes(op, M, shift, settings, free_unknowns, out);
  out.iteration_seconds = seconds_since(t0);
}

}  // namespace

double largest_stiffness_to_mass(const SparseMatrixD& K, const SparseMatrixD& M) {
  double largest = 0.0;
  for (int i = 0; i < K.rows(); ++i)
    if (M.coeff(i, i) > 0.0) largest = std::max(largest, K.coeff(i, i) / M.coeff(i, i));
  return largest;
}

long long lanczos_basis_size(const EigenSolveSettings& settings, long long n) {
  const long long count = settings.count;
  const long long wanted = settings.subspace > 0 ? settings.subspace : std::max(2 * count + 1, count + 20);
  return std::min(wanted, n);
}

double lanczos_peak_bytes(const EigenSolveSettings& settings, long long n) {
  const double ncv = static_cast<double>(lanczos_basis_size(settings, n)), count = settings.count;
  return 8.0 * (static_cast<double>(n) * std::max(2.0 * ncv, ncv + 2.0 * count) + 4.0 * ncv * ncv);
}

EigenSolveResult lowest_vibration_modes(const SparseMatrixD& K, const SparseMatrixD& M, double shift,
                                        const EigenSolveSettings& settings) {
  EigenSolveResult out;
  const int n = static_cast<int>(K.rows());
  if (settings.count < 1 || settings.count >= n) {
    out.error = "asked for " + std::to_string(settings.count) + " modes of a structure with " + std::to_string(n) +
                " unknowns (at most " + std::to_string(n - 1) + ")";
    return out;
  }
  ShiftSolveOp op(K, M, settings.backend, out);
  ProductOp mass(M);
  using Solver = Spectra::SymGEigsShiftSolver<ShiftSolveOp, ProductOp, Spectra::GEigsMode::ShiftInvert>;
  Solver solver(op, mass, settings.count, static_cast<int>(lanczos_basis_size(settings, n)), shift);  // factorizes K − σM
  if (!op.status()) {
    out.error = "K - shift M could not be factorized: " + op.status().message +
                (op.status().code == LinearStatus::Code::singular ? " (the shift is an eigenvalue; choose another)" : "");
    return out;
  }
  shift_invert_lanczos(solver, op, M, shift, settings, n, "a solve with K - shift M", out);
  return out;
}

EigenSolveResult lowest_constrained_vibration_modes(const SparseMatrixD& K, const SparseMatrixD& M,
                                                    const SparseMatrixD& B, double shift,
                                                    const EigenSolveSettings& settings) {
  if (B.rows() == 0) return lowest_vibration_modes(K, M, shift, settings);
  EigenSolveResult out;
  const int n = static_cast<int>(K.rows());
  if (settings.count < 1 || settings.count >= n - static_cast<int>(B.rows())) {
    out.error = "asked for " + std::to_string(settings.count) + " modes of a structure with " + std::to_string(n) +
                " unknowns and " + std::to_string(B.rows()) + " constraints";
    return out;
  }
  BorderedShiftSolveOp op(K, M, B, settings.backend, out);
  ProductOp mass(M);
  using Solver = Spectra::SymGEigsShiftSolver<BorderedShiftSolveOp, ProductOp, Spectra::GEigsMode::ShiftInvert>;
  Solver solver(op, mass, settings.count, static_cast<int>(lanczos_basis_size(settings, n)), shift);
  if (!op.status()) {
    out.error = "the bordered matrix [K - shift M, B'; B, 0] could not be factorized: " + op.status().message +
                (op.status().code == LinearStatus::Code::singular
                     ? " (redundant joint constraints, or the shift is an eigenvalue)"
                     : "");
    return out;
  }
  shift_invert_lanczos(solver, op, M, shift, settings, n - static_cast<int>(B.rows()), "a bordered solve", out);
  return out;
}

EigenSolveResult lowest_buckling_multipliers(const SparseMatrixD& K0, const SparseMatrixD& KG,
                                             const EigenSolveSettings& settings, int* negative) {
  EigenSolveResult out;
  const int n = static_cast<int>(K0.rows());
  if (negative) *negative = 0;
  if (settings.count < 1 || settings.count >= n) {
    out.error = "asked for " + std::to_string(settings.count) + " buckling modes of a structure with " +
                std::to_string(n) + " unknowns (at most " + std::to_string(n - 1) + ")";
    return out;
  }
  FactorizedOp k0(K0, settings.backend, out);
  if (!k0.status()) {
    out.error = "the stiffness could not be factorized: " + k0.status().message +
                (k0.status().code == LinearStatus::Code::singular
                     ? " (a mechanism: some part is not held against rigid motion, which buckles at no load)"
                     : "");
    return out;
  }
  ProductOp minus_kg(KG, -1.0);
  using Solver = Spectra::SymGEigsSolver<ProductOp, FactorizedOp, Spectra::GEigsMode::RegularInverse>;
  Solver solver(minus_kg, k0, settings.count, static_cast<int>(lanczos_basis_size(settings, n)));
  const Clock::time_point t0 = Clock::now();
  try {
    solver.init();
    solver.compute(Spectra::SortRule::LargestAlge, settings.max_restarts, settings.tolerance);
  } catch (const std::exception& e) {
    out.error = std::string("the Lanczos iteration failed: ") + e.what() +
                " (a solve with the stiffness gave no finite answer: a mechanism?)";
    return out;
  }
  out.iteration_seconds = seconds_since(t0);
  out.operator_applications = static_cast<int>(solver.num_operations());
  out.restarts = static_cast<int>(solver.num_iterations());
  if (solver.info() != Spectra::CompInfo::Successful) {
    out.error = info_text(solver.info());
    return out;
  }
  const Eigen::VectorXd theta = solver.eigenvalues();
  const Eigen::MatrixXd vectors = solver.eigenvectors();
  if (!vectors.allFinite()) {
    out.error = "the eigenvectors are not finite (a failed solve with the stiffness)";
    return out;
  }
  // θ = 1/λ: the largest positive θ are the smallest positive λ; θ ≤ 0 buckle only reversed
  std::vector<int> kept;
  for (int k = 0; k < theta.size(); ++k)
    if (theta[k] > 0.0)
      kept.push_back(k);
    else if (negative)
      ++*negative;
  out.vectors.resize(n, static_cast<Eigen::Index>(kept.size()));
  for (std::size_t k = 0; k < kept.size(); ++k) {
    out.values.push_back(1.0 / theta[kept[k]]);
    out.vectors.col(k) = vectors.col(kept[k]);
  }
  sort_ascending(out.values, out.vectors);
  return out;
}

}  // namespace ff
