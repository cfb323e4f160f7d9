// SparseLinearSolver: every backend solves a shell-pattern system to tolerance, reuses its symbolic
// analysis while the pattern is unchanged, and reports (never crashes on) singular, non-finite,
// non-symmetric and indefinite input.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <climits>
#include <cstdlib>
#include <barrier>
#include <random>
#include <thread>

#include "core/solve/equilibrate.h"
#include "tests/support/sparse_grid.h"
#include "core/solve/sparse_solver.h"

namespace ff {
namespace {

using Code = LinearStatus::Code;

std::vector<LinearBackend> available_backends() {
  std::vector<LinearBackend> out;
  for (LinearBackend b : all_linear_backends())
    if (linear_backend_available(b)) out.push_back(b);
  return out;
}

SparseMatrixD from_dense(const Eigen::MatrixXd& d) {
  SparseMatrixD s = d.sparseView(0.0, 0.0);
  s.makeCompressed();
  return s;
}

TEST(SparseGrid, ShellPatternHasSixDofsPerNodeAndNineNodeStencil) {
  const int n = 4;
  const SparseMatrixD k = shell_grid_matrix(n);
  const int side = n + 1;
  EXPECT_EQ(k.rows(), 6 * side * side);
  // interior nodes couple with 9 nodes, edge nodes with 6, corners with 4
  const long nodes9 = (side - 2) * (side - 2), nodes6 = 4 * (side - 2), nodes4 = 4;
  EXPECT_EQ(k.nonZeros(), 36 * (9 * nodes9 + 6 * nodes6 + 4 * nodes4));
  const Eigen::MatrixXd d = Eigen::MatrixXd(k);
  // structurally symmetric, numerically slightly non-symmetric, row-diagonally dominant
  EXPECT_GT((d - d.transpose()).norm(), 1e-3 * d.norm());
  EXPECT_LT((d - d.transpose()).norm(), 0.2 * d.norm());
  for (int i = 0; i < d.rows(); ++i) { EXPECT_GT(2.0 * std::abs(d(i, i)), d.row(i).cwiseAbs().sum()) << i; }
  const Eigen::MatrixXd s = Eigen::MatrixXd(shell_grid_matrix(n, 0.0));
  EXPECT_EQ((s - s.transpose()).norm(), 0.0);
}

TEST(SparseSolver, NamesRoundTrip) {
  for (LinearBackend b : all_linear_backends()) { EXPECT_EQ(parse_linear_backend(to_string(b)), b); }
  EXPECT_FALSE(parse_linear_backend("superlu").has_value());
  EXPECT_TRUE(linear_backend_available(default_linear_backend()));
}

class EachBackend : public ::testing::TestWithParam<LinearBackend> {};

// scripts/setup links a sequential MUMPS built from source (scripts/build_mumps); a link that
// lost its run path would load Debian's 5.5.1 through its development link instead, a library of
// another version than the headers the solver was compiled with
TEST(SparseSolver, MumpsRunsFromTheLibraryTheBuildWasConfiguredWith) {
  if (!linear_backend_available(LinearBackend::mumps)) GTEST_SKIP() << "no MUMPS in this build";
  const std::string loaded = mumps_library_file();
  ASSERT_FALSE(loaded.empty());
  const std::string folder = mumps_configured_folder();
  if (folder.empty()) return;  // Debian's binary, wherever the loader finds it
  char resolved[PATH_MAX];
  ASSERT_NE(realpath(folder.c_str(), resolved), nullptr) << folder;
  EXPECT_EQ(loaded.rfind(std::string(resolved) + "/", 0), 0u) << "MUMPS loaded from " << loaded;
}

TEST_P(EachBackend, LargeShellSystemSolvesToTolerance) {
  const LinearBackend backend = GetParam();
  // 30×30 quads: 5766 unknowns, ~3e5 non-zeros
  const SparseMatrixD k = shell_grid_matrix(30, linear_backend_is_symmetric(backend) ? 0.0 : 0.05, 7);
  const Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0).array().sin();
  const Eigen::VectorXd b = k * x_true;
  SparseLinearSolver solver(backend);
  ASSERT_TRUE(solver.analyze(k)) << to_string(backend);
  const LinearStatus f = solver.factorize(k);
  ASSERT_TRUE(f) << f.message;
  Eigen::VectorXd x;
  ASSERT_TRUE(solver.solve(b, x));
  // the matrix is diagonally dominant (condition number ~10): 1e-12 leaves room for round-off only
  EXPECT_LT((k * x - b).norm() / b.norm(), 1e-13);
  EXPECT_LT((x - x_true).norm() / x_true.norm(), 1e-12);
}

TEST_P(EachBackend, SymbolicAnalysisReusedWhilePatternUnchanged) {
  const LinearBackend backend = GetParam();
  const double asym = linear_backend_is_symmetric(backend) ? 0.0 : 0.05;
  SparseMatrixD k = shell_grid_matrix(6, asym, 1);
  SparseLinearSolver solver(backend);
  ASSERT_TRUE(solver.factorize(k));
  ASSERT_TRUE(solver.factorize(shell_grid_matrix(6, asym, 2)));  // new values, same pattern
  EXPECT_EQ(solver.analyses(), 1);
  EXPECT_EQ(solver.factorizations(), 2);
  // the second factorization is the one solved with
  const SparseMatrixD k2 = shell_grid_matrix(6, asym, 2);
  const Eigen::VectorXd b = Eigen::VectorXd::Ones(k2.rows());
  Eigen::VectorXd x;
  ASSERT_TRUE(solver.solve(b, x));
  EXPECT_LT((k2 * x - b).norm(), 1e-12 * b.norm());
  // a different pattern is analyzed again, automatically
  ASSERT_TRUE(solver.factorize(shell_grid_matrix(5, asym, 1)));
  EXPECT_EQ(solver.analyses(), 2);
}

TEST_P(EachBackend, ZeroColumnIsReportedWithItsDof) {
  const LinearBackend backend = GetParam();
  SparseMatrixD k = shell_grid_matrix(8, linear_backend_is_symmetric(backend) ? 0.0 : 0.05);
  const int dead = 101;  // a DoF without stiffness (e.g. an unsupported drilling rotation)
  for (int j = 0; j < k.outerSize(); ++j)
    for (SparseMatrixD::InnerIterator it(k, j); it; ++it)
      if (it.row() == dead || it.col() == dead) it.valueRef() = 0.0;
  SparseLinearSolver solver(backend);
  const LinearStatus s = solver.factorize(k);
  ASSERT_FALSE(s.ok());
  EXPECT_EQ(s.code, linear_backend_is_symmetric(backend) && backend == LinearBackend::cholmod_llt
                        ? Code::not_positive_definite
                        : Code::singular)
      << s.message;
  EXPECT_EQ(s.dof, dead) << s.message;
  EXPECT_FALSE(s.message.empty());
  Eigen::VectorXd x;
  EXPECT_EQ(solver.solve(Eigen::VectorXd::Ones(k.rows()), x).code, Code::invalid_input);
}

TEST_P(EachBackend, NonFiniteEntryIsReportedBeforeFactorizing) {
  SparseMatrixD k = shell_grid_matrix(4, linear_backend_is_symmetric(GetParam()) ? 0.0 : 0.05);
  k.coeffRef(40, 33) = std::numeric_limits<double>::quiet_NaN();
  SparseLinearSolver solver(GetParam());
  const LinearStatus s = solver.factorize(k);
  EXPECT_EQ(s.code, Code::non_finite_matrix);
  EXPECT_EQ(s.dof, 33);
}

INSTANTIATE_TEST_SUITE_P(Backends, EachBackend, ::testing::ValuesIn(available_backends()),
                         [](const auto& info) { return std::string(to_string(info.param)); });

TEST(SparseSolver, DeterminantSignMatchesDenseLu) {
  // random sparse matrices with pivoting: the sign flags limit points in load control
  std::mt19937 gen(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int negatives = 0;
  for (int trial = 0; trial < 40; ++trial) {
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(25, 25);
    for (int i = 0; i < 25; ++i) {
      d(i, i) = u(gen);
      for (int j = 0; j < 25; ++j)
        if (u(gen) > 0.7) d(i, j) = u(gen);
    }
    const Eigen::MatrixXd sym = d + d.transpose();
    for (LinearBackend b : available_backends()) {
      if (b == LinearBackend::cholmod_llt) continue;  // definite only: +1 whenever it succeeds
      const Eigen::MatrixXd& m = linear_backend_is_symmetric(b) ? sym : d;
      const double det = m.partialPivLu().determinant();
      SparseLinearSolver solver(b);
      ASSERT_TRUE(solver.factorize(from_dense(m))) << to_string(b);
      EXPECT_EQ(solver.determinant_sign(), det > 0 ? 1 : -1) << to_string(b) << " trial " << trial;
      negatives += det < 0;
    }
  }
  EXPECT_GT(negatives, 10);  // both signs were exercised
}

TEST(SparseSolver, ExactlyDependentRowsAreSingularForLu) {
  // rows 0 and 1 are proportional in exact arithmetic (powers of two): the pivot is exactly zero
  Eigen::MatrixXd d(3, 3);
  d << 2, 1, 0, 4, 2, 0, 0, 0, 1;
  for (LinearBackend b : {LinearBackend::sparse_lu, LinearBackend::umfpack}) {
    if (!linear_backend_available(b)) continue;
    SparseLinearSolver solver(b);
    const LinearStatus s = solver.factorize(from_dense(d));
    EXPECT_EQ(s.code, Code::singular) << to_string(b) << ": " << s.message;
    EXPECT_TRUE(s.dof == 0 || s.dof == 1) << to_string(b) << " dof " << s.dof;
  }
}

TEST(SparseSolver, SymmetricBackendsRefuseNonSymmetricMatrices) {
  const SparseMatrixD k = shell_grid_matrix(3, 0.05);
  for (LinearBackend b : {LinearBackend::cholmod_llt, LinearBackend::simplicial_ldlt}) {
    if (!linear_backend_available(b)) continue;
    SparseLinearSolver solver(b);
    EXPECT_EQ(solver.factorize(k).code, Code::not_symmetric) << to_string(b);
  }
}

TEST(SparseSolver, IndefiniteMatrixFailsCholeskyButSolvesWithLu) {
  // symmetric indefinite (as a tangent past a limit point): eigenvalues 3 and -1
  Eigen::MatrixXd d(2, 2);
  d << 1, 2, 2, 1;
  const SparseMatrixD k = from_dense(d);
  if (linear_backend_available(LinearBackend::cholmod_llt)) {
    SparseLinearSolver llt(LinearBackend::cholmod_llt);
    const LinearStatus s = llt.factorize(k);
    EXPECT_EQ(s.code, Code::not_positive_definite) << s.message;
    EXPECT_GE(s.dof, 0);
  }
  for (LinearBackend b : {LinearBackend::sparse_lu, LinearBackend::umfpack, LinearBackend::simplicial_ldlt}) {
    if (!linear_backend_available(b)) continue;
    SparseLinearSolver solver(b);
    ASSERT_TRUE(solver.factorize(k)) << to_string(b);
    Eigen::VectorXd x;
    ASSERT_TRUE(solver.solve(Eigen::Vector2d(3, 3), x));
    EXPECT_NEAR(x[0], 1.0, 1e-14);
    EXPECT_NEAR(x[1], 1.0, 1e-14);
  }
}

// MUMPS looks at each matrix's values: symmetric (to round-off) goes to LDLᵀ, anything else to LU,
// on one solver object and one pattern analysis (static_solvers.md §7). LDLᵀ pivots, so a
// symmetric indefinite matrix (a tangent past a limit point) solves, with the sign of det K.
TEST(SparseSolver, MumpsFactorsSymmetricMatricesByLdltAndOthersByLu) {
  if (!linear_backend_available(LinearBackend::mumps)) GTEST_SKIP() << "MUMPS not compiled in";
  SparseLinearSolver solver(LinearBackend::mumps);
  const auto solves = [&](const SparseMatrixD& k) {
    const Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(k.rows(), -1.0, 2.0).array().cos();
    Eigen::VectorXd x;
    if (!solver.factorize(k) || !solver.solve(k * x_true, x)) return false;
    return (x - x_true).norm() < 1e-11 * x_true.norm();
  };
  const SparseMatrixD symmetric = shell_grid_matrix(20, 0.0, 4), unsymmetric = shell_grid_matrix(20, 0.05, 4);
  ASSERT_TRUE(solves(symmetric));
  EXPECT_TRUE(solver.symmetric_factorization());
  ASSERT_TRUE(solves(unsymmetric));
  EXPECT_FALSE(solver.symmetric_factorization());
  // an asymmetry at round-off level (a 5-DoF shell tangent's) still counts as symmetric
  SparseMatrixD nearly = symmetric;
  nearly.coeffRef(3, 0) *= 1.0 + 1e-15;
  ASSERT_TRUE(solves(nearly));
  EXPECT_TRUE(solver.symmetric_factorization());
  EXPECT_EQ(solver.analyses(), 1);  // one pattern: the two instances analyze it once each

  // symmetric indefinite: det sign against dense LU
  std::mt19937 gen(5);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  int negatives = 0;
  for (int trial = 0; trial < 20; ++trial) {
    Eigen::MatrixXd d = Eigen::MatrixXd::Zero(30, 30);
    for (int i = 0; i < 30; ++i)
      for (int j = 0; j <= i; ++j)
        if (i == j || u(gen) > 0.6) d(i, j) = d(j, i) = u(gen);
    SparseLinearSolver ldlt(LinearBackend::mumps);
    const SparseMatrixD k = from_dense(d);
    ASSERT_TRUE(ldlt.factorize(k));
    EXPECT_TRUE(ldlt.symmetric_factorization());
    const double det = d.partialPivLu().determinant();
    EXPECT_EQ(ldlt.determinant_sign(), det > 0 ? 1 : -1) << "trial " << trial;
    Eigen::VectorXd x;
    ASSERT_TRUE(ldlt.solve(Eigen::VectorXd::Ones(30), x));
    EXPECT_LT((d * x - Eigen::VectorXd::Ones(30)).norm(), 1e-9 * d.norm() * x.norm());
    negatives += det < 0;
  }
  EXPECT_GT(negatives, 4);
}

// estimate_symmetric_factorization (MUMPS's analysis alone, what docs/performance.md sizes large
// models by): for a diagonally dominant matrix, where LDLᵀ delays no pivot, the analysis's
// estimates of the flops and factor entries are what the factorization of the same pattern then
// reports (MUMPS users' guide: RINFOG(1) against RINFOG(3), INFOG(20) against INFOG(29))
TEST(SparseSolver, AnalysisEstimatesAreWhatTheFactorizationOfThePatternReports) {
  if (!linear_backend_available(LinearBackend::mumps)) GTEST_SKIP() << "MUMPS not compiled in";
  const SparseMatrixD k = shell_grid_matrix(12, 0.0, 4);
  std::vector<int> rows, cols;
  for (int j = 0; j < k.outerSize(); ++j)
    for (SparseMatrixD::InnerIterator it(k, j); it; ++it)
      if (it.row() >= j) rows.push_back(static_cast<int>(it.row())), cols.push_back(j);
  FactorizationEstimate estimate;
  ASSERT_TRUE(estimate_symmetric_factorization(static_cast<int>(k.rows()), rows, cols, estimate));
  SparseLinearSolver solver(LinearBackend::mumps);
  ASSERT_TRUE(solver.factorize(k));
  ASSERT_TRUE(solver.symmetric_factorization());
  const LinearFigures done = solver.factorization_figures();
  EXPECT_GT(estimate.flops, 0.0);
  EXPECT_NEAR(estimate.flops, done.flops, 1e-9 * done.flops);
  EXPECT_EQ(estimate.factor_entries, done.factor_entries);
  EXPECT_GE(estimate.largest_front, 6 * 13);  // at least a separator across the grid, 6 DoFs a node
  // INFOG(16) holds ICNTL(14)'s 20 % margin over what the factorization then used
  EXPECT_GE(estimate.memory_mb_max_rank, done.memory_mb_max_rank);

  // anything but a lower triangle is refused, not handed to MUMPS
  FactorizationEstimate bad;
  EXPECT_EQ(estimate_symmetric_factorization(10, {0, 1}, {0, 2}, bad).code, Code::invalid_input);
  EXPECT_EQ(estimate_symmetric_factorization(10, {0, 10}, {0, 0}, bad).code, Code::invalid_input);
  EXPECT_EQ(estimate_symmetric_factorization(0, {}, {}, bad).code, Code::invalid_input);
}

// Ruiz's equilibration (equilibrate.h): every row and column maximum of D_r A D_c ends within the
// tolerance of 1, checked on the dense scaled matrix, for rows and columns spread over 12 decades;
// the symmetric form keeps one D for both sides and balances the whole symmetric matrix.
TEST(Equilibrate, BalancesRowAndColumnMaximaToOne) {
  std::mt19937 gen(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0), decade(-6.0, 6.0);
  const int n = 40;
  Eigen::MatrixXd d = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      if (i == j || u(gen) > 0.7) d(i, j) = u(gen);
  Eigen::VectorXd r(n), c(n);
  for (int i = 0; i < n; ++i) r[i] = std::pow(10.0, decade(gen)), c[i] = std::pow(10.0, decade(gen));
  const Eigen::MatrixXd a = r.asDiagonal() * d * c.asDiagonal();
  std::vector<int> rows, cols;
  std::vector<double> values;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      if (a(i, j) != 0.0) rows.push_back(i), cols.push_back(j), values.push_back(a(i, j));
  std::vector<double> dr, dc;
  const int sweeps = equilibrate_inf_norm(n, values.size(), rows.data(), cols.data(), 0, values.data(), false, dr, dc, 0.05, 60);
  EXPECT_LT(sweeps, 60);
  const Eigen::MatrixXd scaled = Eigen::Map<Eigen::VectorXd>(dr.data(), n).asDiagonal() * a *
                                 Eigen::Map<Eigen::VectorXd>(dc.data(), n).asDiagonal();
  for (int i = 0; i < n; ++i) {
    EXPECT_NEAR(scaled.row(i).cwiseAbs().maxCoeff(), 1.0, 0.05) << "row " << i;
    EXPECT_NEAR(scaled.col(i).cwiseAbs().maxCoeff(), 1.0, 0.05) << "column " << i;
  }

  // symmetric, given by its lower triangle; an empty row and column keep the scale 1
  Eigen::MatrixXd s = a.triangularView<Eigen::Lower>();
  s = Eigen::MatrixXd(s + s.transpose()) - Eigen::MatrixXd(a.diagonal().asDiagonal());
  s = r.asDiagonal() * Eigen::MatrixXd(r.cwiseInverse().asDiagonal() * s * r.cwiseInverse().asDiagonal()) * r.asDiagonal();
  s.row(7).setZero();
  s.col(7).setZero();
  rows.clear(), cols.clear(), values.clear();
  for (int j = 0; j < n; ++j)
    for (int i = j; i < n; ++i)
      if (s(i, j) != 0.0) rows.push_back(i + 1), cols.push_back(j + 1), values.push_back(s(i, j));  // 1-based
  equilibrate_inf_norm(n, values.size(), rows.data(), cols.data(), 1, values.data(), true, dr, dc, 0.05, 60);
  EXPECT_EQ(dr, dc);
  EXPECT_EQ(dr[7], 1.0);
  const Eigen::VectorXd D = Eigen::Map<Eigen::VectorXd>(dr.data(), n);
  const Eigen::MatrixXd ss = D.asDiagonal() * s * D.asDiagonal();
  for (int i = 0; i < n; ++i)
    if (i != 7) {
      EXPECT_NEAR(ss.row(i).cwiseAbs().maxCoeff(), 1.0, 0.05) << "row " << i;
    }
}

// Over MPI ranks each rank equilibrates the entries it hands MUMPS and the row and column maxima
// are the largest over the ranks (distributed.md (D7)). Two threads play two ranks here, their
// maxima combined at a barrier as MPI_MAX combines them: each must compute, bit for bit, the
// scaling one process computes from the whole matrix, and take the same keep decision.
namespace {
struct TwoPartMaxima {
  std::barrier<> meet{2};
  std::vector<double> part[2];
};
TwoPartMaxima* g_parts = nullptr;
thread_local int t_part = 0;
void combine_two_parts(double* maxima, std::size_t n) {
  g_parts->part[t_part].assign(maxima, maxima + n);
  g_parts->meet.arrive_and_wait();
  for (std::size_t i = 0; i < n; ++i) maxima[i] = std::max(g_parts->part[0][i], g_parts->part[1][i]);
  g_parts->meet.arrive_and_wait();  // both have read the other's maxima before the next sweep writes
}
}  // namespace

TEST(SparseSolver, EquilibrationOfEntriesSpreadOverPartsIsThatOfTheWholeMatrix) {
  for (bool symmetric : {false, true}) {
    const SparseMatrixD whole = shell_grid_matrix(9, symmetric ? 0.0 : 0.05, 4);
    const int n = static_cast<int>(whole.rows());
    std::vector<int> rows, cols;
    std::vector<double> values;
    for (int j = 0; j < n; ++j)
      for (SparseMatrixD::InnerIterator it(whole, j); it; ++it)
        if (!symmetric || it.row() >= j) {
          rows.push_back(it.row() + 1), cols.push_back(j + 1);
          values.push_back(it.value() * std::pow(10.0, 3.0 * std::sin(0.3 * it.row()) + 2.0 * std::cos(0.2 * j)));
        }
    std::vector<double> dr, dc;
    const int sweeps = equilibrate_inf_norm(n, values.size(), rows.data(), cols.data(), 1, values.data(), symmetric, dr, dc);
    ASSERT_GT(sweeps, 1);  // the test must exercise more than one exchange

    // the entries dealt to the two parts in an irregular pattern, each entry to exactly one
    std::vector<int> part_rows[2], part_cols[2];
    std::vector<double> part_values[2];
    for (std::size_t k = 0; k < values.size(); ++k) {
      const int p = (k * 7 + k / 5) % 3 == 0 ? 1 : 0;
      part_rows[p].push_back(rows[k]), part_cols[p].push_back(cols[k]), part_values[p].push_back(values[k]);
    }
    TwoPartMaxima parts;
    g_parts = &parts;
    std::vector<double> part_dr[2], part_dc[2];
    bool kept[2] = {false, false}, kept_drifted[2] = {true, true};
    std::vector<double> drifted[2];
    for (int p = 0; p < 2; ++p) {
      drifted[p] = part_values[p];
      for (std::size_t k = 0; k < drifted[p].size(); ++k)
        if (part_rows[p][k] % 11 == 0) drifted[p][k] *= 1e3;  // some rows out of balance by more than 4
    }
    auto run = [&](int p) {
      t_part = p;
      const std::size_t m = part_values[p].size();
      equilibrate_inf_norm(n, m, part_rows[p].data(), part_cols[p].data(), 1, part_values[p].data(), symmetric,
                           part_dr[p], part_dc[p], 0.1, 20, &combine_two_parts);
      kept[p] = scaling_still_balances(n, m, part_rows[p].data(), part_cols[p].data(), 1, part_values[p].data(),
                                       symmetric, part_dr[p], part_dc[p], 4.0, &combine_two_parts);
      kept_drifted[p] = scaling_still_balances(n, m, part_rows[p].data(), part_cols[p].data(), 1, drifted[p].data(),
                                               symmetric, part_dr[p], part_dc[p], 4.0, &combine_two_parts);
    };
    std::thread other(run, 1);
    run(0);
    other.join();
    g_parts = nullptr;
    for (int p = 0; p < 2; ++p) {
      EXPECT_EQ(part_dr[p], dr) << "part " << p << (symmetric ? ", symmetric" : "");
      EXPECT_EQ(part_dc[p], dc) << "part " << p << (symmetric ? ", symmetric" : "");
      EXPECT_TRUE(kept[p]);           // the scaling balances the matrix it was made for
      EXPECT_FALSE(kept_drifted[p]);  // and no part keeps it for rows a thousand times out
    }
  }
}

// MUMPS factorizes on a scaling computed once and kept over later factorizations of the pattern
// while it still balances them (static_solvers.md §7.2). A sequence of badly scaled matrices whose
// values drift, and then jump by eight decades in some rows and columns, solves as accurately as
// with a scaling of each matrix's own; a singular matrix on a kept scaling is still reported.
TEST(SparseSolver, MumpsKeepsItsScalingAcrossFactorizationsWithoutLosingAccuracy) {
  if (!linear_backend_available(LinearBackend::mumps)) GTEST_SKIP() << "MUMPS not compiled in";
  for (double asymmetry : {0.0, 0.05}) {
    SparseLinearSolver solver(LinearBackend::mumps);
    const SparseMatrixD base = shell_grid_matrix(12, asymmetry, 4);
    const int n = static_cast<int>(base.rows());
    Eigen::VectorXd scale(n);
    for (int i = 0; i < n; ++i) scale[i] = std::pow(10.0, 4.0 * std::sin(0.7 * i));
    const Eigen::VectorXd x_true = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0).array().cos();
    for (int k = 0; k < 40; ++k) {
      SparseMatrixD a = scale.asDiagonal() * base * scale.asDiagonal();
      for (int j = 0; j < n; ++j)  // the values drift from one factorization to the next
        for (SparseMatrixD::InnerIterator it(a, j); it; ++it)
          if (it.row() == j) it.valueRef() *= 1.0 + 0.02 * k;
      if (k >= 35)  // and then some rows and columns jump by eight decades
        for (int i = 0; i < n; i += 17) {
          a.row(i) *= 1e4;
          a.col(i) *= 1e4;
        }
      a.makeCompressed();
      Eigen::VectorXd x, x_fresh;
      ASSERT_TRUE(solver.factorize(a)) << "factorization " << k;
      ASSERT_TRUE(solver.solve(a * x_true, x));
      SparseLinearSolver fresh(LinearBackend::mumps);  // a scaling of this matrix's own
      ASSERT_TRUE(fresh.factorize(a));
      ASSERT_TRUE(fresh.solve(a * x_true, x_fresh));
      const double error = (x - x_true).norm() / x_true.norm(), fresh_error = (x_fresh - x_true).norm() / x_true.norm();
      // as accurate as a scaling of its own, up to the scatter of different pivot orders (a factor
      // of 2-3 here; a scaling kept for 32 factorizations regardless was 20-30 times worse after the jump)
      EXPECT_LT(error, 5.0 * fresh_error + 1e-12) << "factorization " << k << ", asymmetry " << asymmetry;
      if (k < 35) {
        EXPECT_LT(error, 1e-9) << "factorization " << k << ", asymmetry " << asymmetry;
      }
    }
    EXPECT_EQ(solver.analyses(), 1);
    SparseMatrixD singular = scale.asDiagonal() * base * scale.asDiagonal();
    for (int j = 0; j < n; ++j)
      for (SparseMatrixD::InnerIterator it(singular, j); it; ++it)
        if (it.row() == 5 || j == 5) it.valueRef() = 0.0;
    EXPECT_EQ(solver.factorize(singular).code, Code::singular);
  }
}

TEST(SparseSolver, MisuseIsReportedNotAsserted) {
  SparseLinearSolver solver(LinearBackend::sparse_lu);
  Eigen::VectorXd x;
  EXPECT_EQ(solver.solve(Eigen::VectorXd::Ones(3), x).code, Code::invalid_input);
  SparseMatrixD rect(3, 2);
  rect.makeCompressed();
  EXPECT_EQ(solver.analyze(rect).code, Code::invalid_input);
  const SparseMatrixD k = shell_grid_matrix(2);
  ASSERT_TRUE(solver.factorize(k));
  EXPECT_EQ(solver.solve(Eigen::VectorXd::Ones(5), x).code, Code::invalid_input);
}

}  // namespace
}  // namespace ff
