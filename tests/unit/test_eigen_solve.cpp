// lowest_vibration_modes on matrices whose spectrum is known exactly: repeated eigenvalues come
// back with their multiplicity (a diagonal K with a six-fold zero, two uncoupled copies of one
// chain), distinct ones in order. On these small matrices Spectra's restarts find every copy by
// themselves (recovered = 0); the deflated check of eigen_solve.cpp (recover_missed_modes) is what
// finds the sixth rigid-body mode of the free 2 x 1 plate in ShellEigen.HingedPlatesHaveSevenZero-
// Frequencies (tests/verification/test_shell_eigen.cpp), which one Lanczos run misses with the METIS
// elimination order (that test failed before the check was added).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "core/solve/eigen_solve.h"

namespace ff {
namespace {

SparseMatrixD diagonal(const std::vector<double>& d) {
  SparseMatrixD a(static_cast<Eigen::Index>(d.size()), static_cast<Eigen::Index>(d.size()));
  for (std::size_t i = 0; i < d.size(); ++i) a.insert(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(i)) = d[i];
  a.makeCompressed();
  return a;
}

TEST(EigenSolve, RepeatedZeroEigenvalueIsFoundWithItsMultiplicity) {
  std::vector<double> k(60, 0.0);
  for (int i = 6; i < 60; ++i) k[i] = static_cast<double>(i - 5);  // 0 (six times), 1, 2, 3, ...
  const SparseMatrixD K = diagonal(k), M = diagonal(std::vector<double>(60, 1.0));
  EigenSolveSettings s;
  s.count = 8;
  const EigenSolveResult r = lowest_vibration_modes(K, M, -1e-3, s);
  ASSERT_TRUE(r.ok()) << r.error;
  ASSERT_EQ(r.values.size(), 8u);
  for (int i = 0; i < 6; ++i) { EXPECT_NEAR(r.values[i], 0.0, 1e-9) << i; }
  EXPECT_NEAR(r.values[6], 1.0, 1e-9);
  EXPECT_NEAR(r.values[7], 2.0, 1e-9);
  // the six zero modes span the zero eigenspace: M-orthonormal, within the first six unknowns
  const Eigen::MatrixXd zero = r.vectors.leftCols(6);
  EXPECT_LT((zero.transpose() * zero - Eigen::MatrixXd::Identity(6, 6)).norm(), 1e-8);
  EXPECT_LT(zero.bottomRows(54).norm(), 1e-8);
}

// Two uncoupled copies of one tridiagonal structure: every eigenvalue twice. The operator never
// couples the copies, so every Krylov vector holds the same ratio of them per eigenvalue, and one
// Lanczos run finds each value once.
TEST(EigenSolve, TwoUncoupledCopiesHaveEveryFrequencyTwice) {
  const int m = 40;
  std::vector<Eigen::Triplet<double>> t;
  for (int copy = 0; copy < 2; ++copy)
    for (int i = 0; i < m; ++i) {
      const int r = copy * m + i;
      t.emplace_back(r, r, 2.0);
      if (i + 1 < m) t.emplace_back(r, r + 1, -1.0), t.emplace_back(r + 1, r, -1.0);
    }
  SparseMatrixD K(2 * m, 2 * m);
  K.setFromTriplets(t.begin(), t.end());
  K.makeCompressed();
  const SparseMatrixD M = diagonal(std::vector<double>(2 * m, 1.0));
  EigenSolveSettings s;
  s.count = 6;
  const EigenSolveResult r = lowest_vibration_modes(K, M, -1e-3, s);
  ASSERT_TRUE(r.ok()) << r.error;
  // the chain's eigenvalues 2 - 2 cos(k pi / (m + 1)), k = 1, 2, 3, each twice
  for (int k = 1; k <= 3; ++k) {
    const double exact = 2.0 - 2.0 * std::cos(k * std::acos(-1.0) / (m + 1));
    EXPECT_NEAR(r.values[2 * (k - 1)], exact, 1e-9 * exact) << k;
    EXPECT_NEAR(r.values[2 * (k - 1) + 1], exact, 1e-9 * exact) << k;
  }
  std::printf("recovered by the deflated check: %d\n", r.recovered);
}

TEST(EigenSolve, DistinctSpectrumNeedsNoRecovery) {
  std::vector<double> k(40);
  for (int i = 0; i < 40; ++i) k[i] = 1.0 + i;
  const SparseMatrixD K = diagonal(k), M = diagonal(std::vector<double>(40, 2.0));
  EigenSolveSettings s;
  s.count = 5;
  const EigenSolveResult r = lowest_vibration_modes(K, M, 0.0, s);
  ASSERT_TRUE(r.ok()) << r.error;
  for (int i = 0; i < 5; ++i) { EXPECT_NEAR(r.values[i], (1.0 + i) / 2.0, 1e-9) << i; }
  EXPECT_EQ(r.recovered, 0);
}

}  // namespace
}  // namespace ff
