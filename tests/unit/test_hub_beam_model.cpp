// Hub-beam equations (core/hubbeam/hub_beam.md eqs. (9), (11)-(17)): analytic Jacobians vs
// central differences, the swapped D1 integral vs the nested form, FEM static cantilever.
#include <gtest/gtest.h>

#include <random>

#include "core/hubbeam/hub_beam_system.h"

using namespace ff::hubbeam;
using Eigen::MatrixXd;
using Eigen::VectorXd;

namespace {
HubBeamSystem make(bool efg, bool first_order = true, bool axial = true) {
  HubBeamParams p;
  HubBeamEffects fx;
  fx.first_order_coupling = first_order;
  fx.axial = axial;
  std::unique_ptr<BeamBasis> b = efg ? make_efg_basis(p.length, EfgOptions{})
                                     : make_fem_basis(p.length, FemOptions{});
  return HubBeamSystem(p, fx, std::move(b));
}

VectorXd random_state(int n, double amp, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> u(-amp, amp);
  VectorXd v(n);
  for (int i = 0; i < n; ++i) v[i] = u(gen);
  return v;
}

// central difference of the residual with respect to one argument
MatrixXd fd(const HubBeamSystem& s, VectorXd x, VectorXd v, VectorXd a, int which) {
  const int n = s.size();
  MatrixXd J(n, n);
  VectorXd rp, rm;
  for (int k = 0; k < n; ++k) {
    VectorXd& z = which == 0 ? x : which == 1 ? v : a;
    const double h = 1e-6 * (1.0 + std::abs(z[k]));
    const double z0 = z[k];
    z[k] = z0 + h;
    s.residual(x, v, a, 0.3, rp);
    z[k] = z0 - h;
    s.residual(x, v, a, 0.3, rm);
    z[k] = z0;
    J.col(k) = (rp - rm) / (2 * h);
  }
  return J;
}
}  // namespace

class HubBeamJacobian : public ::testing::TestWithParam<std::tuple<bool, bool, bool>> {};

TEST_P(HubBeamJacobian, MatchesCentralDifferences) {
  const auto [efg, first_order, axial] = GetParam();
  const HubBeamSystem s = make(efg, first_order, axial);
  const int n = s.size();
  // a large, spinning, accelerating state so every term of (15)-(17) is active
  VectorXd x = random_state(n, 0.05, 1), v = random_state(n, 0.5, 2), a = random_state(n, 2.0, 3);
  x[0] = 0.7;
  v[0] = 3.0;
  a[0] = -1.5;
  // axial stretch is physically ~1e-5 m (EA = 1.7e7 N); larger values only inflate round-off
  for (int i = 1; i <= s.axial_dofs(); ++i) x[i] *= 1e-3;
  MatrixXd A, C, K;
  s.jacobians(x, v, a, A, C, K);
  const MatrixXd Kf = fd(s, x, v, a, 0), Cf = fd(s, x, v, a, 1), Af = fd(s, x, v, a, 2);
  // truncation error of central differences (h ~ 1e-6) ~ 1e-9 relative, plus round-off eps*|r|/h
  VectorXd r;
  s.residual(x, v, a, 0.3, r);
  const double roundoff = 10 * 2.2e-16 * r.cwiseAbs().maxCoeff() / 1e-6;
  EXPECT_LT((A - Af).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + A.cwiseAbs().maxCoeff()) + roundoff);
  EXPECT_LT((C - Cf).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + C.cwiseAbs().maxCoeff()) + roundoff);
  EXPECT_LT((K - Kf).cwiseAbs().maxCoeff(), 1e-7 * (1.0 + K.cwiseAbs().maxCoeff()) + roundoff);
}

INSTANTIATE_TEST_SUITE_P(AllModels, HubBeamJacobian,
                         ::testing::Combine(::testing::Bool(), ::testing::Bool(), ::testing::Bool()));

// eq. (9) (swapped order) equals the paper's nested form (Xie & Jian 2017, eq. 42) D1 = ∫ rhoA (a+x) S(x) dx
TEST(HubBeamMatrices, SwappedD1EqualsNestedIntegral) {
  HubBeamParams p;
  FemOptions fo;
  auto basis = make_fem_basis(p.length, fo);
  const FullMatrices f = assemble_full(p, *basis);
  const int n = basis->node_count();
  MatrixXd nested = MatrixXd::Zero(2 * n, 2 * n);
  // outer Gauss over 90 cells; S(x) exact on each (polynomial integrand)
  const int cells = 90;
  const double h = p.length / cells;
  const double g[2] = {-1 / std::sqrt(3.0), 1 / std::sqrt(3.0)};
  for (int c = 0; c < cells; ++c)
    for (double gp : g) {
      const double x = h * (c + 0.5 * (gp + 1));
      nested += (0.5 * h) * p.density * p.area * (p.hub_radius + x) * coupling_shape_matrix(*basis, x, 9, 4);
    }
  EXPECT_LT((nested - f.d1).cwiseAbs().maxCoeff(), 1e-4 * f.d1.cwiseAbs().maxCoeff());
}

// static cantilever: K2 with a tip load P gives the Euler-Bernoulli tip deflection P L^3 / (3 E I)
TEST(HubBeamMatrices, StaticCantileverTipDeflection) {
  for (bool efg : {false, true}) {
    const HubBeamSystem s = make(efg);
    const auto& m = s.matrices();
    const double P = 2.0, L = s.params().length, EI = s.params().youngs_modulus * s.params().second_moment;
    const VectorXd f = P * m.n2_tip.transpose();
    const VectorXd q = m.k2.ldlt().solve(f);
    const double exact = P * L * L * L / (3 * EI);
    // Hermite cubics are exact for this load case; EFG (quadratic GMLS basis) within 0.5 %
    EXPECT_NEAR(m.n2_tip.dot(q), exact, (efg ? 5e-3 : 1e-10) * exact) << (efg ? "efg" : "fem");
  }
}

TEST(HubBeamMatrices, BeamInertiaMatchesThePaper) {
  const HubBeamSystem s = make(false);
  EXPECT_NEAR(s.matrices().jb, 1.46, 0.005);  // the hub-beam paper: J_b ≈ 1.46 kg m^2
}
