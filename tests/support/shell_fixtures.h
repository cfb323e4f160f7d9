#pragma once
// Element states shared by the CB shell tests: reference geometries (flat distorted, curved),
// large-rotation deformed states and local-increment perturbations H <- H exp(eps e_k).
#include <random>

#include "core/shell/cb_shell.h"

namespace ff::shell::testing {

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

inline ElementPoses flat_distorted() {
  ElementPoses p;
  const Vec3 X[4] = {{0, 0, 0}, {1.3, 0.1, 0}, {1.1, 0.9, 0}, {-0.2, 1.2, 0}};
  for (int i = 0; i < 4; ++i) p[i] = {frame(Vec3::UnitZ()), X[i]};
  return p;
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
    n.x = Q * n.x + Vec3(0.3, -0.2, 0.5) + amp * Vec3(u(g), u(g), u(g));
    n.R = Q * n.R * rot(2 * amp * Vec3(u(g), u(g), u(g)));
  }
  return p;
}

/// Local increment of DoF k (node k/6, component k%6) by eps: x += R e or R <- R exp(e~).
inline ElementPoses perturb(ElementPoses p, int k, double eps) {
  const int I = k / 6, c = k % 6;
  Vec3 e = Vec3::Zero();
  e[c % 3] = eps;
  if (c < 3) p[I].x += p[I].R * e;
  else p[I].R = p[I].R * rot(e);
  return p;
}

/// The same superposed rigid motion (Q, c) on every node.
inline ElementPoses moved(ElementPoses p, const Mat3& Q, const Vec3& c) {
  for (auto& n : p) n.x = Q * n.x + c, n.R = Q * n.R;
  return p;
}

}  // namespace ff::shell::testing
