// The one-column routing of dgemm/dtrsm (core/solve/blas_single_rhs.h) against plain loops written
// from the BLAS definitions: every transpose, side, triangle and diagonal, α ≠ 1, β ≠ 0 and
// leading dimensions larger than the matrices.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "core/solve/blas_single_rhs.h"

namespace {

// column-major element (i, j) of a matrix with leading dimension ld
double& at(std::vector<double>& a, int ld, int i, int j) { return a[static_cast<std::size_t>(j) * ld + i]; }
double at(const std::vector<double>& a, int ld, int i, int j) { return a[static_cast<std::size_t>(j) * ld + i]; }

std::vector<double> random_values(std::size_t n, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  std::vector<double> v(n);
  for (double& x : v) x = u(gen);
  return v;
}

TEST(BlasOneColumn, GemmMatchesTheDefinitionForEveryTranspose) {
  const int m = 37, k = 23, lda = 41, ldb = 29, ldc = 40;
  for (char ta : {'N', 'T', 'n', 't'})
    for (char tb : {'N', 'T'}) {
      const std::vector<double> A = random_values(static_cast<std::size_t>(lda) * 41, 1);
      const std::vector<double> B = random_values(static_cast<std::size_t>(ldb) * 29, 2);
      std::vector<double> C = random_values(static_cast<std::size_t>(ldc), 3), ref = C;
      const double alpha = -1.7, beta = 0.6;
      const bool tA = ta == 'T' || ta == 't', tB = tb == 'T';
      for (int i = 0; i < m; ++i) {
        double s = 0.0;
        for (int p = 0; p < k; ++p) s += (tA ? at(A, lda, p, i) : at(A, lda, i, p)) * (tB ? at(B, ldb, 0, p) : at(B, ldb, p, 0));
        ref[i] = alpha * s + beta * ref[i];
      }
      ASSERT_TRUE(ff::blas::gemm_one_column(ta, tb, m, 1, k, alpha, A.data(), lda, B.data(), ldb, beta, C.data(), ldc));
      for (int i = 0; i < m; ++i) EXPECT_NEAR(C[i], ref[i], 1e-13) << ta << tb << " row " << i;
      for (int i = m; i < ldc; ++i) EXPECT_EQ(C[i], ref[i]) << "beyond m";
    }
}

TEST(BlasOneColumn, GemmWithBetaZeroIgnoresWhatCHeld) {
  const int m = 5, k = 4;
  const std::vector<double> A = random_values(20, 4), B = random_values(4, 5);
  std::vector<double> C(5, std::numeric_limits<double>::quiet_NaN());
  ASSERT_TRUE(ff::blas::gemm_one_column('N', 'N', m, 1, k, 1.0, A.data(), m, B.data(), k, 0.0, C.data(), m));
  for (double c : C) EXPECT_TRUE(std::isfinite(c));
}

TEST(BlasOneColumn, TrsmMatchesSubstitutionForEverySideTriangleAndDiagonal) {
  const int n = 19, lda = 23, ldb = 7;
  for (char side : {'L', 'R'})
    for (char uplo : {'U', 'L'})
      for (char ta : {'N', 'T'})
        for (char diag : {'N', 'U'}) {
          std::vector<double> A = random_values(static_cast<std::size_t>(lda) * n, 6);
          for (int i = 0; i < n; ++i) at(A, lda, i, i) = 3.0 + i % 3;  // well conditioned
          // the full op(A) as the routine sees it: the chosen triangle, unit diagonal if asked
          std::vector<double> T(static_cast<std::size_t>(n) * n, 0.0);
          for (int i = 0; i < n; ++i)
            for (int j = 0; j < n; ++j) {
              const bool in = uplo == 'U' ? j >= i : j <= i;
              double a = in ? at(A, lda, i, j) : 0.0;
              if (i == j && diag == 'U') a = 1.0;
              at(T, n, ta == 'N' ? i : j, ta == 'N' ? j : i) = a;
            }
          const double alpha = 1.3;
          // B holds one column (side L, stride 1) or one row (side R, stride ldb)
          const int stride = side == 'L' ? 1 : ldb;
          std::vector<double> B = random_values(static_cast<std::size_t>(n) * stride, 7), b0 = B;
          const int m = side == 'L' ? n : 1, cols = side == 'L' ? 1 : n;
          ASSERT_TRUE(ff::blas::trsm_one_column(side, uplo, ta, diag, m, cols, alpha, A.data(), lda, B.data(), side == 'L' ? n : ldb));
          // check the defining equation: op(A) x = α b (L) or x op(A) = α b (R)
          for (int i = 0; i < n; ++i) {
            double s = 0.0;
            for (int j = 0; j < n; ++j)
              s += side == 'L' ? at(T, n, i, j) * B[j * stride] : B[j * stride] * at(T, n, j, i);
            EXPECT_NEAR(s, alpha * b0[i * stride], 1e-12) << side << uplo << ta << diag << " entry " << i;
          }
          for (std::size_t i = 0; i < B.size(); ++i)
            if (i % stride != 0) EXPECT_EQ(B[i], b0[i]) << "an entry between the row's strides moved";
        }
}

TEST(BlasOneColumn, ManyColumnsAreLeftToTheBlas) {
  std::vector<double> A(16, 1.0), B(16, 1.0), C(16, 0.0), C0 = C;
  EXPECT_FALSE(ff::blas::gemm_one_column('N', 'N', 4, 2, 4, 1.0, A.data(), 4, B.data(), 4, 0.0, C.data(), 4));
  EXPECT_FALSE(ff::blas::trsm_one_column('L', 'U', 'N', 'N', 4, 3, 1.0, A.data(), 4, B.data(), 4));
  EXPECT_FALSE(ff::blas::trsm_one_column('R', 'U', 'N', 'N', 2, 4, 1.0, A.data(), 4, B.data(), 4));
  EXPECT_EQ(C, C0);
}

}  // namespace
