#pragma once
/// \file sample_elements.h
/// Element states for `flexframe bench --solve` and the CB shell's tests: a curved, skewed
/// patch of a cylinder and a large-rotation deformed state of it, so that every term of the
/// element (curvature, distortion, finite rotation) is exercised.
#include <cmath>
#include <random>

#include "core/shell/cb_shell.h"

namespace ff::shell::samples {

inline Mat3 rot(const Vec3& th) {
  const double a = th.norm();
  return a < 1e-300 ? Mat3::Identity() : Mat3(Eigen::AngleAxisd(a, th / a).toRotationMatrix());
}

/// Frame with director n and e1 as close to `hint` as possible.
inline Mat3 frame(const Vec3& n, const Vec3& hint = Vec3::UnitX()) {
  Vec3 e3 = n.normalized(), e1 = (hint - hint.dot(e3) * e3);
  if (e1.norm() < 1e-8) e1 = Vec3::UnitY() - Vec3::UnitY().dot(e3) * e3;
  e1.normalize();
  Mat3 R;
  R << e1, e3.cross(e1), e3;
  return R;
}

/// Patch of a cylinder of radius 2 (axis y), exact normals, slightly skewed.
inline ElementPoses curved() {
  ElementPoses p;
  const double R = 2.0, ang[4] = {-0.25, 0.22, 0.27, -0.2}, y[4] = {0, 0.05, 0.8, 0.7};
  for (int i = 0; i < 4; ++i) {
    const Vec3 n(std::sin(ang[i]), 0, std::cos(ang[i]));
    p[i] = {frame(n), R * n + Vec3(0, y[i], 0)};
  }
  return p;
}

/// A rigid rotation by about 2 rad plus a random deformation of amplitude `amp`.
inline ElementPoses deformed(const ElementPoses& ref, unsigned seed, double amp = 0.05) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  const Mat3 Q = rot(Vec3(0.9, -1.4, 1.1));
  ElementPoses p = ref;
  for (auto& n : p) {
    n.p = Q * n.p + Vec3(0.3, -0.2, 0.5) + amp * Vec3(u(g), u(g), u(g));
    n.R = Q * n.R * rot(2 * amp * Vec3(u(g), u(g), u(g)));
  }
  return p;
}

}  // namespace ff::shell::samples
