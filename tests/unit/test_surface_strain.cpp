// The display strain of cb_shell.md eqs. (V1)-(V3): zero under rigid motion, the exact Green-Lagrange
// value under a uniform stretch, and h/(2R) on the outer surface when a strip is bent to radius R.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "core/shell/surface_strain.h"

using namespace ff::shell;

namespace {

ElementPoses flat_square(double a) {
  ElementPoses p;
  const double xy[4][2] = {{0, 0}, {a, 0}, {a, a}, {0, a}};
  for (int c = 0; c < 4; ++c) p[c] = {Mat3::Identity(), Vec3(xy[c][0], xy[c][1], 0.0)};
  return p;
}

TEST(SurfaceStrain, RigidMotionGivesZero) {
  const ElementPoses ref = flat_square(0.3);
  const Mat3 Q = Eigen::AngleAxisd(1.1, Vec3(0.3, -0.5, 0.8).normalized()).toRotationMatrix();
  const Vec3 t(2.0, -1.0, 0.5);
  ElementPoses cur;
  for (int c = 0; c < 4; ++c) cur[c] = {Q * ref[c].R, Q * ref[c].p + t};
  EXPECT_LT(max_surface_strain(ref, cur, 0.01), 1e-14);
}

TEST(SurfaceStrain, UniformStretchGivesGreenLagrange) {
  const ElementPoses ref = flat_square(0.3);
  ElementPoses cur = ref;
  const double s = 1.1;  // stretch along x: E_xx = (s^2 - 1) / 2 = 0.105
  for (int c = 0; c < 4; ++c) cur[c].p.x() *= s;
  EXPECT_NEAR(max_surface_strain(ref, cur, 0.01), 0.5 * (s * s - 1.0), 1e-14);
  // a contraction of the same size shows as its absolute value
  for (int c = 0; c < 4; ++c) cur[c].p.x() = ref[c].p.x() * 0.9;
  EXPECT_NEAR(max_surface_strain(ref, cur, 0.01), 0.5 * (1.0 - 0.81), 1e-14);
}

TEST(SurfaceStrain, BentStripShowsHalfThicknessOverRadius) {
  // a flat a x a element wrapped onto a cylinder of radius R about the y axis, directors radial:
  // surface strains (1 +- h/(2R))^2-ish, to first order +- h/(2R); the mid-surface chord is shorter
  // than the arc by O(theta^2)
  const double a = 0.02, R = 1.0, h = 0.01;
  const ElementPoses ref = flat_square(a);
  ElementPoses cur;
  for (int c = 0; c < 4; ++c) {
    const double phi = ref[c].p.x() / R;
    const Vec3 d(-std::sin(phi), 0.0, std::cos(phi));  // outward normal of the cylinder of centre (0,0,-R)
    Mat3 Rm;
    Rm.col(0) = Vec3(std::cos(phi), 0.0, std::sin(phi));
    Rm.col(1) = Vec3(0.0, 1.0, 0.0);
    Rm.col(2) = d;
    cur[c] = {Rm, Vec3(R * std::sin(phi), ref[c].p.y(), R * std::cos(phi) - R)};
  }
  const double expected = h / (2.0 * R) + 0.5 * std::pow(h / (2.0 * R), 2);  // top surface, exact G-L of a ring
  EXPECT_NEAR(max_surface_strain(ref, cur, h), expected, 5e-5);  // chord error ~ theta^2 / 24 = 2e-5
}

TEST(SurfaceStrain, NodalAverageOfAdjacentElements) {
  const std::vector<std::array<int, 4>> quads = {{0, 1, 4, 3}, {1, 2, 5, 4}};
  const std::vector<double> v = average_to_nodes({1.0, 3.0}, quads, 7);
  EXPECT_DOUBLE_EQ(v[0], 1.0);
  EXPECT_DOUBLE_EQ(v[1], 2.0);
  EXPECT_DOUBLE_EQ(v[2], 3.0);
  EXPECT_DOUBLE_EQ(v[6], 0.0);  // no element
}

}  // namespace
