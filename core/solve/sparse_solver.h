#pragma once
/// \file sparse_solver.h
/// Sparse direct solver for K x = b with K square, sparse and in general non-symmetric (tangent
/// stiffness with follower loads or drilling penalties). One object per linear system: analyze()
/// once per sparsity pattern, factorize() per Newton iteration, solve() per right-hand side.
/// Every failure (singular pivot with its DoF, non-finite entries or solution, indefinite matrix for
/// a Cholesky backend, missing backend) is returned as a LinearStatus, never thrown or aborted.
/// Backend choice and its benchmark: core/solve/static_solvers.md §4.

#include <Eigen/SparseCore>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ff {

using SparseMatrixD = Eigen::SparseMatrix<double, Eigen::ColMajor, int>;

enum class LinearBackend {
  umfpack,         ///< SuiteSparse UMFPACK (multifrontal LU, AMD/COLAMD), via Eigen::UmfPackLU
  sparse_lu,       ///< Eigen::SparseLU with COLAMD ordering (supernodal LU, no external library)
  cholmod_llt,     ///< CHOLMOD supernodal LLᵀ: symmetric positive definite only (fails past a limit point)
  simplicial_ldlt,  ///< Eigen::SimplicialLDLT (AMD): symmetric, no pivoting; for symmetric indefinite use LU
  mumps             ///< MUMPS (sequential or MPI build), nested dissection: LDLᵀ when K = Kᵀ, else LU (per factorization)
};

/// The backend every solver uses unless a scene says otherwise: MUMPS when compiled in (LDLᵀ for
/// the symmetric static tangents, LU otherwise), else UMFPACK, else Eigen's SparseLU
/// (static_solvers.md §7 gives the measurements).
LinearBackend default_linear_backend();
/// Compiled in (UMFPACK and CHOLMOD need SuiteSparse at configure time).
bool linear_backend_available(LinearBackend backend);
/// True for the Cholesky-type backends, which read only one triangle and need K = Kᵀ.
bool linear_backend_is_symmetric(LinearBackend backend);
/// How MUMPS orders on one rank: MUMPS's own automatic choice, or our METIS ordering
/// (nested_dissection.h) when FLEXFRAME_MUMPS_ORDERING=metis.
const char* mumps_ordering_description();
/// The shared library this process runs MUMPS from (empty without MUMPS), as the loader found it.
std::string mumps_library_file();
/// MUMPS_VERSION of the headers this build compiled against ("" without MUMPS).
std::string mumps_version();
/// The folder of the source-built MUMPS this binary was configured to link (scripts/build_mumps:
/// FLEXFRAME_MUMPS_SEQ_DIR, or FLEXFRAME_MUMPS_MPI_DIR for the MPI build); empty for Debian's binary.
std::string mumps_configured_folder();
/// Scene-file name: "umfpack", "sparse_lu", "cholmod_llt", "simplicial_ldlt", "mumps".
std::string_view to_string(LinearBackend backend);
std::optional<LinearBackend> parse_linear_backend(std::string_view name);
std::vector<LinearBackend> all_linear_backends();

struct LinearStatus {
  enum class Code {
    ok,
    unavailable,             ///< backend not compiled in
    invalid_input,           ///< not square, size mismatch, factorize()/solve() out of order
    non_finite_matrix,       ///< NaN/Inf entry in K (dof = its column)
    not_symmetric,           ///< K ≠ Kᵀ given to a symmetric backend (dof = a column where it differs)
    singular,                ///< zero pivot (dof = the unknown whose column is dependent, when known)
    not_positive_definite,   ///< Cholesky failed (dof = the column where it failed, when known)
    non_finite_solution,     ///< NaN/Inf in x (dof = its index)
    backend_error            ///< anything else the library reported
  };
  Code code = Code::ok;
  int dof = -1;           ///< row/column index of the offending unknown, -1 when unknown
  std::string message;    ///< one line for logs and result files
  bool ok() const { return code == Code::ok; }
  explicit operator bool() const { return ok(); }
};

/// A backend's own figures of its last factorization (MUMPS only; zero otherwise): what
/// docs/performance.md scales to larger models from.
struct LinearFigures {
  int ranks = 1;                    ///< processes the factorization ran on (solver_ranks.h)
  double flops = 0.0;               ///< floating-point operations of the elimination
  double memory_mb_max_rank = 0.0;  ///< MB the factorization used on its largest rank
  double memory_mb_total = 0.0;     ///< MB over all ranks
  double factor_entries = 0.0;      ///< entries of the factors
};

/// What MUMPS's analysis alone (no factorization) estimates a factorization of a pattern needs,
/// over the ranks sharing the solvers (solver_ranks.h): how docs/performance.md sizes models too
/// large to factorize here (core/solve/distributed.md, "What is left" 8).
struct FactorizationEstimate {
  int ranks = 1;
  double flops = 0.0;               ///< RINFOG(1): floating-point operations of the elimination
  double factor_entries = 0.0;      ///< INFOG(20): entries of the factors
  double memory_mb_max_rank = 0.0;  ///< INFOG(16): MB of the in-core factorization on its largest rank
  double memory_mb_total = 0.0;     ///< INFOG(17): MB over all ranks
  int largest_front = 0;            ///< INFOG(5): order of the largest frontal matrix
};

/// Runs MUMPS's analysis (LDLᵀ, symmetric) of an n x n pattern given by the 0-based coordinates of
/// its lower triangle (rows[k] >= cols[k]) and returns its estimates. Over several ranks each passes
/// its own share of the entries (together the whole triangle, any split), so no rank builds the
/// whole pattern; the vectors are taken over, since they may be large. `unavailable` without MUMPS.
LinearStatus estimate_symmetric_factorization(int n, std::vector<int> rows, std::vector<int> cols,
                                              FactorizationEstimate& out);

class SparseLinearSolver {
 public:
  explicit SparseLinearSolver(LinearBackend backend = default_linear_backend());
  ~SparseLinearSolver();
  SparseLinearSolver(SparseLinearSolver&&) noexcept;
  SparseLinearSolver& operator=(SparseLinearSolver&&) noexcept;

  LinearBackend backend() const { return backend_; }
  /// Ordering and symbolic factorization of the pattern of `pattern` (values ignored). Needs a
  /// compressed column-major matrix.
  LinearStatus analyze(const SparseMatrixD& pattern);
  /// Numeric factorization. Re-analyzes by itself when K's pattern differs from the analyzed one
  /// (compared index by index, O(nnz)), so callers may simply call factorize() every iteration.
  LinearStatus factorize(const SparseMatrixD& k);
  /// Replaces K by its symmetric part ½(K + Kᵀ), in place through the mirror table of the
  /// pattern (a structurally unsymmetric pattern takes the transpose and the sum: the same
  /// numbers), and factorizes that: a backend that can use symmetry does (static_solvers.md §7.1).
  LinearStatus factorize_symmetric_part(SparseMatrixD& k);
  /// x = K⁻¹ b with the last successful factorization.
  LinearStatus solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const;

  /// Processes this solver's factorization spans: the ranks sharing the solvers for MUMPS
  /// (solver_ranks.h), 1 for every other backend and when alone.
  int ranks() const;
  /// For a matrix assembled in parts over the ranks (core/solve/distributed.md §5): the positions
  /// of the CSC value array (ascending) whose values this rank holds in full and alone hands the
  /// factorization. Together the ranks' lists hold every position once, each list holds the mirror
  /// (j, i) of each of its entries (i, j), and the pattern must be structurally symmetric; the
  /// values at other positions are never read. The checks that read values (non-finite entries,
  /// the symmetry that picks LDLᵀ) are made over this rank's positions and reduced over the ranks,
  /// so every rank takes the same decision. A rank may hold no entry (a small model over many
  /// ranks). invalid_input when ranks() is 1.
  LinearStatus hold_positions_over_ranks(std::vector<int> positions);
  /// The matrix is held in parts (hold_positions_over_ranks succeeded).
  bool held_in_parts() const { return in_parts_; }

  /// Sign of det K for the last factorization: +1 or −1, 0 when singular or not factorized. Its
  /// change along a load path marks a limit or bifurcation point (static_solvers.md §4.4). O(n).
  int determinant_sign() const;

  /// True when the last factorization used K's symmetry: the Cholesky-type backends always, MUMPS
  /// when K = Kᵀ to round-off (LDLᵀ instead of LU, static_solvers.md §7).
  bool symmetric_factorization() const;

  /// The library's figures of the last successful factorization (zeros when it gives none).
  LinearFigures factorization_figures() const;

  bool factorized() const { return factorized_; }
  int rows() const { return n_; }
  int analyses() const { return analyses_; }            ///< symbolic factorizations so far
  int factorizations() const { return factorizations_; }  ///< numeric factorizations so far

  class Impl;  ///< one per backend (sparse_solver.cpp)

 private:
  bool same_pattern(const SparseMatrixD& k) const;
  /// factorize() for a K known to be exactly symmetric (no check) or not (checked as it says)
  LinearStatus factorize_values(const SparseMatrixD& k, bool known_symmetric);
  /// The first column where K and Kᵀ differ by more than relative_bound × max|K_ij|, −1 when
  /// symmetric; read through mirror_, no transpose. With `any`, the column of the first difference
  /// met is returned at once (enough to tell that K ≠ Kᵀ: a dynamics matrix differs in its first
  /// columns, and the full scan was 2 % of a factorizing run).
  int first_asymmetric_column(const SparseMatrixD& k, double relative_bound, bool any = false) const;
  LinearBackend backend_;
  std::unique_ptr<Impl> impl_;
  int n_ = 0;
  bool analyzed_ = false, factorized_ = false;
  int analyses_ = 0, factorizations_ = 0;
  std::vector<int> outer_, inner_;  // analyzed pattern
  std::vector<int> mirror_;         // CSC position of (j, i) for each (i, j), −1 when absent
  std::vector<int> held_;           // hold_positions_over_ranks, when in_parts_
  bool in_parts_ = false;
  /// The first column holding a NaN/Inf among the values read (over the ranks), −1 when none.
  int first_non_finite_column(const SparseMatrixD& k) const;
  /// held_'s fit with the analyzed pattern (ascending, in range, mirror-closed)
  LinearStatus check_held_positions() const;
};

}  // namespace ff
