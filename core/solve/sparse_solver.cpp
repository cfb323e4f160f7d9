#include "core/solve/sparse_solver.h"

#include "core/solve/equilibrate.h"
#include "core/solve/nested_dissection.h"
#include "core/solve/solver_ranks.h"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>
#include <Eigen/SparseLU>
#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <limits>
#include <sstream>

#ifdef FF_HAVE_SUITESPARSE
#include <Eigen/CholmodSupport>
#include <Eigen/UmfPackSupport>
#endif
#ifdef FF_HAVE_MUMPS
#include <dlfcn.h>
#include <dmumps_c.h>

#include "core/solve/solver_ranks_mpi.h"
#endif

namespace ff {

// FLEXFRAME_MUMPS_ORDERING=metis hands MUMPS our METIS ordering on one rank (nested_dissection.h):
// 12 % fewer flops than the SCOTCH order of Debian's sequential MUMPS on the 128² plate, but not
// the default, because MUMPS's null-pivot detection of a mechanism (a part held by nothing) found
// the singular pivot with SCOTCH's order and not with ours (docs/performance.md, the last section)
static bool own_ordering_wanted() {
  static const bool wanted = [] {
    const char* e = std::getenv("FLEXFRAME_MUMPS_ORDERING");
    return e && std::string(e) == "metis";
  }();
  return wanted;
}
const char* mumps_ordering_description() {
  return own_ordering_wanted() ? "METIS (FlexFrame's, FLEXFRAME_MUMPS_ORDERING=metis)" : "MUMPS's automatic choice";
}

std::string mumps_library_file() {
#ifdef FF_HAVE_MUMPS
  // dladdr names the object that defines dmumps_c: a RUNPATH lost at link time shows here as
  // Debian's library although the build was configured with another
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&dmumps_c), &info) != 0 && info.dli_fname != nullptr) {
    char resolved[PATH_MAX];
    return realpath(info.dli_fname, resolved) != nullptr ? resolved : info.dli_fname;
  }
#endif
  return {};
}

std::string mumps_version() {
#ifdef FF_HAVE_MUMPS
  return MUMPS_VERSION;
#else
  return {};
#endif
}

std::string mumps_configured_folder() {
#ifdef FF_MUMPS_BUILT_DIR
  return FF_MUMPS_BUILT_DIR;
#else
  return {};
#endif
}

namespace {

using Code = LinearStatus::Code;

LinearStatus fail(Code code, int dof, std::string message) {
  LinearStatus s;
  s.code = code;
  s.dof = dof;
  s.message = std::move(message);
  return s;
}

// CSC position of (j, i) for each entry (i, j) of a compressed square pattern, −1 when absent
// (the rows are sorted in each column)
std::vector<int> mirror_positions(const SparseMatrixD& k) {
  const int* outer = k.outerIndexPtr();
  const int* inner = k.innerIndexPtr();
  std::vector<int> mirror(static_cast<std::size_t>(k.nonZeros()), -1);
  for (int j = 0; j < k.outerSize(); ++j)
    for (int p = outer[j]; p < outer[j + 1]; ++p) {
      const int i = inner[p];
      const int* m = std::lower_bound(inner + outer[i], inner + outer[i + 1], j);
      if (m != inner + outer[i + 1] && *m == j) mirror[p] = static_cast<int>(m - inner);
    }
  return mirror;
}

std::string singular_message(int dof) {
  std::ostringstream m;
  m << "singular matrix: zero pivot";
  if (dof >= 0) m << " for unknown (DoF) " << dof;
  m << " (unconstrained rigid-body mode, missing support, or an exact limit/bifurcation point)";
  return m.str();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
class SparseLinearSolver::Impl {
 public:
  virtual ~Impl() = default;
  virtual LinearStatus analyze(const SparseMatrixD& a) = 0;
  /// `symmetric`: K = Kᵀ to round-off (SparseLinearSolver::first_asymmetric_column, 1e-12); a
  /// backend may use it to pick a symmetric factorization
  virtual LinearStatus factorize(const SparseMatrixD& a, bool symmetric) = 0;
  /// false when the library reports a failure during the solve
  virtual bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) = 0;
  /// sign of det K of the current factorization (+1, −1), 0 when zero or unknown
  virtual int determinant_sign() = 0;
  /// true when the last factorization used the matrix's symmetry (LDLᵀ or LLᵀ)
  virtual bool symmetric_factorization() const { return false; }
  /// the library's own flop and memory figures, when it gives them
  virtual LinearFigures figures() const { return {}; }
  /// processes the factorization spans (only MUMPS spans ranks)
  virtual int ranks() const { return 1; }
  /// SparseLinearSolver::hold_positions_over_ranks, for a backend that spans ranks (before analyze)
  virtual void hold_positions(const std::vector<int>& positions) {}
};

namespace {

// Eigen::SparseLU, COLAMD column ordering, partial pivoting (threshold 1)
class SparseLuImpl final : public SparseLinearSolver::Impl {
 public:
  LinearStatus analyze(const SparseMatrixD& a) override {
    lu_.analyzePattern(a);
    return {};
  }
  LinearStatus factorize(const SparseMatrixD& a, bool symmetric) override {
    lu_.factorize(a);
    if (lu_.info() == Eigen::Success) return {};
    // SparseLU reports "... ZERO COLUMN AT <j+1>" with j in the column-permuted numbering
    const std::string msg = lu_.lastErrorMessage();
    const auto pos = msg.find_last_of(' ');
    int dof = -1;
    if (msg.find("ZERO COLUMN") != std::string::npos && pos != std::string::npos) {
      const int jcol = std::atoi(msg.c_str() + pos + 1) - 1;
      const auto& perm = lu_.colsPermutation().indices();
      for (int i = 0; i < perm.size(); ++i)
        if (perm[i] == jcol) dof = i;
      return fail(Code::singular, dof, singular_message(dof));
    }
    return fail(Code::backend_error, -1, "SparseLU: " + msg);
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    x = lu_.solve(b);
    return lu_.info() == Eigen::Success;
  }
  int determinant_sign() override { return static_cast<int>(lu_.signDeterminant()); }

 private:
  Eigen::SparseLU<SparseMatrixD, Eigen::COLAMDOrdering<int>> lu_;
};

// Eigen::SimplicialLDLT with AMD: symmetric (lower triangle read), no pivoting
class SimplicialLdltImpl final : public SparseLinearSolver::Impl {
 public:
  LinearStatus analyze(const SparseMatrixD& a) override {
    ldlt_.analyzePattern(a);
    return {};
  }
  LinearStatus factorize(const SparseMatrixD& a, bool symmetric) override {
    ldlt_.factorize(a);
    if (ldlt_.info() == Eigen::Success) return {};
    // D(k,k) = 0 stops the factorization at k; the entries before k are non-zero
    const Eigen::VectorXd d = ldlt_.vectorD();
    int dof = -1;
    for (int k = 0; k < d.size(); ++k)
      if (d[k] == 0.0) {
        dof = ldlt_.permutationPinv().indices()[k];
        break;
      }
    return fail(Code::singular, dof, singular_message(dof));
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    x = ldlt_.solve(b);
    return ldlt_.info() == Eigen::Success;
  }
  int determinant_sign() override {  // P K Pᵀ = L D Lᵀ
    int sign = 1;
    for (double d : ldlt_.vectorD()) {
      if (d == 0.0) return 0;
      if (d < 0.0) sign = -sign;
    }
    return sign;
  }

 private:
  Eigen::SimplicialLDLT<SparseMatrixD, Eigen::Lower, Eigen::AMDOrdering<int>> ldlt_;
};

#ifdef FF_HAVE_SUITESPARSE
// Eigen's UmfPackLU keeps a reference to the factorized matrix and hands it to umfpack_solve, so
// the wrapper owns that copy. Iterative refinement is off: it made each solve ~5× slower
// (static_solvers.md §7) and the Newton iteration around every solve refines anyway.
class UmfpackImpl final : public SparseLinearSolver::Impl {
  struct Lu : Eigen::UmfPackLU<SparseMatrixD> {
    int det_sign() const {
      double mantissa = 0.0, exponent = 0.0;
      if (umfpack_di_get_determinant(&mantissa, &exponent, m_numeric, nullptr) < 0) return 0;
      return mantissa > 0.0 ? 1 : (mantissa < 0.0 ? -1 : 0);
    }
  };

 public:
  UmfpackImpl() { lu_.umfpackControl()(UMFPACK_IRSTEP) = 0; }
  LinearStatus analyze(const SparseMatrixD& a) override {
    a_ = a;
    lu_.analyzePattern(a_);
    if (lu_.info() != Eigen::Success)
      return fail(Code::backend_error, -1, "UMFPACK symbolic analysis failed");
    return {};
  }
  LinearStatus factorize(const SparseMatrixD& a, bool symmetric) override {
    std::copy(a.valuePtr(), a.valuePtr() + a.nonZeros(), a_.valuePtr());
    lu_.factorize(a_);
    if (lu_.info() == Eigen::Success) return {};
    const int code = lu_.umfpackFactorizeReturncode();
    if (code == UMFPACK_WARNING_singular_matrix) {
      // P R A Q = L U: a zero U(k,k) marks column Q(k) of A as dependent
      const auto& u = lu_.matrixU();
      const auto& q = lu_.permutationQ();
      int dof = -1;
      for (int k = 0; k < u.outerSize() && dof < 0; ++k) {
        double ukk = 0.0;
        for (SparseMatrixD::InnerIterator it(u, k); it; ++it)
          if (it.row() == k) ukk = it.value();
        if (ukk == 0.0) dof = q[k];
      }
      return fail(Code::singular, dof, singular_message(dof));
    }
    return fail(Code::backend_error, -1, "UMFPACK numeric factorization failed (status " + std::to_string(code) + ")");
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    x = lu_.solve(b);
    return lu_.info() == Eigen::Success;
  }
  int determinant_sign() override { return lu_.det_sign(); }

 private:
  SparseMatrixD a_;
  Lu lu_;
};

// CHOLMOD supernodal LLᵀ (reads the lower triangle)
class CholmodImpl final : public SparseLinearSolver::Impl {
  // exposes the factor's `minor` (first failed column) and permutation
  struct Llt : Eigen::CholmodSupernodalLLT<SparseMatrixD, Eigen::Lower> {
    int failed_dof() const {
      if (!m_cholmodFactor || m_cholmodFactor->minor >= m_cholmodFactor->n) return -1;
      const int k = static_cast<int>(m_cholmodFactor->minor);
      const int* perm = static_cast<const int*>(m_cholmodFactor->Perm);
      return perm ? perm[k] : k;
    }
  };

 public:
  CholmodImpl() { llt_.cholmod().print = 0; }  // failures come back as statuses, not stderr lines
  LinearStatus analyze(const SparseMatrixD& a) override {
    llt_.analyzePattern(a);
    if (llt_.cholmod().status < CHOLMOD_OK)
      return fail(Code::backend_error, -1, "CHOLMOD analysis failed (status " + std::to_string(llt_.cholmod().status) + ")");
    return {};
  }
  LinearStatus factorize(const SparseMatrixD& a, bool symmetric) override {
    llt_.factorize(a);
    if (llt_.info() == Eigen::Success) return {};
    const int dof = llt_.failed_dof();
    std::ostringstream m;
    m << "matrix not positive definite (CHOLMOD LLT failed";
    if (dof >= 0) m << " at DoF " << dof;
    m << "): an indefinite tangent past a limit or bifurcation point needs an LU backend";
    return fail(Code::not_positive_definite, dof, m.str());
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override {
    x = llt_.solve(b);
    return llt_.info() == Eigen::Success;
  }
  int determinant_sign() override { return 1; }  // factorized, so positive definite

 private:
  Llt llt_;
};
#endif


#ifdef FF_HAVE_MUMPS
// One MUMPS instance of one symmetry type: SYM = 0, multifrontal LU, or SYM = 2, LDLᵀ with
// pivoting for symmetric indefinite matrices (a tangent past a limit point is indefinite), on the
// lower triangle only: about half the flops and memory of LU. With MUMPS's MPI build and the
// solvers shared over the world (solver_ranks.h), the instance spans every rank and each hands
// MUMPS entries of its own (ICNTL(18) = 3): those it holds when the matrix was assembled in parts
// (distributed.md §5), else an equal slice of the whole matrix it holds; the right-hand side is
// read on rank 0 and the solution broadcast from it.
class MumpsInstance {
 public:
  explicit MumpsInstance(int sym) {
    // MPI_COMM_SELF, or the world once shared; the sequential build's stand-in value otherwise
    id_.comm_fortran = solver_communicator_fortran();
    ranks_ = linear_solver_ranks();
    rank_ = linear_solver_rank();
    id_.par = 1;                 // the host works
    id_.sym = sym;
    id_.job = -1;
    dmumps_c(&id_);
    initialised_ = id_.infog[0] >= 0;
    icntl(1) = icntl(2) = icntl(3) = -1;  // no output streams: failures come back as statuses
    icntl(4) = 0;
    icntl(28) = 1;   // sequential analysis, so ICNTL(7) picks the ordering
    // automatic: METIS when the build has it, else SCOTCH (Debian's sequential build: SCOTCH).
    // Not PORD, although it was 9-30 % faster for LDLᵀ on the larger plates: it ends the process
    // (exit, no status) on matrices of a few unknowns (static_solvers.md §7.1). On one rank,
    // with FLEXFRAME_MUMPS_ORDERING=metis, analyze() hands MUMPS our METIS ordering instead
    icntl(7) = 7;
    icntl(24) = 1;   // null pivot detection, so a singular K is reported, not factorized
    icntl(33) = 1;   // the determinant (its sign marks limit and bifurcation points)
    icntl(8) = -1;   // the row and column scaling is ours, kept across factorizations (static_solvers.md §7.2)
    // ... handed to MUMPS with a centralized matrix only (given ours with distributed input, MUMPS
    // 5.5 freed memory twice at the end): over ranks the entries go to MUMPS scaled already and
    // the right-hand side and the solution are scaled here (distributed.md (D7))
    if (ranks_ > 1) icntl(8) = 0;
    // over ranks the right-hand side is handed in distributed form (ICNTL(20) = 10), each rank the
    // rows MUMPS's solve needs on it (JOB = 9 after each factorization; distributed.md (D8)); the
    // solution comes back on rank 0 (ICNTL(21) = 0) and is broadcast
    if (ranks_ > 1) icntl(20) = 10;
    apply_user_controls();
  }
  ~MumpsInstance() {
    // over ranks JOB = −2 is a call every rank joins: not once this rank has left the others
    if (!initialised_ || (ranks_ > 1 && shared_solvers_left())) return;
    id_.job = -2;
    dmumps_c(&id_);
  }
  MumpsInstance(const MumpsInstance&) = delete;
  MumpsInstance& operator=(const MumpsInstance&) = delete;

  bool analyzed() const { return analyzed_; }
  void forget_analysis() { analyzed_ = false; }

  int ranks() const { return ranks_; }

  // 1-based coordinates of the entries `positions` of the CSC matrix a (all, or the lower triangle;
  // over ranks an equal share of them each, or, `own_share`, the ones this rank holds)
  LinearStatus analyze(const SparseMatrixD& a, const std::vector<int>& positions, bool own_share) {
    if (!initialised_) return fail(Code::backend_error, -1, "MUMPS could not be initialised");
    const int n = static_cast<int>(a.rows());
    irn_.resize(positions.size());
    jcn_.resize(positions.size());
    values_.resize(positions.size());
    for (int j = 0, q = 0; j < n; ++j)
      for (int p = a.outerIndexPtr()[j]; p < a.outerIndexPtr()[j + 1]; ++p)
        if (q < static_cast<int>(positions.size()) && positions[q] == p) {
          irn_[q] = a.innerIndexPtr()[p] + 1;
          jcn_[q] = j + 1;
          values_[q] = a.valuePtr()[p];
          ++q;
        }
    given_order_ = ranks_ == 1 && own_ordering_wanted() ? nested_dissection_positions(a) : std::vector<int>{};
    for (int& p : given_order_) ++p;  // MUMPS counts from 1
    return analyze_entries(n, own_share);
  }
  // The analysis of a pattern alone, for its estimates (estimate_symmetric_factorization): no
  // values are handed over, so nothing of MUMPS's analysis may read them — no matching or
  // compressed ordering (ICNTL(12) = 1 for LDLᵀ, ICNTL(6) = 0) and no scaling (ICNTL(8) = 0)
  // (the entries given are this rank's own share)
  LinearStatus analyze_pattern(int n, std::vector<int> irn1, std::vector<int> jcn1) {
    if (!initialised_) return fail(Code::backend_error, -1, "MUMPS could not be initialised");
    irn_ = std::move(irn1);
    jcn_ = std::move(jcn1);
    values_.clear();
    given_order_.clear();
    icntl(6) = 0;
    icntl(8) = 0;
    icntl(12) = 1;
    return analyze_entries(n, true);
  }
  FactorizationEstimate estimates() const {
    FactorizationEstimate e;
    e.ranks = ranks_;
    e.flops = id_.rinfog[0];                 // RINFOG(1)
    const int entries = id_.infog[19];       // INFOG(20), in millions when negative
    e.factor_entries = entries >= 0 ? static_cast<double>(entries) : 1e6 * -entries;
    e.memory_mb_max_rank = id_.infog[15];    // INFOG(16)
    e.memory_mb_total = id_.infog[16];       // INFOG(17)
    e.largest_front = id_.infog[4];          // INFOG(5)
    return e;
  }

 private:
  // MUMPS's analysis (JOB = 1) of the entries irn_/jcn_ (1-based) of an n x n matrix, values_ with
  // them or empty; on one rank with given_order_ as PERM_IN when it is not empty. Over several
  // ranks each hands MUMPS an equal share of the entries, or all it holds when they are its own
  // share already (`own_share`)
  LinearStatus analyze_entries(int n, bool own_share = false) {
    double* values = values_.empty() ? nullptr : values_.data();
    id_.n = n;
    if (ranks_ == 1) {  // centralized input, as with the sequential build (same arithmetic)
      id_.nnz = static_cast<int>(irn_.size());
      id_.irn = irn_.data();
      id_.jcn = jcn_.data();
      id_.a = values;
      icntl(7) = given_order_.empty() ? 7 : 1;
      id_.perm_in = given_order_.empty() ? nullptr : given_order_.data();
    } else {
      // distributed input: this rank's share of the entries, an equal count per rank (the
      // analysis gathers their coordinates only, the factorization reads the values where they are)
      icntl(18) = 3;
      const std::size_t total = irn_.size();
      share_begin_ = own_share ? 0 : total * rank_ / ranks_;
      share_end_ = own_share ? total : total * (rank_ + 1) / ranks_;
      id_.nnz_loc = static_cast<int>(share_end_ - share_begin_);
      id_.irn_loc = irn_.data() + share_begin_;
      id_.jcn_loc = jcn_.data() + share_begin_;
      id_.a_loc = values ? values + share_begin_ : nullptr;
    }
    if (ranks_ > 1) synchronize_stop_over_ranks();  // rank 0's stop, seen by every rank here
    id_.job = 1;
    dmumps_c(&id_);
    if (id_.infog[0] < 0) return fail(Code::backend_error, -1, "MUMPS analysis failed (INFOG(1) = " + std::to_string(id_.infog[0]) + ")");
    analyzed_ = true;
    scaled_ = false;
    return {};
  }

 public:
  LinearStatus factorize(const SparseMatrixD& a, const std::vector<int>& positions) {
    for (std::size_t q = 0; q < positions.size(); ++q) values_[q] = a.valuePtr()[positions[q]];
    // §7.2: the scaling of an earlier matrix of the pattern is kept while it still balances this
    // one's rows and columns to within a factor scaling_spread; a factorization that fails on a kept
    // scaling is tried once more on a current one. Over ranks (D7) each rank looks at the entries
    // it hands MUMPS and the maxima are the largest over the ranks: every rank takes the same
    // decision and computes the same scaling, that of the whole matrix
    const bool kept = scaled_ && scaling_still_balances(id_.n, share_size(), irn_.data() + share_begin(),
                                                        jcn_.data() + share_begin(), 1, values_.data() + share_begin(),
                                                        id_.sym != 0, row_scale_, col_scale_, scaling_spread,
                                                        combine_maxima());
    if (!kept) rescale();
    LinearStatus st = factorize_scaled();
    if (!st && kept) {
      rescale();
      st = factorize_scaled();
    }
    return st;
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) {
    x = b;
    // over ranks MUMPS factorized D_r A D_c (D7): it solves for y = D_c⁻¹ x from D_r b, given as
    // this rank's rows (D8); the solution arrives in x on rank 0
    if (ranks_ > 1)
      for (int k = 0; k < id_.nloc_rhs; ++k) {
        const int i = rhs_rows_[k] - 1;
        rhs_share_[k] = b[i] * row_scale_[i];
      }
    id_.rhs = x.data();
    id_.nrhs = 1;
    id_.lrhs = static_cast<int>(x.size());
    if (ranks_ > 1) synchronize_stop_over_ranks();
    id_.job = 3;
    dmumps_c(&id_);
    // the solution is on rank 0 only: every rank takes the same Newton update
    if (ranks_ > 1) {
      broadcast_from_first_rank(x.data(), static_cast<int>(x.size()));
      for (Eigen::Index i = 0; i < x.size(); ++i) x[i] *= col_scale_[i];
    }
    return id_.infog[0] >= 0;
  }
  int determinant_sign() const {
    // det = RINFOG(12) * 2^INFOG(34)
    const double mantissa = id_.rinfog[11];
    return mantissa > 0.0 ? 1 : (mantissa < 0.0 ? -1 : 0);
  }

 private:
  // MUMPS recomputes its automatic scaling (ICNTL(8) = 77) at every factorization, about a tenth of
  // a factorization at these sizes, for magnitudes that hardly move between two Newton matrices
  static constexpr double scaling_spread = 4.0;
  void rescale() {
    equilibrate_inf_norm(id_.n, share_size(), irn_.data() + share_begin(), jcn_.data() + share_begin(), 1,
                         values_.data() + share_begin(), id_.sym != 0, row_scale_, col_scale_, 0.1, 20,
                         combine_maxima());
    if (ranks_ == 1) {  // MUMPS applies it (ICNTL(8) = -1)
      id_.rowsca = row_scale_.data();
      id_.colsca = col_scale_.data();
      id_.rowsca_from_mumps = id_.colsca_from_mumps = 0;
    }
    scaled_ = true;
  }
  // the entries this rank hands MUMPS: [share_begin(), share_begin() + share_size()) of irn_, jcn_, values_
  std::size_t share_begin() const { return ranks_ > 1 ? share_begin_ : 0; }
  std::size_t share_size() const { return ranks_ > 1 ? share_end_ - share_begin_ : values_.size(); }
  CombineMaxima combine_maxima() const {
    if (ranks_ == 1) return nullptr;
    return &largest_over_ranks;
  }
  LinearStatus factorize_scaled() {
    if (ranks_ > 1) {
      // (D7): this rank's entries of D_r A D_c, what MUMPS factorizes over ranks (ICNTL(8) = 0)
      scaled_share_.resize(share_size());
      for (std::size_t k = 0; k < scaled_share_.size(); ++k) {
        const std::size_t q = share_begin_ + k;
        scaled_share_[k] = values_[q] * row_scale_[irn_[q] - 1] * col_scale_[jcn_[q] - 1];
      }
      id_.a_loc = scaled_share_.data();
      synchronize_stop_over_ranks();
    }
    for (int attempt = 0;; ++attempt) {
      id_.job = 2;
      dmumps_c(&id_);
      // -8, -9: the workspace MUMPS estimated in the analysis was short (pivoting grew the
      // fronts): give it more and factorize again
      if ((id_.infog[0] == -8 || id_.infog[0] == -9) && attempt < 4) {
        icntl(14) = std::max(icntl(14), 20) * 2;
        continue;
      }
      break;
    }
    if (id_.infog[0] == -10 || (id_.infog[0] >= 0 && id_.infog[27] > 0)) {
      // INFOG(28) null pivots; PIVNUL_LIST is only kept with ICNTL(24): the first one is the DoF
      int dof = id_.infog[27] > 0 && id_.pivnul_list ? id_.pivnul_list[0] - 1 : -1;
      if (ranks_ > 1) broadcast_from_first_rank(&dof, 1);  // PIVNUL_LIST is on the host only
      return fail(Code::singular, dof, singular_message(dof));
    }
    if (id_.infog[0] < 0)
      return fail(Code::backend_error, -1, "MUMPS factorization failed (INFOG(1) = " + std::to_string(id_.infog[0]) + ")");
    if (ranks_ > 1) return ask_right_hand_side_rows();
    return {};
  }
  // (D8): the rows of the right-hand side this rank hands MUMPS, MUMPS's own choice for this
  // factorization's mapping of the fronts, which needs no right-hand-side message in the solve
  // (JOB = 9, ICNTL(20) = 10; INFO(23) rows at most). Every rank holds the whole right-hand side,
  // so any distribution would do: this one is the cheapest for MUMPS
  LinearStatus ask_right_hand_side_rows() {
    rhs_rows_.assign(std::max(id_.info[22], 1), 0);
    id_.irhs_loc = rhs_rows_.data();
    id_.lrhs_loc = static_cast<int>(rhs_rows_.size());  // the C interface passes IRHS_loc(1:LRHS_loc)
    id_.job = 9;
    dmumps_c(&id_);
    if (id_.infog[0] < 0)
      return fail(Code::backend_error, -1,
                  "MUMPS could not distribute the right-hand side (JOB = 9, INFOG(1) = " + std::to_string(id_.infog[0]) + ")");
    const int rows = std::max(id_.info[22], 0);
    rhs_rows_.resize(std::max(rows, 1));
    rhs_share_.assign(rhs_rows_.size(), 0.0);
    id_.nloc_rhs = rows;
    id_.lrhs_loc = std::max(rows, 1);
    id_.irhs_loc = rhs_rows_.data();
    id_.rhs_loc = rhs_share_.data();
    return {};
  }

 public:
  // MUMPS's own figures of the last factorization (INFOG/RINFOG are the same on every rank)
  LinearFigures figures() const {
    LinearFigures f;
    f.ranks = ranks_;
    f.flops = id_.rinfog[2];            // RINFOG(3): flops of the elimination, estimated in the analysis
    f.memory_mb_max_rank = id_.infog[20];  // INFOG(21): MB used by the factorization on the largest rank
    f.memory_mb_total = id_.infog[21];     // INFOG(22): MB over all ranks
    f.factor_entries = id_.infog[28] >= 0 ? static_cast<double>(id_.infog[28]) : 1e6 * -id_.infog[28];  // INFOG(29)
    return f;
  }

 private:
  int& icntl(int k) { return id_.icntl[k - 1]; }  // MUMPS documents ICNTL 1-based
  // FLEXFRAME_MUMPS_ICNTL="13=1,14=40": MUMPS controls set over ours, for tuning runs (MUMPS's
  // users' guide, section 6); a malformed entry or an index outside 1..60 is ignored with a warning
  void apply_user_controls() {
    const char* e = std::getenv("FLEXFRAME_MUMPS_ICNTL");
    if (!e) return;
    std::istringstream in(e);
    std::string item;
    while (std::getline(in, item, ',')) {
      int k = 0, v = 0;
      char eq = 0;
      std::istringstream one(item);
      if (one >> k >> eq >> v && eq == '=' && k >= 1 && k <= 60)
        icntl(k) = v;
      else
        std::fprintf(stderr, "warning: FLEXFRAME_MUMPS_ICNTL: '%s' is not index=value (1..60), ignored\n", item.c_str());
    }
  }
  int ranks_ = 1, rank_ = 0;
  DMUMPS_STRUC_C id_{};
  bool initialised_ = false, analyzed_ = false;
  std::vector<int> irn_, jcn_;
  std::vector<int> given_order_;  // PERM_IN: our METIS ordering, 1-based (empty: MUMPS orders)
  std::vector<double> values_;
  std::vector<double> row_scale_, col_scale_;
  bool scaled_ = false;  // row_scale_, col_scale_ hold a scaling of this analysis's pattern
  std::size_t share_begin_ = 0, share_end_ = 0;  // over ranks: the entries handed to MUMPS
  std::vector<double> scaled_share_;              // over ranks: their values in D_r A D_c (D7)
  std::vector<int> rhs_rows_;                     // over ranks: the right-hand side's rows handed (D8), 1-based
  std::vector<double> rhs_share_;                 // ... and their values in D_r b
};

// MUMPS with a nested-dissection ordering: on 2-D shell meshes it keeps the factor's fill at
// O(n log n), against the column orderings of UMFPACK and SparseLU (static_solvers.md §4 has the
// measurements). Each factorization looks at the values: a symmetric matrix (a static tangent
// without drilling or follower loads, static_solvers.md §7) goes to the LDLᵀ instance, any
// other to LU, so one backend serves statics and dynamics and a user never has to know which
// tangent is symmetric. Each instance analyzes the pattern once, when first needed.
class MumpsImpl final : public SparseLinearSolver::Impl {
 public:
  MumpsImpl() : lu_(0), ldlt_(2) {}

  LinearStatus analyze(const SparseMatrixD& a) override {
    lu_.forget_analysis();
    ldlt_.forget_analysis();
    if (!in_parts_) {
      all_.resize(a.nonZeros());
      for (int p = 0; p < a.nonZeros(); ++p) all_[p] = p;
    } else {
      all_ = held_;
    }
    lower_.clear();
    for (int j = 0, q = 0; j < a.outerSize(); ++j)
      for (int p = a.outerIndexPtr()[j]; p < a.outerIndexPtr()[j + 1]; ++p) {
        if (q == static_cast<int>(all_.size()) || all_[q] != p) continue;
        ++q;
        if (a.innerIndexPtr()[p] >= j) lower_.push_back(p);
      }
    // each instance analyzes at its first factorization (factorize below), so a run whose
    // matrices are all symmetric never pays an analysis of the LU instance, nor LDLᵀ's for
    // unsymmetric ones (sequential, and on the host over ranks)
    return {};
  }
  LinearStatus factorize(const SparseMatrixD& a, bool symmetric) override {
    last_ = symmetric ? &ldlt_ : &lu_;
    const std::vector<int>& positions = symmetric ? lower_ : all_;
    if (!last_->analyzed())
      if (LinearStatus s = last_->analyze(a, positions, in_parts_); !s) return s;
    return last_->factorize(a, positions);
  }
  int ranks() const override { return lu_.ranks(); }
  void hold_positions(const std::vector<int>& positions) override {
    in_parts_ = true;
    held_ = positions;
  }
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) override { return last_ && last_->solve(b, x); }
  int determinant_sign() override { return last_ ? last_->determinant_sign() : 0; }
  bool symmetric_factorization() const override { return last_ == &ldlt_; }
  LinearFigures figures() const override { return last_ ? last_->figures() : LinearFigures{}; }

 private:
  MumpsInstance lu_, ldlt_;
  MumpsInstance* last_ = nullptr;
  std::vector<int> all_, lower_;  // CSC positions: every entry (this rank's), the lower triangle of them
  std::vector<int> held_;         // the positions this rank holds, in parts (it may hold none)
  bool in_parts_ = false;
};
#endif

std::unique_ptr<SparseLinearSolver::Impl> make_impl(LinearBackend backend) {
  switch (backend) {
    case LinearBackend::sparse_lu: return std::make_unique<SparseLuImpl>();
    case LinearBackend::simplicial_ldlt: return std::make_unique<SimplicialLdltImpl>();
#ifdef FF_HAVE_SUITESPARSE
    case LinearBackend::umfpack: return std::make_unique<UmfpackImpl>();
    case LinearBackend::cholmod_llt: return std::make_unique<CholmodImpl>();
#else
    case LinearBackend::umfpack:
    case LinearBackend::cholmod_llt: return nullptr;
#endif
#ifdef FF_HAVE_MUMPS
    case LinearBackend::mumps: return std::make_unique<MumpsImpl>();
#else
    case LinearBackend::mumps: return nullptr;
#endif
  }
  return nullptr;
}

}  // namespace

LinearStatus estimate_symmetric_factorization(int n, std::vector<int> rows, std::vector<int> cols,
                                              FactorizationEstimate& out) {
  out = FactorizationEstimate{};
  if (n <= 0 || rows.size() != cols.size())
    return fail(Code::invalid_input, -1, "a pattern needs n > 0 and as many rows as columns");
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (rows[k] < cols[k] || cols[k] < 0 || rows[k] >= n)
      return fail(Code::invalid_input, -1,
                  "entry " + std::to_string(k) + " is not in the lower triangle of an " + std::to_string(n) + " x " +
                      std::to_string(n) + " matrix");
#ifdef FF_HAVE_MUMPS
  for (std::size_t k = 0; k < rows.size(); ++k) ++rows[k], ++cols[k];  // MUMPS counts from 1
  MumpsInstance mumps(2);  // general symmetric: LDLᵀ, as the solvers' symmetric tangents
  const LinearStatus st = mumps.analyze_pattern(n, std::move(rows), std::move(cols));
  if (st) out = mumps.estimates();
  return st;
#else
  return fail(Code::unavailable, -1, "MUMPS is not compiled in: no analysis estimates");
#endif
}

// ---------------------------------------------------------------------------------------------
LinearBackend default_linear_backend() {
  for (LinearBackend b : {LinearBackend::mumps, LinearBackend::umfpack})
    if (linear_backend_available(b)) return b;
  return LinearBackend::sparse_lu;
}

bool linear_backend_available(LinearBackend backend) {
  if (backend == LinearBackend::mumps) {
#ifdef FF_HAVE_MUMPS
    return true;
#else
    return false;
#endif
  }
#ifdef FF_HAVE_SUITESPARSE
  return true;
#else
  return backend == LinearBackend::sparse_lu || backend == LinearBackend::simplicial_ldlt;
#endif
}

bool linear_backend_is_symmetric(LinearBackend backend) {
  return backend == LinearBackend::cholmod_llt || backend == LinearBackend::simplicial_ldlt;
}

std::string_view to_string(LinearBackend backend) {
  switch (backend) {
    case LinearBackend::umfpack: return "umfpack";
    case LinearBackend::sparse_lu: return "sparse_lu";
    case LinearBackend::cholmod_llt: return "cholmod_llt";
    case LinearBackend::simplicial_ldlt: return "simplicial_ldlt";
    case LinearBackend::mumps: return "mumps";
  }
  return "unknown";
}

std::vector<LinearBackend> all_linear_backends() {
  return {LinearBackend::umfpack, LinearBackend::sparse_lu, LinearBackend::cholmod_llt,
          LinearBackend::simplicial_ldlt, LinearBackend::mumps};
}

std::optional<LinearBackend> parse_linear_backend(std::string_view name) {
  for (LinearBackend b : all_linear_backends())
    if (to_string(b) == name) return b;
  return std::nullopt;
}

SparseLinearSolver::SparseLinearSolver(LinearBackend backend) : backend_(backend), impl_(make_impl(backend)) {}
SparseLinearSolver::~SparseLinearSolver() = default;
SparseLinearSolver::SparseLinearSolver(SparseLinearSolver&&) noexcept = default;
SparseLinearSolver& SparseLinearSolver::operator=(SparseLinearSolver&&) noexcept = default;

bool SparseLinearSolver::same_pattern(const SparseMatrixD& k) const {
  if (!analyzed_ || k.rows() != n_ || k.cols() != n_ || !k.isCompressed()) return false;
  const auto nnz = static_cast<std::size_t>(k.nonZeros());
  return nnz == inner_.size() &&
         std::memcmp(k.outerIndexPtr(), outer_.data(), outer_.size() * sizeof(int)) == 0 &&
         std::memcmp(k.innerIndexPtr(), inner_.data(), nnz * sizeof(int)) == 0;
}

LinearStatus SparseLinearSolver::analyze(const SparseMatrixD& pattern) {
  analyzed_ = factorized_ = false;
  if (!impl_)
    return fail(Code::unavailable, -1,
                "linear backend '" + std::string(to_string(backend_)) + "' is not compiled in (umfpack and cholmod_llt need SuiteSparse, mumps needs MUMPS at configure time)");
  if (pattern.rows() != pattern.cols() || pattern.rows() == 0)
    return fail(Code::invalid_input, -1, "matrix must be square and non-empty");
  if (!pattern.isCompressed()) return fail(Code::invalid_input, -1, "matrix must be compressed (makeCompressed())");
  mirror_ = mirror_positions(pattern);
  if (LinearStatus held = check_held_positions(); !held) return held;  // before MUMPS reads the entries
  LinearStatus s = impl_->analyze(pattern);
  if (!s) return s;
  n_ = static_cast<int>(pattern.rows());
  outer_.assign(pattern.outerIndexPtr(), pattern.outerIndexPtr() + n_ + 1);
  inner_.assign(pattern.innerIndexPtr(), pattern.innerIndexPtr() + pattern.nonZeros());
  analyzed_ = true;
  ++analyses_;
  return s;
}

int SparseLinearSolver::ranks() const { return impl_ ? impl_->ranks() : 1; }

LinearStatus SparseLinearSolver::hold_positions_over_ranks(std::vector<int> positions) {
  if (ranks() == 1)
    return fail(Code::invalid_input, -1, "a matrix held in parts needs a solver shared over ranks (solver_ranks.h)");
  held_ = std::move(positions);
  in_parts_ = true;
  impl_->hold_positions(held_);
  analyzed_ = factorized_ = false;  // the next factorize() analyzes the held entries
  return {};
}

// what hold_positions_over_ranks asks of the list, against the analyzed pattern: every check that
// reads a value and its mirror (symmetry, the symmetric part) must find both on this rank. The
// verdict is every rank's (a rank that stopped here alone would leave the others in a shared call)
LinearStatus SparseLinearSolver::check_held_positions() const {
  if (!in_parts_) return {};
  int fault = 0;  // 1: not ascending positions of the pattern, 2: a mirror not held
  std::vector<char> held(mirror_.size(), 0);
  for (std::size_t q = 0; q < held_.size() && !fault; ++q) {
    const int p = held_[q];
    if (p < 0 || p >= static_cast<int>(mirror_.size()) || (q > 0 && p <= held_[q - 1])) fault = 1;
    else held[p] = 1;
  }
  for (std::size_t q = 0; q < held_.size() && !fault; ++q)
    if (mirror_[held_[q]] < 0 || !held[mirror_[held_[q]]]) fault = 2;
  fault = -smallest_over_ranks(-fault);  // the worst over the ranks
  if (fault == 1) return fail(Code::invalid_input, -1, "held positions must be ascending positions of the pattern's values");
  if (fault == 2)
    return fail(Code::invalid_input, -1,
                "a matrix held in parts over ranks needs each held entry's mirror held too, in a structurally "
                "symmetric pattern");
  return {};
}

int SparseLinearSolver::first_non_finite_column(const SparseMatrixD& k) const {
  int first = std::numeric_limits<int>::max();
  const double* v = k.valuePtr();
  if (!in_parts_) {
    for (int j = 0; j < k.outerSize() && first > j; ++j)
      for (int p = k.outerIndexPtr()[j]; p < k.outerIndexPtr()[j + 1]; ++p)
        if (!std::isfinite(v[p])) {
          first = j;
          break;
        }
  } else {
    for (int j = 0, q = 0; q < static_cast<int>(held_.size()); ++q) {
      while (outer_[j + 1] <= held_[q]) ++j;
      if (!std::isfinite(v[held_[q]])) {
        first = j;
        break;
      }
    }
    first = smallest_over_ranks(first);  // every rank the same verdict
  }
  return first == std::numeric_limits<int>::max() ? -1 : first;
}

LinearStatus SparseLinearSolver::factorize(const SparseMatrixD& k) { return factorize_values(k, false); }

LinearStatus SparseLinearSolver::factorize_symmetric_part(SparseMatrixD& k) {
  if (k.rows() != k.cols() || !k.isCompressed()) return factorize(k);  // which says what is wrong
  const bool analyzed_pattern = same_pattern(k);
  const std::vector<int> fresh = analyzed_pattern ? std::vector<int>{} : mirror_positions(k);  // a new pattern's
  const std::vector<int>& mirror = analyzed_pattern ? mirror_ : fresh;
  if (in_parts_) {  // only this rank's entries, whose mirrors it holds (check_held_positions)
    if (!analyzed_pattern)
      if (LinearStatus s = analyze(k); !s) return s;
    double* v = k.valuePtr();
    for (const int p : held_) {
      const int m = mirror_[p];
      if (m < p) continue;
      const double mean = 0.5 * (v[p] + v[m]);
      v[p] = v[m] = mean;
    }
  } else if (std::find(mirror.begin(), mirror.end(), -1) != mirror.end()) {
    const SparseMatrixD transposed = k.transpose();
    k = 0.5 * (k + transposed);
    k.makeCompressed();
  } else {
    double* v = k.valuePtr();
    for (std::size_t p = 0; p < mirror.size(); ++p) {
      const auto m = static_cast<std::size_t>(mirror[p]);
      if (m < p) continue;  // the pair was averaged from its first entry
      const double mean = 0.5 * (v[p] + v[m]);  // as 0.5 (K + Kᵀ) forms it
      v[p] = v[m] = mean;
    }
  }
  return factorize_values(k, true);
}

LinearStatus SparseLinearSolver::factorize_values(const SparseMatrixD& k, bool known_symmetric) {
  factorized_ = false;
  if (!same_pattern(k)) {
    LinearStatus s = analyze(k);
    if (!s) return s;
  }
  if (const int j = first_non_finite_column(k); j >= 0)
    return fail(Code::non_finite_matrix, j, "matrix has a NaN/Inf entry in column (DoF) " + std::to_string(j));
  if (linear_backend_is_symmetric(backend_) && !known_symmetric)
    if (const int j = first_asymmetric_column(k, 1e-10); j >= 0)
      return fail(Code::not_symmetric, j,
                  "matrix is not symmetric (column " + std::to_string(j) + "); backend '" +
                      std::string(to_string(backend_)) + "' reads one triangle only: use umfpack or sparse_lu");
  // MUMPS picks LDLᵀ for a symmetric K (static_solvers.md §7.1); the others do not ask
  const bool symmetric =
      backend_ == LinearBackend::mumps && (known_symmetric || first_asymmetric_column(k, 1e-12, true) < 0);
  LinearStatus s = impl_->factorize(k, symmetric);
  if (!s) return s;
  factorized_ = true;
  ++factorizations_;
  return s;
}

int SparseLinearSolver::first_asymmetric_column(const SparseMatrixD& k, double relative_bound, bool any) const {
  const double* v = k.valuePtr();
  double largest = 0.0;
  if (!in_parts_) {
    for (int p = 0; p < k.nonZeros(); ++p) largest = std::max(largest, std::abs(v[p]));
  } else {
    for (const int p : held_) largest = std::max(largest, std::abs(v[p]));
    largest = largest_over_ranks(largest);
  }
  const double bound = relative_bound * std::max(1e-300, largest);
  int first = std::numeric_limits<int>::max();  // the first column of K − Kᵀ with an entry above the bound
  auto differs = [&](int j, int p) {
    const double mirrored = mirror_[p] >= 0 ? v[mirror_[p]] : 0.0;  // absent: a structural zero
    if (std::abs(v[p] - mirrored) <= bound) return false;
    first = std::min(first, std::min(j, inner_[p]));
    return any;  // enough to tell that K ≠ Kᵀ
  };
  if (!in_parts_) {
    for (int j = 0; j < n_; ++j)
      for (int p = outer_[j]; p < outer_[j + 1]; ++p)
        if (differs(j, p)) return first;
  } else {
    for (int j = 0, q = 0; q < static_cast<int>(held_.size()); ++q) {
      while (outer_[j + 1] <= held_[q]) ++j;
      if (differs(j, held_[q])) break;
    }
    first = smallest_over_ranks(first);  // every rank the same verdict (LDLᵀ or LU)
  }
  return first == std::numeric_limits<int>::max() ? -1 : first;
}

LinearFigures SparseLinearSolver::factorization_figures() const {
  return factorized_ ? impl_->figures() : LinearFigures{};
}

int SparseLinearSolver::determinant_sign() const { return factorized_ ? impl_->determinant_sign() : 0; }

bool SparseLinearSolver::symmetric_factorization() const {
  return factorized_ && (linear_backend_is_symmetric(backend_) || impl_->symmetric_factorization());
}

LinearStatus SparseLinearSolver::solve(const Eigen::VectorXd& b, Eigen::VectorXd& x) const {
  if (!factorized_) return fail(Code::invalid_input, -1, "solve() without a successful factorize()");
  if (b.size() != n_) return fail(Code::invalid_input, -1, "right-hand side has the wrong size");
  if (!impl_->solve(b, x)) return fail(Code::backend_error, -1, "the backend's solve failed");
  for (int i = 0; i < x.size(); ++i)
    if (!std::isfinite(x[i]))
      return fail(Code::non_finite_solution, i,
                  "non-finite solution at DoF " + std::to_string(i) + " (numerically singular matrix)");
  return {};
}

}  // namespace ff
