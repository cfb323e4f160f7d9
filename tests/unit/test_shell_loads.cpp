// Consistent nodal forces of a dead surface traction (core/shell/shell_model.md P5,
// core/scene/shell_boundary.cpp surface_load_forces), against the exact integrals:
// - a flat regular plate: the forces sum to t times its area, and a corner, edge and interior node
//   get 1/4, 1/2 and 1 of one quad's share (the bilinear shape functions integrate to A/4 each);
// - a distorted flat quad: the resultant is t times its area and the first moment is exact too,
//   Σ_a x_a f_a = t ∫ Σ_a N_a x_a dA = t ∫ x dA (area times centroid, by the shoelace formulas);
// - a cylindrical panel: the sum equals t times the facets' area to the rule's accuracy.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <numeric>

#include "core/mesh/generators.h"
#include "core/scene/shell_boundary.h"

namespace {

using Vec3 = Eigen::Vector3d;

std::vector<int> all_quads(const ff::mesh::ShellMesh& m) {
  std::vector<int> q(m.quad_count());
  std::iota(q.begin(), q.end(), 0);
  return q;
}

Vec3 sum(const std::vector<std::pair<int, Vec3>>& f) {
  Vec3 s = Vec3::Zero();
  for (const auto& [node, v] : f) s += v;
  return s;
}

TEST(SurfaceLoad, RegularPlateGetsTheQuarterShares) {
  const double a = 2.0, b = 1.0;
  const int na = 4, nb = 2;
  const ff::mesh::ShellMesh m = ff::mesh::rectangular_plate(a, b, na, nb);
  const Vec3 t(0.3, -0.2, -90.0);
  const auto f = ff::scene::surface_load_forces(m, all_quads(m), t);
  EXPECT_LT((sum(f) - a * b * t).norm(), 1e-12 * (a * b * t).norm());
  const double quad_area = (a / na) * (b / nb);
  std::map<int, Vec3> by_node(f.begin(), f.end());
  auto node_at = [&](double x, double y) {
    for (int i = 0; i < m.node_count(); ++i)
      if ((m.points[i] - Vec3(x, y, 0)).norm() < 1e-12) return i;
    return -1;
  };
  EXPECT_LT((by_node.at(node_at(0, 0)) - 0.25 * quad_area * t).norm(), 1e-12 * t.norm());
  EXPECT_LT((by_node.at(node_at(0.5, 0)) - 0.5 * quad_area * t).norm(), 1e-12 * t.norm());
  EXPECT_LT((by_node.at(node_at(1.0, 0.5)) - quad_area * t).norm(), 1e-12 * t.norm());
}

TEST(SurfaceLoad, DistortedFlatQuadKeepsTheResultantAndItsMoment) {
  ff::mesh::ShellMesh m = ff::mesh::rectangular_plate(1.0, 1.0, 1, 1);
  // a general convex quad in z = 0 (same node order: counter-clockwise)
  const std::array<Vec3, 4> x = {Vec3(0, 0, 0), Vec3(2.0, 0.3, 0), Vec3(1.6, 1.9, 0), Vec3(-0.4, 1.1, 0)};
  for (int c = 0; c < 4; ++c) m.points[m.quads[0][c]] = x[c];
  const Vec3 t(0, 0, -1.0);
  const auto f = ff::scene::surface_load_forces(m, {0}, t);
  // area and centroid of the polygon (shoelace)
  double area = 0, cx = 0, cy = 0;
  for (int c = 0; c < 4; ++c) {
    const Vec3 &p = x[c], &q = x[(c + 1) % 4];
    const double w = p.x() * q.y() - q.x() * p.y();
    area += 0.5 * w, cx += (p.x() + q.x()) * w / 6, cy += (p.y() + q.y()) * w / 6;
  }
  cx /= area, cy /= area;
  EXPECT_NEAR(sum(f).z(), -area, 1e-12);
  double mx = 0, my = 0;  // Σ x_a f_a,z = −∫ x dA
  for (const auto& [node, v] : f) mx += m.points[node].x() * v.z(), my += m.points[node].y() * v.z();
  EXPECT_NEAR(mx, -area * cx, 1e-12);
  EXPECT_NEAR(my, -area * cy, 1e-12);
}

TEST(SurfaceLoad, CylindricalPanelCarriesTheTractionTimesItsArea) {
  ff::mesh::CylinderPatch spec;
  spec.radius = 25.0;
  spec.axis = Vec3::UnitY();
  spec.radial0 = Vec3::UnitZ();
  spec.phi0 = 0.0, spec.phi1 = 40.0 * std::numbers::pi / 180.0;
  spec.s0 = 0.0, spec.s1 = 25.0;
  const int n = 8;
  const ff::mesh::ShellMesh m = ff::mesh::cylindrical_patch(spec, n, n);
  const Vec3 t(0, 0, -90.0);
  const auto f = ff::scene::surface_load_forces(m, all_quads(m), t);
  // the facets are flat rectangles of chord 2 R sin(Δφ / 2) by the axial step
  const double dphi = (spec.phi1 - spec.phi0) / n;
  const double facets = n * 2 * spec.radius * std::sin(0.5 * dphi) * (spec.s1 - spec.s0);
  EXPECT_NEAR(sum(f).z(), -90.0 * facets, 1e-9 * 90.0 * facets);
  EXPECT_LT(std::abs(sum(f).x()) + std::abs(sum(f).y()), 1e-9 * 90.0 * facets);
}

}  // namespace
