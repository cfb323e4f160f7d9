// Cantilever strip rolled up by an end moment (seed 000 example 1; Sze, Liu & Lo 2004 §3.2).
// Analytic pure bending: t = M L / (E I), u/L = sin(t)/t - 1, w/L = (1 - cos t)/t; at M_max = 2 pi EI/L
// the strip closes into a circle. Paper's data: L = 12, B = 1, h = 0.1, E = 6.825e7, nu = 0, mesh 20x2.
#include <gtest/gtest.h>

#include <Eigen/SparseLU>
#include <cmath>

#include "core/shell/shell_model.h"

using namespace ff::shell;

namespace {
constexpr double kL = 12, kB = 1, kH = 0.1, kE = 6.825e7;

struct Tip {
  double u_half, w_half, u_full, w_full;  // tip mid-node displacement / L at M_max/2 and M_max
};

Tip roll_up(int nx, bool hr, bool ans, bool drilling) {
  const int ny = 2;
  ShellModelSpec s;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      s.mesh.points.emplace_back(kL * i / nx, kB * j / ny, 0);
      s.mesh.normals.push_back(Vec3::UnitZ());
      s.mesh.frames.push_back(Mat3::Identity());
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      s.mesh.quads.push_back({a, a + 1, a + nx + 2, a + nx + 1});
    }
  s.mesh.fold.assign(s.mesh.points.size(), 0);
  s.section = {kE, 0.0, kH, 5.0 / 6.0};
  s.options.hr = hr;
  s.options.ans = ans;
  s.options.drilling = drilling;
  const double EI = kE * kB * kH * kH * kH / 12, Mmax = 2 * M_PI * EI / kL;
  for (int j = 0; j <= ny; ++j) s.restraints.push_back({j * (nx + 1), kClamped});
  // consistent edge moment: 1/4, 1/2, 1/4 of M on the free-edge nodes, about -y (rolls toward +z)
  for (int j = 0; j <= ny; ++j)
    s.loads.push_back({j * (nx + 1) + nx, Vec3::Zero(), Vec3(0, -(j == 1 ? 0.5 : 0.25) * Mmax, 0), false});
  ShellModel m(s);
  const int tip = (nx + 1) + nx;
  Eigen::VectorXd r;
  Eigen::SparseMatrix<double> K;
  Tip out{};
  const int steps = 20;
  for (int k = 1; k <= steps; ++k) {
    const double lam = double(k) / steps;
    for (int it = 0; it < 30; ++it) {
      m.evaluate(lam, r, &K, nullptr);
      Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(K);
      const Eigen::VectorXd d = lu.solve(-r);
      m.update(d);
      if (d.norm() < 1e-10) break;
    }
    const Vec3 u = m.node_displacement(tip) / kL;
    if (k == steps / 2) out.u_half = u.x(), out.w_half = u.z();
    if (k == steps) out.u_full = u.x(), out.w_full = u.z();
  }
  return out;
}

const double kUHalf = std::sin(M_PI) / M_PI - 1, kWHalf = (1 - std::cos(M_PI)) / M_PI;  // -1, 2/pi
}  // namespace

// paper's mesh: measured 0.44 % / 0.35 % at M_max/2 and 1.8 % of L at M_max (see the next test)
TEST(ShellRollUp, PaperMeshMatchesPureBending) {
  for (bool drilling : {false, true}) {
    const Tip t = roll_up(20, true, true, drilling);
    EXPECT_NEAR(t.u_half, kUHalf, 0.006) << "drilling " << drilling;
    EXPECT_NEAR(t.w_half, kWHalf, 0.006) << "drilling " << drilling;
    EXPECT_NEAR(t.u_full, -1.0, 0.025) << "drilling " << drilling;
    EXPECT_NEAR(t.w_full, 0.0, 0.005) << "drilling " << drilling;
  }
}

// the remaining error is the CB element's chord interpolation over 18 degrees of rotation per
// element: it falls ~4x when the mesh is halved (measured 1.79 % -> 0.51 % -> 0.20 %)
TEST(ShellRollUp, ErrorConvergesUnderRefinement) {
  const double e20 = std::abs(roll_up(20, true, true, false).u_full + 1.0);
  const double e40 = std::abs(roll_up(40, true, true, false).u_full + 1.0);
  EXPECT_GT(e20 / e40, 3.0);
  EXPECT_LT(e40, 0.007);
}

// locking: the plain displacement-based element (no HR, no ANS) on the thin strip is far too stiff
TEST(ShellRollUp, WithoutHrAndAnsTheElementLocks) {
  const Tip locked = roll_up(20, false, false, false);
  EXPECT_LT(locked.w_half, 0.25 * kWHalf) << "measured w/L = 0.098 against 0.637";
  const Tip ans_only = roll_up(20, false, true, false);
  const Tip both = roll_up(20, true, true, false);
  EXPECT_LT(std::abs(both.w_half - kWHalf), std::abs(ans_only.w_half - kWHalf) + 1e-12);
}
