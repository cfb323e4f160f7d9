#pragma once
/// \file eigen_solve.h
/// The lowest eigen-pairs of the two symmetric generalized problems of structural analysis
/// (core/shell/shell_eigen.md): natural vibration K φ = ω² M φ, and linear buckling
/// (K₀ + λ K_G) φ = 0. Spectra's implicitly restarted Lanczos iterates on an operator whose
/// largest eigenvalues are the wanted ones; every linear solve goes through one factorization of
/// SparseLinearSolver (MUMPS LDLᵀ by default), made once per analysis. Failures (a singular
/// shifted matrix, no convergence) come back as a reason, never thrown.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/solve/sparse_solver.h"

namespace ff {

struct EigenSolveSettings {
  int count = 6;        ///< eigen-pairs wanted
  /// Lanczos basis size (0: max(2 count + 1, count + 20), at most n). A larger basis converges
  /// clustered spectra (a cylinder's buckling loads) in fewer restarts.
  int subspace = 0;
  int max_restarts = 1000;
  double tolerance = 1e-10;  ///< Spectra's relative residual tolerance of a Ritz pair
  LinearBackend backend = default_linear_backend();
};

struct EigenSolveResult {
  std::string error;              ///< "" when every wanted pair converged
  std::vector<double> values;     ///< ascending: ω² (modal) or λ (buckling)
  Eigen::MatrixXd vectors;        ///< one column per value, M- (modal) or K₀- (buckling) normalized
  int factorizations = 0;
  int operator_applications = 0;  ///< Lanczos matrix-vector products (one solve each)
  int restarts = 0;
  int recovered = 0;              ///< modes the first Lanczos run missed, found by the deflated check
  double factorization_seconds = 0.0, iteration_seconds = 0.0;
  bool ok() const { return error.empty(); }
};

/// max_i K_ii / M_ii over the rows with mass (0 when none): a structure's frequency scale ω²_ref,
/// of the order of its highest ω² (shell_eigen.md (E3)).
double largest_stiffness_to_mass(const SparseMatrixD& K, const SparseMatrixD& M);

/// The Lanczos basis a solve of `n` unknowns builds: settings.subspace, or max(2 count + 1,
/// count + 20) when it is 0; at most n.
long long lanczos_basis_size(const EigenSolveSettings& settings, long long n);

/// Peak memory [bytes] of the Lanczos iteration on `n` unknowns, beside the matrices and their
/// factorization (shell_eigen.md §5): Spectra keeps the basis V (n x ncv doubles) and, while it
/// restarts, builds the compressed basis in a second n x (k + 1) block (k < ncv) before copying it
/// back; the ncv x ncv tridiagonal matrix, its rotations and its eigenvectors; at the end the
/// n x count Ritz vectors and their sorted copy beside V. So n max(2 ncv, ncv + 2 count) + 4 ncv²
/// doubles. For `check`, which refuses a basis the machine cannot hold before any is allocated.
double lanczos_peak_bytes(const EigenSolveSettings& settings, long long n);

/// The `count` eigenvalues ω² of K φ = ω² M φ nearest above the shift σ (K, M symmetric, M
/// positive definite), by shift-invert: Lanczos on (K − σM)⁻¹ M in the M inner product, whose
/// largest eigenvalues ν = 1/(ω² − σ) are those ω² closest to σ from above (shell_eigen.md (E2)).
/// σ below zero makes K − σM positive definite for a positive semi-definite K (free parts: ω² = 0).
EigenSolveResult lowest_vibration_modes(const SparseMatrixD& K, const SparseMatrixD& M, double shift,
                                        const EigenSolveSettings& settings);

/// As lowest_vibration_modes, for a structure whose unknowns are tied by linear constraints B φ = 0
/// (joints, m rows): the multipliers are massless, and each Lanczos step solves the bordered
/// system [K − σM, Bᵀ; B, 0] [y; μ] = [M x; 0] with one factorization of that symmetric indefinite
/// matrix (shell_eigen.md (E2')). The constraints must be independent (a redundant joint makes the
/// bordered matrix singular: the failure says so).
EigenSolveResult lowest_constrained_vibration_modes(const SparseMatrixD& K, const SparseMatrixD& M,
                                                    const SparseMatrixD& B, double shift,
                                                    const EigenSolveSettings& settings);

/// The `count` smallest positive multipliers λ of (K₀ + λ K_G) φ = 0 (K₀ symmetric positive
/// definite, K_G symmetric), by the regular-inverse Lanczos on K₀⁻¹(−K_G) in the K₀ inner product:
/// its largest eigenvalues θ = 1/λ (shell_eigen.md (E5)). Fewer than `count` come back when the
/// largest θ are not all positive (the rest buckle only under the reversed load); `negative`
/// counts those found.
EigenSolveResult lowest_buckling_multipliers(const SparseMatrixD& K0, const SparseMatrixD& KG,
                                             const EigenSolveSettings& settings, int* negative = nullptr);

}  // namespace ff
