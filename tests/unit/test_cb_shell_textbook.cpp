// The fast CB shell kernel (core/shell/cb_shell.cpp) against the textbook oracle
// (core/shell/cb_shell_textbook.cpp). Source of truth: core/shell/cb_shell.md eqs (S1)-(S17);
// the oracle evaluates the energy of (S1)-(S13) literally and differentiates it exactly
// (hyper-dual numbers), so an error in the fast kernel's hand-derived variations (S4), (S5),
// (S14)-(S17) or in its fused algebra shows here even where its own FD tests (which difference
// the same solid_terms they check) would pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>

#include "core/shell/cb_shell.h"
#include "tests/support/cb_shell_textbook.h"
#include "tests/support/shell_fixtures.h"

using namespace ff::shell;
using ff::shell::testing::frame;
using ff::shell::testing::perturb;
using ff::shell::testing::rot;

namespace {

ShellSection section(double h) { return isotropic_section(1.0e7, 0.3, h); }

/// A patch of a cylinder of radius 1 (axis y), side about 0.3, corners moved off the rectangle;
/// directors are the exact surface normals, so they differ from node to node.
ElementPoses cylinder_patch() {
  ElementPoses p;
  const double ang[4] = {-0.16, 0.13, 0.18, -0.12}, y[4] = {0.0, 0.04, 0.33, 0.27};
  for (int I = 0; I < 4; ++I) {
    const Vec3 n(std::sin(ang[I]), 0, std::cos(ang[I]));
    p[I] = {frame(n), n + Vec3(0, y[I], 0)};
  }
  return p;
}

/// A rigid motion plus random node increments: translations up to 0.02 per component
/// (strains of several percent) and rotations of about 0.15-0.3 rad.
ElementPoses deform(const ElementPoses& ref, unsigned seed) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const Mat3 Q = rot(Vec3(0.7, -1.1, 0.4));
  ElementPoses p = ref;
  for (auto& n : p) {
    n.p = Q * n.p + Vec3(0.2, 0.1, -0.3) + 0.02 * Vec3(u(g), u(g), u(g));
    n.R = Q * n.R * rot(0.17 * Vec3(u(g), u(g), u(g)));
  }
  return p;
}

struct Effects {
  bool hr, ans, drilling;
};
ShellOptions options(const Effects& e) {
  ShellOptions o;
  o.hr = e.hr;
  o.ans = e.ans;
  o.drilling = e.drilling;
  o.drilling_factor = 0.1;  // large enough that the drilling term is not lost in the round-off
  return o;
}
std::string name(const Effects& e) {
  return std::string(e.hr ? "hr" : "nohr") + (e.ans ? "_ans" : "_noans") + (e.drilling ? "_drilling_6dof" : "_5dof");
}

template <class M>
double rel_diff(const M& a, const M& b) {
  return (a - b).cwiseAbs().maxCoeff() / b.cwiseAbs().maxCoeff();
}

// The largest difference relative to the oracle's largest entry within each block of DoF kinds
// (u, bending θ0 θ1, drilling θ2), so that the small bending (E h³) and drilling (γ) entries are
// checked on their own scale and not only against the membrane entries (E h), 1e4-1e5 larger.
// Blocks that are zero in the oracle (drilling rows without the drilling effect) are skipped.
int kind(int dof) { return dof % 6 < 3 ? 0 : (dof % 6 < 5 ? 1 : 2); }
double blockwise_rel_diff(const Mat24& K, const Mat24& Ko) {
  double worst = 0;
  for (int ka = 0; ka < 3; ++ka)
    for (int kb = 0; kb < 3; ++kb) {
      double diff = 0, scale = 0;
      for (int a = 0; a < 24; ++a)
        for (int b = 0; b < 24; ++b)
          if (kind(a) == ka && kind(b) == kb) {
            diff = std::max(diff, std::abs(K(a, b) - Ko(a, b)));
            scale = std::max(scale, std::abs(Ko(a, b)));
          }
      if (scale > 0) worst = std::max(worst, diff / scale);
    }
  return worst;
}
double blockwise_rel_diff(const Vec24& F, const Vec24& Fo) {
  double worst = 0;
  for (int k = 0; k < 3; ++k) {
    double diff = 0, scale = 0;
    for (int a = 0; a < 24; ++a)
      if (kind(a) == k) diff = std::max(diff, std::abs(F[a] - Fo[a])), scale = std::max(scale, std::abs(Fo[a]));
    if (scale > 0) worst = std::max(worst, diff / scale);
  }
  return worst;
}

// the 20 DoFs a 5-DoF model keeps: all but the drilling rotation θ2 of each node
Eigen::Matrix<double, 20, 20> five_dof(const Mat24& K) {
  Eigen::Matrix<double, 20, 20> k5;
  for (int i = 0; i < 20; ++i)
    for (int j = 0; j < 20; ++j) k5(i, j) = K(6 * (i / 5) + i % 5, 6 * (j / 5) + j % 5);
  return k5;
}

}  // namespace

class CbShellTextbookMatch : public ::testing::TestWithParam<Effects> {};

// Measured (gcc 12, Release, printed per case): relative to the largest entry at most 2.8e-14
// (energy), 1.8e-14 (force), 5.2e-15 (tangent); block by block at most 6.6e-14 (force) and
// 7.2e-14 (tangent), over all eight effect sets, h = 0.01 and 0.05, two states each.
TEST_P(CbShellTextbookMatch, FastKernelEqualsTextbookToRoundOff) {
  const Effects e = GetParam();
  const ElementPoses ref = cylinder_patch();
  for (double h : {0.01, 0.05}) {
    const CbShellElement fast(ref, section(h), options(e));
    const CbShellTextbook oracle(ref, section(h), options(e));
    for (unsigned seed : {11u, 12u}) {
      const ElementPoses cur = deform(ref, seed);
      Vec24 F, Fo;
      Mat24 K, Ko;
      fast.evaluate(cur, F, &K);
      oracle.evaluate(cur, Fo, Ko);
      const double eo = oracle.energy(cur), de = std::abs(fast.energy(cur) - eo) / std::abs(eo);
      const double dF = rel_diff(F, Fo), dK = rel_diff(K, Ko);
      const double dFb = blockwise_rel_diff(F, Fo), dKb = blockwise_rel_diff(K, Ko);
      std::printf("%-24s h=%.2f seed %u: rel. diff energy %.1e force %.1e (per block %.1e) tangent %.1e (%.1e)\n",
                  name(e).c_str(), h, seed, de, dF, dFb, dK, dKb);
      EXPECT_LT(de, 1e-9) << name(e);
      EXPECT_LT(dF, 1e-9) << name(e);
      EXPECT_LT(dK, 1e-9) << name(e);
      EXPECT_LT(dFb, 1e-9) << name(e);
      EXPECT_LT(dKb, 1e-9) << name(e);
      if (!e.drilling) {  // used with 5 DoFs: the kept block, and no drilling row in either
        EXPECT_LT(rel_diff(five_dof(K), five_dof(Ko)), 1e-9) << name(e);
        for (int I = 0; I < 4; ++I) {
          EXPECT_EQ(Ko.row(6 * I + 5).cwiseAbs().maxCoeff(), 0.0);
          EXPECT_EQ(Fo[6 * I + 5], 0.0);
          EXPECT_LT(K.row(6 * I + 5).cwiseAbs().maxCoeff(), 1e-13 * K.cwiseAbs().maxCoeff());
        }
      }
    }
  }
}

INSTANTIATE_TEST_SUITE_P(AllEffects, CbShellTextbookMatch,
                         ::testing::Values(Effects{false, false, false}, Effects{true, false, false},
                                           Effects{false, true, false}, Effects{true, true, false},
                                           Effects{false, false, true}, Effects{true, false, true},
                                           Effects{false, true, true}, Effects{true, true, true}),
                         [](const auto& info) { return name(info.param); });

// The oracle on its own, without the fast kernel: its force is the central difference of its
// double-valued energy (perturbed through the test fixture's own exp, not the hyper-dual one),
// and its tangent the central difference of its force through X exp(ε e_b). Measured 1.6e-10
// (force) and 8.6e-11 (tangent) relative to the largest entry.
TEST(CbShellTextbook, ForceAndTangentAreDerivativesOfItsEnergy) {
  const ElementPoses ref = cylinder_patch();
  for (const Effects e : {Effects{false, false, false}, Effects{true, true, true}}) {
    const CbShellTextbook oracle(ref, section(0.03), options(e));
    const ElementPoses cur = deform(ref, 5);
    Vec24 F;
    Mat24 K;
    oracle.evaluate(cur, F, K);
    const double step = 1e-6;
    Vec24 Ffd;
    Mat24 Kfd;
    for (int k = 0; k < 24; ++k) {
      Ffd[k] = (oracle.energy(perturb(cur, k, step)) - oracle.energy(perturb(cur, k, -step))) / (2 * step);
      Vec24 Fp, Fm;
      Mat24 unused;
      oracle.evaluate(perturb(cur, k, step), Fp, unused);
      oracle.evaluate(perturb(cur, k, -step), Fm, unused);
      Kfd.col(k) = (Fp - Fm) / (2 * step);
    }
    // truncation ~ step² |third derivative|, round-off ~ 1e-16 |Π| / step
    std::printf("%-24s oracle vs central differences: force %.1e tangent %.1e\n", name(e).c_str(),
                rel_diff(Ffd, F), rel_diff(Kfd, K));
    EXPECT_LT(rel_diff(Ffd, F), 1e-6) << name(e);
    EXPECT_LT(rel_diff(Kfd, K), 1e-6) << name(e);
  }
}

// The comparison has teeth: an oracle built with a 1 % thicker section, κ = 1 instead of 5/6 or
// a 10 % larger drilling factor is far outside the tolerance of the match test.
TEST(CbShellTextbook, ComparisonDetectsAWrongSection) {
  const ElementPoses ref = cylinder_patch();
  const ShellOptions o = options({true, true, true});
  const CbShellElement fast(ref, section(0.03), o);
  ShellSection thicker = section(0.03), stiffer_shear = section(0.03);
  thicker.thickness *= 1.01;
  stiffer_shear.shear_factor = 1.0;
  const ElementPoses cur = deform(ref, 3);
  Vec24 F;
  Mat24 K;
  fast.evaluate(cur, F, &K);
  for (const ShellSection& wrong : {thicker, stiffer_shear}) {
    const CbShellTextbook oracle(ref, wrong, o);
    Vec24 Fo;
    Mat24 Ko;
    oracle.evaluate(cur, Fo, Ko);
    EXPECT_GT(rel_diff(F, Fo), 1e-3);
    EXPECT_GT(rel_diff(K, Ko), 1e-3);
    EXPECT_GT(std::abs(fast.energy(cur) - oracle.energy(cur)) / oracle.energy(cur), 1e-3);
  }
  // the drilling term is ~1 % of the energy and ~1e-3 of the largest entry: its own block shows it
  ShellOptions wrong_drilling = o;
  wrong_drilling.drilling_factor *= 1.1;
  const CbShellTextbook oracle(ref, section(0.03), wrong_drilling);
  Vec24 Fo;
  Mat24 Ko;
  oracle.evaluate(cur, Fo, Ko);
  EXPECT_GT(blockwise_rel_diff(F, Fo), 1e-3);
  EXPECT_GT(blockwise_rel_diff(K, Ko), 1e-3);
}
