#include "core/solve/blas_single_rhs.h"

#include <Eigen/Core>
#include <atomic>
#include <cstdlib>
#include <string>

extern "C" {
void dgemv_(const char* trans, const int* m, const int* n, const double* alpha, const double* a, const int* lda,
            const double* x, const int* incx, const double* beta, double* y, const int* incy);
void dtrsv_(const char* uplo, const char* trans, const char* diag, const int* n, const double* a, const int* lda,
            double* x, const int* incx);
void dscal_(const int* n, const double* alpha, double* x, const int* incx);
}

namespace ff::blas {
namespace {
std::atomic<long long> calls{0};
// FLEXFRAME_BLAS_ROUTING=off leaves every call to the BLAS (for before/after measurements)
const bool routing_on = [] {
  const char* e = std::getenv("FLEXFRAME_BLAS_ROUTING");
  return !(e && std::string(e) == "off");
}();
bool plain(char t) { return t == 'N' || t == 'n'; }

// op(A) x = b in place for the m × m triangle of A (column major, leading dimension lda), by
// Eigen's triangular solver: a front's pivot block is small, where OpenBLAS's dtrsv goes through a
// dot-product call per row; 3-5 % of a solve of the main job's matrix (docs/performance.md)
void triangular_solve(char uplo, bool transposed, bool unit, int m, const double* A, int lda, double* x) {
  using Stride = Eigen::OuterStride<>;
  const Eigen::Map<const Eigen::MatrixXd, 0, Stride> a(A, m, m, Stride(lda));
  Eigen::Map<Eigen::VectorXd> v(x, m);
  const bool lower = uplo == 'L' || uplo == 'l';
  // the transposed cases solve with the stored triangle read the other way: Lᵀ is upper, Uᵀ lower
  const bool upper_op = lower == transposed;
  if (!transposed) {
    if (upper_op && unit) a.triangularView<Eigen::UnitUpper>().solveInPlace(v);
    else if (upper_op) a.triangularView<Eigen::Upper>().solveInPlace(v);
    else if (unit) a.triangularView<Eigen::UnitLower>().solveInPlace(v);
    else a.triangularView<Eigen::Lower>().solveInPlace(v);
  } else {
    if (upper_op && unit) a.transpose().triangularView<Eigen::UnitUpper>().solveInPlace(v);
    else if (upper_op) a.transpose().triangularView<Eigen::Upper>().solveInPlace(v);
    else if (unit) a.transpose().triangularView<Eigen::UnitLower>().solveInPlace(v);
    else a.transpose().triangularView<Eigen::Lower>().solveInPlace(v);
  }
}
}  // namespace

bool gemm_one_column(char transa, char transb, int m, int n, int k, double alpha, const double* A, int lda,
                     const double* B, int ldb, double beta, double* C, int ldc) {
  (void)ldc;  // one column: its leading dimension is never stepped over
  if (!routing_on || n != 1 || m <= 0 || k <= 0) return false;
  const int one = 1;
  const int incb = plain(transb) ? 1 : ldb;  // op(B)(:, 0): B's first column, or its first row
  // op(A) is m × k: A itself (m × k) with 'N', otherwise the transpose of the stored k × m matrix
  if (plain(transa)) dgemv_("N", &m, &k, &alpha, A, &lda, B, &incb, &beta, C, &one);
  else dgemv_("T", &k, &m, &alpha, A, &lda, B, &incb, &beta, C, &one);
  calls.fetch_add(1, std::memory_order_relaxed);
  return true;
}

bool trsm_one_column(char side, char uplo, char transa, char diag, int m, int n, double alpha, const double* A,
                     int lda, double* B, int ldb) {
  if (!routing_on) return false;
  const char s = side == 'l' ? 'L' : side == 'r' ? 'R' : side;
  if (s == 'L' && n == 1 && m > 0) {  // op(A) x = α b, b a column
    const int one = 1;
    if (alpha != 1.0) dscal_(&m, &alpha, B, &one);
    triangular_solve(uplo, !plain(transa), diag == 'U' || diag == 'u', m, A, lda, B);
  } else if (s == 'R' && m == 1 && n > 0) {  // x op(A) = α b, b a row: op(A)ᵀ xᵀ = α bᵀ
    if (alpha != 1.0) dscal_(&n, &alpha, B, &ldb);
    const char t = plain(transa) ? 'T' : 'N';
    dtrsv_(&uplo, &t, &diag, &n, A, &lda, B, &ldb);
  } else {
    return false;
  }
  calls.fetch_add(1, std::memory_order_relaxed);
  return true;
}

long long one_column_calls() { return calls.load(std::memory_order_relaxed); }

}  // namespace ff::blas
