#pragma once
// Element states shared by the CB shell tests: reference geometries (flat distorted, curved),
// large-rotation deformed states and local-increment perturbations H <- H exp(eps e_k).
#include <random>

#include "core/shell/cb_shell.h"
#include "app/bench/sample_elements.h"

namespace ff::shell::testing {

using samples::curved;
using samples::deformed;
using samples::frame;
using samples::rot;

inline ElementPoses flat_distorted() {
  ElementPoses p;
  const Vec3 X[4] = {{0, 0, 0}, {1.3, 0.1, 0}, {1.1, 0.9, 0}, {-0.2, 1.2, 0}};
  for (int i = 0; i < 4; ++i) p[i] = {frame(Vec3::UnitZ()), X[i]};
  return p;
}

/// Local increment of DoF k (node k/6, component k%6) by eps: x += R e or R <- R exp(e~).
inline ElementPoses perturb(ElementPoses p, int k, double eps) {
  const int I = k / 6, c = k % 6;
  Vec3 e = Vec3::Zero();
  e[c % 3] = eps;
  if (c < 3) p[I].p += p[I].R * e;
  else p[I].R = p[I].R * rot(e);
  return p;
}

/// The same superposed rigid motion (Q, c) on every node.
inline ElementPoses moved(ElementPoses p, const Mat3& Q, const Vec3& c) {
  for (auto& n : p) n.p = Q * n.p + c, n.R = Q * n.R;
  return p;
}

// Central differences with step h through perturb(): of the energy (the force's oracle) and of
// the force (the tangent's oracle) of `el` at `cur`
template <class Element>
void central_differences(const Element& el, const ElementPoses& cur, double h, Vec24& Ffd, Mat24& Kfd) {
  for (int k = 0; k < 24; ++k) {
    Ffd[k] = (el.energy(perturb(cur, k, h)) - el.energy(perturb(cur, k, -h))) / (2 * h);
    Vec24 Fp, Fm;
    el.evaluate(perturb(cur, k, h), Fp, nullptr);
    el.evaluate(perturb(cur, k, -h), Fm, nullptr);
    Kfd.col(k) = (Fp - Fm) / (2 * h);
  }
}

}  // namespace ff::shell::testing
