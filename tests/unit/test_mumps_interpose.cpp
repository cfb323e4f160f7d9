// MUMPS's per-call save/restore statistics are skipped in the flexframe executable
// (app/mumps_interpose.cpp, linked into this test the same way). The skip must take effect on
// every MUMPS call and must leave the factorization and the solution exactly as they were: the
// MUMPS solution of a non-symmetric convection-diffusion system is checked against Eigen's
// SparseLU and against the system itself.
#include <gtest/gtest.h>

#include <Eigen/SparseLU>
#include <vector>

#include "core/solve/sparse_solver.h"

extern "C" long long flexframe_mumps_statistics_skipped();

namespace {

// 5-point Laplacian on an m x m grid with a one-sided convection term: non-symmetric, non-singular
ff::SparseMatrixD convection_diffusion(int m) {
  std::vector<Eigen::Triplet<double>> t;
  auto id = [m](int i, int j) { return i * m + j; };
  for (int i = 0; i < m; ++i)
    for (int j = 0; j < m; ++j) {
      t.emplace_back(id(i, j), id(i, j), 4.5);
      if (i > 0) t.emplace_back(id(i, j), id(i - 1, j), -1.5);
      if (i + 1 < m) t.emplace_back(id(i, j), id(i + 1, j), -0.5);
      if (j > 0) t.emplace_back(id(i, j), id(i, j - 1), -1.0);
      if (j + 1 < m) t.emplace_back(id(i, j), id(i, j + 1), -1.0);
    }
  ff::SparseMatrixD a(m * m, m * m);
  a.setFromTriplets(t.begin(), t.end());
  a.makeCompressed();
  return a;
}

TEST(MumpsInterpose, SkipsTheStatisticsOfEveryCallAndSolvesAsBefore) {
  if (!ff::linear_backend_available(ff::LinearBackend::mumps)) GTEST_SKIP() << "MUMPS is not compiled in";
  if (flexframe_mumps_statistics_skipped() < 0)
    GTEST_SKIP() << "statistics computed (FLEXFRAME_MUMPS_STATISTICS=on, or a MUMPS other than 5.5)";
  const ff::SparseMatrixD a = convection_diffusion(30);
  Eigen::VectorXd b(a.rows());
  for (int i = 0; i < b.size(); ++i) b[i] = 1.0 + 0.01 * (i % 17);

  const long long before = flexframe_mumps_statistics_skipped();
  ff::SparseLinearSolver mumps(ff::LinearBackend::mumps);
  ASSERT_TRUE(mumps.analyze(a));
  ASSERT_TRUE(mumps.factorize(a));
  Eigen::VectorXd x;
  ASSERT_TRUE(mumps.solve(b, x));
  ASSERT_TRUE(mumps.solve(2.0 * b, x));
  // analysis, factorization and two solves: MUMPS ends each call with the statistics
  EXPECT_GE(flexframe_mumps_statistics_skipped() - before, 4);

  Eigen::SparseLU<ff::SparseMatrixD> reference(a);
  ASSERT_EQ(reference.info(), Eigen::Success);
  const Eigen::VectorXd expected = reference.solve(2.0 * b);
  EXPECT_LT((x - expected).norm(), 1e-12 * expected.norm());
  EXPECT_LT((a * x - 2.0 * b).norm(), 1e-12 * b.norm());
}

}  // namespace
