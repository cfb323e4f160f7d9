// CB shell element (core/shell/cb_shell.md): force = dE along local increments, tangent = dF by
// central differences through H exp(eps e_k), rigid-motion invariance, exact affine membrane states.
#include <gtest/gtest.h>

#include <random>

#include "core/shell/cb_shell.h"
#include "tests/support/shell_fixtures.h"

using namespace ff::shell;
using namespace ff::shell::testing;

namespace {

ShellSection section(double h = 0.05) { return isotropic_section(2.0e5, 0.3, h); }

struct Case {
  bool hr, ans, drilling;
  bool curved;
};

ShellOptions options(const Case& c) {
  ShellOptions o;
  o.hr = c.hr;
  o.ans = c.ans;
  o.drilling = c.drilling;
  o.drilling_factor = 0.1;
  return o;
}

std::string name(const Case& c) {
  return std::string(c.hr ? "hr" : "nohr") + (c.ans ? "_ans" : "_noans") + (c.drilling ? "_6dof" : "_5dof") +
         (c.curved ? "_curved" : "_flat");
}
}  // namespace

class CbShellConsistency : public ::testing::TestWithParam<Case> {};

TEST_P(CbShellConsistency, ForceIsEnergyGradientAndTangentIsForceDerivative) {
  const Case c = GetParam();
  const ElementPoses ref = c.curved ? curved() : flat_distorted();
  const CbShellElement el(ref, section(), options(c));
  for (unsigned seed : {1u, 2u}) {
    const ElementPoses cur = deformed(ref, seed);
    Vec24 F;
    Mat24 K;
    el.evaluate(cur, F, &K);
    const double h = 1e-6;
    Vec24 Ffd;
    Mat24 Kfd;
    central_differences(el, cur, h, Ffd, Kfd);
    // central differences, h = 1e-6: truncation ~h^2 |third derivative|, round-off ~eps |F| / h
    const double fscale = F.cwiseAbs().maxCoeff(), kscale = K.cwiseAbs().maxCoeff();
    EXPECT_LT((F - Ffd).cwiseAbs().maxCoeff(), 1e-6 * fscale) << name(c) << " seed " << seed;
    EXPECT_LT((K - Kfd).cwiseAbs().maxCoeff(), 1e-6 * kscale) << name(c) << " seed " << seed;
  }
}

TEST_P(CbShellConsistency, RigidMotionInvariance) {
  const Case c = GetParam();
  const ElementPoses ref = c.curved ? curved() : flat_distorted();
  const CbShellElement el(ref, section(), options(c));
  // a rigid motion of the reference gives zero force
  ElementPoses rigid = ref;
  const Mat3 Q = rot(Vec3(2.1, 0.4, -1.3));
  for (auto& n : rigid) n.p = Q * n.p + Vec3(5, -3, 1), n.R = Q * n.R;
  Vec24 F0;
  el.evaluate(rigid, F0, nullptr);
  EXPECT_LT(F0.cwiseAbs().maxCoeff(), 1e-9) << name(c);
  // a superposed rigid motion leaves force and tangent unchanged (local frames)
  const ElementPoses cur = deformed(ref, 7);
  ElementPoses moved = cur;
  const Mat3 Q2 = rot(Vec3(-0.7, 2.9, 0.2));
  for (auto& n : moved) n.p = Q2 * n.p + Vec3(-1, 4, 2), n.R = Q2 * n.R;
  Vec24 F1, F2;
  Mat24 K1, K2;
  el.evaluate(cur, F1, &K1);
  el.evaluate(moved, F2, &K2);
  EXPECT_LT((F1 - F2).cwiseAbs().maxCoeff(), 1e-10 * F1.cwiseAbs().maxCoeff()) << name(c);
  EXPECT_LT((K1 - K2).cwiseAbs().maxCoeff(), 1e-10 * K1.cwiseAbs().maxCoeff()) << name(c);
}

INSTANTIATE_TEST_SUITE_P(AllEffects, CbShellConsistency,
                         ::testing::Values(Case{false, false, false, false}, Case{true, false, false, false},
                                           Case{false, true, false, false}, Case{true, true, false, false},
                                           Case{true, true, true, false}, Case{true, true, false, true},
                                           Case{true, true, true, true}, Case{false, false, true, true}),
                         [](const auto& info) { return name(info.param); });

// without the drilling effect nothing resists the drilling rotation: its row (force and tangent) is
// zero, so a 5-DoF model drops it. (Its column is not zero away from equilibrium: spinning a node
// frame about its director rotates the local axes its moments are expressed in, eq. (16).)
TEST(CbShell, DrillingRowsVanishWithoutDrilling) {
  const ElementPoses ref = flat_distorted();
  ShellOptions o;
  o.drilling = false;
  const CbShellElement el(ref, section(), o);
  Vec24 F;
  Mat24 K;
  el.evaluate(deformed(ref, 3), F, &K);
  for (int I = 0; I < 4; ++I) {
    EXPECT_LT(K.row(6 * I + 5).cwiseAbs().maxCoeff(), 1e-12 * K.cwiseAbs().maxCoeff());
    EXPECT_LT(std::abs(F[6 * I + 5]), 1e-12 * F.cwiseAbs().maxCoeff());
  }
  o.drilling = true;
  const CbShellElement el6(ref, section(), o);
  el6.evaluate(deformed(ref, 3), F, &K);
  EXPECT_GT(K(5, 5), 0.0);
}

// affine in-plane stretch of a distorted flat element: uniform Green-Lagrange strain, so the
// energy must be exactly 1/2 eps^T C eps * volume, with and without the assumed stress
TEST(CbShell, AffineMembraneStateIsExact) {
  const ElementPoses ref = flat_distorted();
  const ShellSection sec = section(0.02);
  Eigen::Matrix2d F2;
  F2 << 1.03, 0.02, -0.01, 0.98;
  Eigen::Matrix3d Fd = Eigen::Matrix3d::Identity();
  Fd.topLeftCorner<2, 2>() = F2;
  ElementPoses cur = ref;
  for (auto& n : cur) n.p = Fd * n.p;
  const Eigen::Matrix2d E = 0.5 * (F2.transpose() * F2 - Eigen::Matrix2d::Identity());
  const double Em = sec.youngs_modulus / (1 - sec.poisson_ratio * sec.poisson_ratio), nu = sec.poisson_ratio;
  const double w = 0.5 * Em * (E(0, 0) * E(0, 0) + E(1, 1) * E(1, 1) + 2 * nu * E(0, 0) * E(1, 1) +
                               2 * (1 - nu) * E(0, 1) * E(0, 1));
  // area of the quad
  const Vec3 d1 = ref[2].p - ref[0].p, d2 = ref[3].p - ref[1].p;
  const double area = 0.5 * d1.cross(d2).norm();
  for (bool hr : {false, true}) {
    ShellOptions o;
    o.hr = hr;
    const CbShellElement el(ref, sec, o);
    EXPECT_NEAR(el.energy(cur), w * area * sec.thickness, 1e-9 * w * area * sec.thickness) << (hr ? "hr" : "no hr");
    Vec24 F;
    el.evaluate(cur, F, nullptr);
    Vec3 total = Vec3::Zero();
    for (int I = 0; I < 4; ++I) total += cur[I].R * F.segment<3>(6 * I);
    EXPECT_LT(total.norm(), 1e-9 * F.cwiseAbs().maxCoeff());  // self-equilibrated
  }
}
