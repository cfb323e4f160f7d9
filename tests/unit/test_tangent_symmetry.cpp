// Why MUMPS may factor static shell tangents by LDLᵀ (core/solve/static_solvers.md §7): with 5 DoF
// per node and dead loads the assembled tangent is symmetric in every state, not only at
// equilibrium; with drilling (6 DoF) the local-frame increments leave an asymmetric part that is
// linear in the out-of-balance force, so it vanishes as Newton converges. A cantilever plate under
// a pressure large enough for a finite deflection (tip ~ 0.4 of the span), full Newton.
#include <gtest/gtest.h>

#include <Eigen/SparseLU>

#include "core/mesh/generators.h"
#include "core/shell/shell_model.h"

namespace {

using namespace ff;

double relative_asymmetry(const Eigen::SparseMatrix<double>& K) {
  const Eigen::SparseMatrix<double> A = K - Eigen::SparseMatrix<double>(K.transpose());
  return A.coeffs().cwiseAbs().maxCoeff() / K.coeffs().cwiseAbs().maxCoeff();
}

struct NewtonHistory {
  std::vector<double> residual, asymmetry;
};

shell::ShellModelSpec cantilever(bool drilling) {
  shell::ShellModelSpec s;
  s.mesh = mesh::rectangular_plate(1.0, 1.0, 8, 8, "plate");
  s.section = ff::shell::isotropic_section(1.0e7, 0.3, 0.01);
  s.options.hr = s.options.ans = true;
  s.options.drilling = drilling;
  for (int i = 0; i < s.mesh.node_count(); ++i)
    if (s.mesh.points[i].x() < 1e-12) s.restraints.push_back({i, shell::kClamped});
  s.pressures.push_back({0, 300.0, false});
  return s;
}

// Newton from the reference state; with `symmetric_part` each correction solves with ½(K + Kᵀ)
NewtonHistory cantilever_newton(bool drilling, bool symmetric_part = false) {
  shell::ShellModel model(cantilever(drilling));
  NewtonHistory h;
  Eigen::VectorXd r, f;
  Eigen::SparseMatrix<double> K;
  for (int it = 0; it < 30; ++it) {
    model.evaluate(1.0, r, &K, &f);
    h.residual.push_back(r.norm());
    h.asymmetry.push_back(relative_asymmetry(K));
    if (r.norm() < 1e-9) break;
    if (symmetric_part) K = 0.5 * (K + Eigen::SparseMatrix<double>(K.transpose()));
    Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(K);
    const Eigen::VectorXd dq = -lu.solve(r);
    model.update(std::min(1.0, 0.2 / dq.cwiseAbs().maxCoeff()) * dq);  // at most 0.2 per step
  }
  return h;
}

TEST(TangentSymmetry, FiveDofTangentIsSymmetricInEveryState) {
  const NewtonHistory h = cantilever_newton(false);
  ASSERT_LT(h.residual.back(), 1e-9);
  double largest_residual = 0.0;
  for (std::size_t k = 0; k < h.asymmetry.size(); ++k) {
    EXPECT_LT(h.asymmetry[k], 1e-14) << "iteration " << k << ", |r| = " << h.residual[k];
    largest_residual = std::max(largest_residual, h.residual[k]);
  }
  EXPECT_GT(largest_residual, 10.0);  // states far from equilibrium were visited
}

TEST(TangentSymmetry, DrillingAsymmetryVanishesAtEquilibrium) {
  const NewtonHistory h = cantilever_newton(true);
  ASSERT_LT(h.residual.back(), 1e-9);
  // far from equilibrium the tangent is visibly unsymmetric (measured 7e-8 at |r| = 29) ...
  EXPECT_GT(*std::max_element(h.asymmetry.begin(), h.asymmetry.end()), 1e-9);
  // ... and at the converged state it is symmetric to round-off (measured 1.2e-16)
  EXPECT_LT(h.asymmetry.back(), 1e-14);
}

// What the static solvers do with mumps (static_common.cpp): the symmetric part ½(K + Kᵀ) differs
// from K by O(|r|), so it converges as K does: the same number of corrections and, iteration by
// iteration, residuals within a factor 2 of K's (measured: equal to 3 digits).
TEST(TangentSymmetry, NewtonWithTheSymmetricPartConvergesAsWithK) {
  const NewtonHistory exact = cantilever_newton(true), symmetric = cantilever_newton(true, true);
  ASSERT_LT(symmetric.residual.back(), 1e-9);
  ASSERT_EQ(symmetric.residual.size(), exact.residual.size());
  for (std::size_t k = 0; k + 1 < exact.residual.size(); ++k) {
    EXPECT_LT(symmetric.residual[k], 2.0 * exact.residual[k]) << "iteration " << k;
    EXPECT_GT(symmetric.residual[k], 0.5 * exact.residual[k]) << "iteration " << k;
  }
}

// The model says when its tangent is symmetric at equilibrium: not with follower pressure, not
// with a dead moment (not conservative on finite rotations)
TEST(TangentSymmetry, ModelDeclaresWhenItsTangentIsSymmetricAtEquilibrium) {
  EXPECT_TRUE(shell::ShellModel(cantilever(true)).tangent_symmetric_at_equilibrium());
  shell::ShellModelSpec follower = cantilever(true);
  follower.pressures.front().follower = true;
  EXPECT_FALSE(shell::ShellModel(std::move(follower)).tangent_symmetric_at_equilibrium());
  shell::ShellModelSpec moment = cantilever(false);
  moment.loads.push_back({5, shell::Vec3::Zero(), shell::Vec3(0.0, 1.0, 0.0), false});
  EXPECT_FALSE(shell::ShellModel(std::move(moment)).tangent_symmetric_at_equilibrium());
}

}  // namespace
