// Parametric shell meshes (core/mesh/generators.h): counts, points on the analytic surface,
// exact unit outward normals, quad orientation, frames, area convergence O(h^2), benchmarks.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/mesh/generators.h"
#include "core/mesh/node_sets.h"

using namespace ff::mesh;
using Eigen::Vector3d;

namespace {
constexpr double kPi = std::numbers::pi;

// every quad's geometric normal within max_angle of each of its corner directors
void expect_oriented(const ShellMesh& m, double max_angle, const char* what) {
  const double cos_max = std::cos(max_angle);
  int bad = 0;
  for (int q = 0; q < m.quad_count(); ++q) {
    const Vector3d g = quad_normal(m, q);
    for (int k = 0; k < 4; ++k)
      if (g.dot(m.corner_normals[q][k]) < cos_max) ++bad;
  }
  EXPECT_EQ(bad, 0) << what << ": quad normals disagree with the directors";
}

void expect_unit_normals_and_frames(const ShellMesh& m) {
  for (int i = 0; i < m.node_count(); ++i) {
    EXPECT_NEAR(m.normals[i].norm(), 1.0, 1e-14);
    const Eigen::Matrix3d& R = m.frames[i];
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
    EXPECT_LT((R.col(2) - m.normals[i]).norm(), 1e-15);
  }
}

void expect_valid(const ShellMesh& m) {
  const MeshCheck c = validate(m);
  EXPECT_TRUE(c.ok()) << c.summary();
}

// |A_h - A| for n, 2n, 4n elements per direction; the ratios must approach 4 (O(h^2))
template <class Make>
void expect_area_converges_quadratically(Make make, double exact, int n0, const char* what) {
  double err[3];
  for (int k = 0; k < 3; ++k) err[k] = std::abs(total_area(make(n0 << k)) - exact);
  for (int k = 0; k < 2; ++k) {
    const double ratio = err[k] / err[k + 1];
    EXPECT_GT(ratio, 3.6) << what << " refinement " << k;
    EXPECT_LT(ratio, 4.4) << what << " refinement " << k;
  }
  EXPECT_LT(err[2] / exact, 2e-3) << what;
}
}  // namespace

TEST(MeshGenerators, RectangularPlateCountsGeometryAndArea) {
  const ShellMesh m = rectangular_plate(2.0, 1.0, 4, 3);
  EXPECT_EQ(m.node_count(), 5 * 4);
  EXPECT_EQ(m.quad_count(), 4 * 3);
  ASSERT_EQ(m.patches.size(), 1u);
  EXPECT_TRUE(m.patches[0].structured());
  EXPECT_EQ(m.fold_count(), 0);
  for (int i = 0; i < m.node_count(); ++i) {
    EXPECT_EQ(m.points[i].z(), 0.0);
    EXPECT_EQ(m.normals[i], Vector3d::UnitZ());
    // frame: e1 = x (the default reference lies in the plane)
    EXPECT_LT((m.frames[i].col(0) - Vector3d::UnitX()).norm(), 1e-15);
  }
  // node (i, j) at (i a/4, j b/3)
  EXPECT_LT((m.points[m.patches[0].node(4, 3)] - Vector3d(2, 1, 0)).norm(), 1e-15);
  EXPECT_LT((m.points[m.patches[0].node(1, 2)] - Vector3d(0.5, 2.0 / 3.0, 0)).norm(), 1e-15);
  EXPECT_NEAR(total_area(m), 2.0, 1e-14);
  expect_unit_normals_and_frames(m);
  expect_oriented(m, 1e-12, "plate");
  expect_valid(m);
}

TEST(MeshGenerators, PlateOrientationFollowsRequestedNormal) {
  // e_a x e_b = -z: quads must run counter-clockwise about -z
  RectangularPlate s;
  s.e_a = Vector3d::UnitY();
  s.e_b = Vector3d::UnitX();
  const ShellMesh m = rectangular_plate(s, 3, 2);
  for (int q = 0; q < m.quad_count(); ++q) { EXPECT_LT((quad_normal(m, q) + Vector3d::UnitZ()).norm(), 1e-14); }
  expect_valid(m);
}

TEST(MeshGenerators, CylindricalPatchOnSurfaceWithOutwardNormals) {
  CylinderPatch s;
  s.radius = 3.0;
  s.origin = Vector3d(1, 2, 3);
  s.axis = Vector3d(1, 1, 0);  // not normalized on purpose
  s.radial0 = Vector3d::UnitZ();
  s.phi0 = 0.3;
  s.phi1 = 2.0;
  s.s0 = -1.0;
  s.s1 = 4.0;
  const ShellMesh m = cylindrical_patch(s, 6, 5);
  EXPECT_EQ(m.node_count(), 7 * 6);
  EXPECT_EQ(m.quad_count(), 30);
  const Vector3d a = s.axis.normalized();
  for (int i = 0; i < m.node_count(); ++i) {
    const Vector3d d = m.points[i] - s.origin;
    const double axial = d.dot(a);
    const Vector3d radial = d - axial * a;
    EXPECT_NEAR(radial.norm(), 3.0, 1e-13);
    EXPECT_GE(axial, -1.0 - 1e-13);
    EXPECT_LE(axial, 4.0 + 1e-13);
    EXPECT_LT((m.normals[i] - radial.normalized()).norm(), 1e-13) << "normal not radial outward at node " << i;
  }
  expect_unit_normals_and_frames(m);
  expect_oriented(m, 1.7 / 6, "cylinder");
  expect_valid(m);
}

TEST(MeshGenerators, InwardCylinderFlipsNormalsAndQuads) {
  CylinderPatch s;
  s.outward = false;
  const ShellMesh m = cylindrical_patch(s, 4, 2);
  for (int i = 0; i < m.node_count(); ++i) {
    Vector3d radial = m.points[i];
    radial.z() = 0;
    EXPECT_LT((m.normals[i] + radial.normalized()).norm(), 1e-14);
  }
  expect_oriented(m, kPi / 8, "inward cylinder");
  expect_valid(m);
}

TEST(MeshGenerators, ClosedCylinderMergesItsSeam) {
  CylinderPatch s;
  s.phi0 = 0;
  s.phi1 = 2 * kPi;
  const ShellMesh m = cylindrical_patch(s, 8, 3);
  EXPECT_EQ(m.node_count(), 8 * 4);  // the phi = 2 pi column is the phi = 0 column
  EXPECT_EQ(m.quad_count(), 24);
  EXPECT_EQ(m.fold_count(), 0);
  expect_valid(m);  // includes consistent orientation across the seam
}

TEST(MeshGenerators, SphericalPatchOnSurfaceWithOutwardNormals) {
  SpherePatch s;
  s.radius = 2.5;
  s.center = Vector3d(0.5, -1, 2);
  s.theta0 = 0.2;
  s.theta1 = 1.4;
  s.phi0 = -0.5;
  s.phi1 = 1.0;
  const ShellMesh m = spherical_patch(s, 5, 7);
  EXPECT_EQ(m.node_count(), 6 * 8);
  EXPECT_EQ(m.quad_count(), 35);
  for (int i = 0; i < m.node_count(); ++i) {
    const Vector3d d = m.points[i] - s.center;
    EXPECT_NEAR(d.norm(), 2.5, 1e-13);
    const double theta = std::acos(d.z() / d.norm());
    EXPECT_GE(theta, 0.2 - 1e-12);
    EXPECT_LE(theta, 1.4 + 1e-12);
    EXPECT_LT((m.normals[i] - d.normalized()).norm(), 1e-13);
  }
  expect_unit_normals_and_frames(m);
  expect_oriented(m, 0.3, "sphere");
  expect_valid(m);
}

TEST(MeshGenerators, AnnularSectorInPlaneWithRadiiInRange) {
  AnnularSector s;
  s.r_inner = 1.0;
  s.r_outer = 3.0;
  s.phi0 = 0.25;
  s.phi1 = 2.5;
  const ShellMesh m = annular_sector(s, 4, 9);
  EXPECT_EQ(m.node_count(), 5 * 10);
  EXPECT_EQ(m.quad_count(), 36);
  for (int i = 0; i < m.node_count(); ++i) {
    const double r = m.points[i].head<2>().norm();
    EXPECT_GE(r, 1.0 - 1e-14);
    EXPECT_LE(r, 3.0 + 1e-14);
    EXPECT_EQ(m.points[i].z(), 0.0);
    EXPECT_EQ(m.normals[i], Vector3d::UnitZ());
  }
  expect_oriented(m, 1e-12, "annulus");
  expect_valid(m);
}

TEST(MeshGenerators, AreasConvergeQuadraticallyToTheAnalyticArea) {
  CylinderPatch c;
  c.radius = 2;
  c.phi0 = 0;
  c.phi1 = 2.0;
  c.s0 = 0;
  c.s1 = 3;
  expect_area_converges_quadratically([&](int n) { return cylindrical_patch(c, n, n); }, 2 * 2.0 * 3, 4, "cylinder");

  SpherePatch s;  // hemisphere quarter: R^2 dphi (cos t0 - cos t1)
  s.radius = 10;
  s.theta0 = 18 * kPi / 180;
  s.theta1 = kPi / 2;
  expect_area_converges_quadratically([&](int n) { return spherical_patch(s, n, n); },
                                      100 * (kPi / 2) * std::cos(s.theta0), 4, "sphere");

  AnnularSector a;
  a.r_inner = 1;
  a.r_outer = 2;
  a.phi0 = 0;
  a.phi1 = 1.5;
  expect_area_converges_quadratically([&](int n) { return annular_sector(a, n, n); }, 0.5 * 1.5 * (4 - 1), 4,
                                      "annulus");
}

TEST(MeshGenerators, FrameFallsBackWhenReferenceIsParallelToNormal) {
  // octant of the open cylinder: the normal at phi = 0 is +x, the default reference
  const ShellMesh m = open_cylinder_octant(4, 2);
  const NodeSet on_x = nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitY());
  ASSERT_EQ(on_x.size(), 3u);
  for (int i : on_x) {
    EXPECT_LT((m.normals[i] - Vector3d::UnitX()).norm(), 1e-15);
    EXPECT_LT((m.frames[i].col(0) - Vector3d::UnitY()).norm(), 1e-15) << "fallback axis is the least aligned one";
    EXPECT_LT((m.frames[i].col(1) - Vector3d::UnitZ()).norm(), 1e-15);
  }
  // elsewhere e1 is the projection of x: e1 . x > 0 and e1 . z == 0
  for (int i = 0; i < m.node_count(); ++i) {
    if (std::find(on_x.begin(), on_x.end(), i) != on_x.end()) continue;
    EXPECT_GT(m.frames[i].col(0).x(), 0.0);
    EXPECT_NEAR(m.frames[i].col(0).z(), 0.0, 1e-15);
  }
}

TEST(MeshGenerators, RejectInvalidArguments) {
  EXPECT_THROW(rectangular_plate(1, 1, 0, 2), std::invalid_argument);
  EXPECT_THROW(rectangular_plate(-1, 1, 2, 2), std::invalid_argument);
  SpherePatch pole;
  pole.theta0 = 0;  // would collapse the first row of quads to triangles
  EXPECT_THROW(spherical_patch(pole, 4, 4), std::invalid_argument);
  try {
    spherical_patch(pole, 4, 4, "cap");
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("pole"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("cap"), std::string::npos) << e.what();
  }
  CylinderPatch c;
  c.radial0 = c.axis;
  EXPECT_THROW(cylindrical_patch(c, 4, 4), std::invalid_argument);
  c = CylinderPatch{};
  c.phi1 = 7.0;  // more than a full turn
  EXPECT_THROW(cylindrical_patch(c, 4, 4), std::invalid_argument);
  AnnularSector a;
  a.r_inner = 0;  // the centre is a pole
  EXPECT_THROW(annular_sector(a, 2, 2), std::invalid_argument);
}

// ---- benchmark geometries -------------------------------------------------------------------

TEST(MeshBenchmarks, CantileverStrip20x2) {
  const ShellMesh m = cantilever_strip();
  EXPECT_EQ(m.node_count(), 21 * 3);
  EXPECT_EQ(m.quad_count(), 40);
  EXPECT_NEAR(total_area(m), 12.0, 1e-13);
  EXPECT_EQ(nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitX()).size(), 3u);    // clamped end
  EXPECT_EQ(nodes_on_plane(m, Vector3d(12, 0, 0), Vector3d::UnitX()).size(), 3u);  // moment end
  expect_valid(m);
}

TEST(MeshBenchmarks, HemisphereQuarterWith18DegreeHole) {
  const ShellMesh m = hemisphere_quarter(8, 8);
  EXPECT_EQ(m.node_count(), 81);
  for (int i = 0; i < m.node_count(); ++i) {
    EXPECT_NEAR(m.points[i].norm(), 10.0, 1e-13);
    EXPECT_GE(m.points[i].z(), -1e-13);                            // upper hemisphere
    EXPECT_LE(m.points[i].z(), 10 * std::cos(18 * kPi / 180) + 1e-12);  // the hole
    EXPECT_GE(m.points[i].x(), -1e-13);
    EXPECT_GE(m.points[i].y(), -1e-13);
  }
  // load points A = (10, 0, 0), B = (0, 10, 0) are nodes
  for (const Vector3d& p : {Vector3d(10, 0, 0), Vector3d(0, 10, 0)}) {
    const NodeSet a = nearest_node(m, p);
    ASSERT_EQ(a.size(), 1u);
    EXPECT_LT((m.points[a[0]] - p).norm(), 1e-13);
    EXPECT_LT((m.normals[a[0]] - p / 10).norm(), 1e-13);
  }
  EXPECT_EQ(patch_edge_nodes(m, "hemisphere", PatchEdge::v_min), nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitY()));
  EXPECT_EQ(patch_edge_nodes(m, "hemisphere", PatchEdge::v_max), nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitX()));
  EXPECT_EQ(patch_edge_nodes(m, "hemisphere", PatchEdge::u_max), nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitZ()));
  expect_valid(m);
}

TEST(MeshBenchmarks, OpenCylinderOctant) {
  const ShellMesh m = open_cylinder_octant(24, 16);
  EXPECT_EQ(m.node_count(), 25 * 17);
  EXPECT_EQ(m.quad_count(), 24 * 16);
  double zmax = 0;
  for (int i = 0; i < m.node_count(); ++i) {
    EXPECT_NEAR(m.points[i].head<2>().norm(), 4.953, 1e-13);
    zmax = std::max(zmax, m.points[i].z());
  }
  EXPECT_NEAR(zmax, 10.35 / 2, 1e-13);
  const NodeSet a = nearest_node(m, Vector3d(4.953, 0, 0));
  EXPECT_LT((m.points[a[0]] - Vector3d(4.953, 0, 0)).norm(), 1e-13);
  EXPECT_EQ(patch_edge_nodes(m, "cylinder", PatchEdge::v_min).size(), 25u);  // mid-length plane
  EXPECT_EQ(nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitZ()), patch_edge_nodes(m, "cylinder", PatchEdge::v_min));
  expect_valid(m);
}

TEST(MeshBenchmarks, HingedRoofQuarter) {
  const ShellMesh m = hinged_roof_quarter(8, 8);
  const double R = 2540, theta = 0.1;
  EXPECT_EQ(m.node_count(), 81);
  for (int i = 0; i < m.node_count(); ++i) {
    const Vector3d d = m.points[i] - Vector3d(m.points[i].x(), 0, -R);
    EXPECT_NEAR(d.norm(), R, 1e-10);
    EXPECT_GE(m.points[i].x(), -1e-12);
    EXPECT_LE(m.points[i].x(), 254 + 1e-12);
    EXPECT_GE(m.points[i].y(), -1e-12);
    EXPECT_GT(m.normals[i].z(), std::cos(theta) - 1e-12);  // outward = up
  }
  // crown/centre load point and the hinged straight edge
  EXPECT_LT(m.points[nearest_node(m, Vector3d::Zero())[0]].norm(), 1e-10);
  const NodeSet hinged = patch_edge_nodes(m, "roof", PatchEdge::u_min);
  ASSERT_EQ(hinged.size(), 9u);
  for (int i : hinged) {
    EXPECT_NEAR(m.points[i].y(), R * std::sin(theta), 1e-10);
    EXPECT_NEAR(m.points[i].z(), R * (std::cos(theta) - 1), 1e-10);
  }
  // area of the quarter: R * theta * L
  EXPECT_NEAR(total_area(m), R * theta * 254, 1e-5 * R * theta * 254);
  expect_valid(m);
}

TEST(MeshBenchmarks, FlatLPlateOfSimoFoxRifai) {
  const int na = 7, nw = 2;
  const ShellMesh m = l_plate_simo_fox_rifai(na, nw);
  // two arms + corner, minus the two shared edges
  EXPECT_EQ(m.node_count(), 2 * (na + 1) * (nw + 1) + (nw + 1) * (nw + 1) - 2 * (nw + 1));
  EXPECT_EQ(m.quad_count(), 2 * na * nw + nw * nw);
  EXPECT_EQ(m.fold_count(), 0);  // the L lies in the plate's plane
  // centre lines 240 from each end to the centre of the corner square (240, 15)
  EXPECT_NEAR(total_area(m), 2 * 225 * 30 + 30 * 30, 1e-9);
  EXPECT_EQ(patch_edge_nodes(m, "arm1", PatchEdge::u_min), nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitX()));
  EXPECT_EQ(patch_edge_nodes(m, "arm2", PatchEdge::u_max), nodes_on_plane(m, Vector3d(0, 255, 0), Vector3d::UnitY()));
  for (const Vector3d& p : m.points) {
    EXPECT_GE(p.x(), -1e-12);
    EXPECT_LE(p.x(), 255 + 1e-12);
    EXPECT_LE(p.y(), 255 + 1e-12);
  }
  for (int i = 0; i < m.node_count(); ++i) { EXPECT_EQ(m.normals[i], Vector3d::UnitZ()); }
  expect_valid(m);
}

// ---- pole-free caps and disks, slits, folds, L plates (parametric geometry) ---------------------

TEST(MeshGenerators, ClosedCapHasNoCollapsedQuadsAndItsAreaConverges) {
  for (double span_deg : {90.0, 180.0, 360.0}) {
    SpherePatch s;
    s.radius = 2.0;
    s.theta0 = 0.0;  // closed at the pole: core + ring
    s.theta1 = 70.0 * kPi / 180;
    s.phi0 = 0.3;
    s.phi1 = 0.3 + span_deg * kPi / 180;
    const int q = static_cast<int>(span_deg / 90);
    const ShellMesh m = spherical_cap(s, 6, 4 * q, "cap");
    expect_valid(m);
    expect_unit_normals_and_frames(m);
    expect_oriented(m, 0.5, "closed cap");
    ASSERT_EQ(m.patches.size(), 2u);
    EXPECT_EQ(m.patches[0].name, "cap_core");
    EXPECT_EQ(m.patches[1].name, "cap");
    EXPECT_EQ(m.patches[1].edge_names[1], "rim");
    // core (2 q' x ...) + ring; nodes on the sphere, normals radial; the pole is a node
    bool pole = false;
    for (int i = 0; i < m.node_count(); ++i) {
      EXPECT_NEAR(m.points[i].norm(), 2.0, 1e-12);
      EXPECT_LT((m.normals[i] - m.points[i] / 2.0).norm(), 1e-12);
      EXPECT_GE(m.points[i].z(), 2.0 * std::cos(s.theta1) - 1e-12);
      pole = pole || (m.points[i] - Vector3d(0, 0, 2)).norm() < 1e-12;
    }
    EXPECT_TRUE(pole);
    // the rim edge: n2 + 1 nodes at theta1 (n2 for the closed cap)
    const NodeSet rim = patch_edge_nodes(m, "cap", resolve_patch_edge(m, "cap", "rim"));
    EXPECT_EQ(static_cast<int>(rim.size()), q == 4 ? 4 * q : 4 * q + 1);
    for (int i : rim) { EXPECT_NEAR(m.points[i].z(), 2.0 * std::cos(s.theta1), 1e-12); }
  }
  SpherePatch s;
  s.radius = 1.0;
  s.theta0 = 0.0;
  s.theta1 = kPi / 2;
  s.phi0 = 0.0;
  s.phi1 = 2 * kPi;
  expect_area_converges_quadratically([&](int n) { return spherical_cap(s, n, 8 * n); }, 2 * kPi, 3, "hemisphere");
}

TEST(MeshGenerators, DiskWithoutHoleIsAnOGridOfTheRightArea) {
  AnnularSector a;
  a.r_inner = 0.0;
  a.r_outer = 1.5;
  a.phi0 = 0.0;
  a.phi1 = 2 * kPi;
  const ShellMesh m = annulus(a, 4, 16, "disk");
  expect_valid(m);
  // core 4 x 4 quads + ring 4 x 16; nodes 25 + 4 x 16 (the ring's seam and inner row are merged)
  EXPECT_EQ(m.quad_count(), 16 + 64);
  EXPECT_EQ(m.node_count(), 25 + 4 * 16);
  for (int i = 0; i < m.node_count(); ++i) { EXPECT_LE(m.points[i].norm(), 1.5 + 1e-12); }
  // a flat polygon: the area error is the chord error at the rim only, O(h^2)
  expect_area_converges_quadratically([&](int n) { return annulus(a, n, 4 * n); }, kPi * 1.5 * 1.5, 4, "disk");
  // a quarter disk running clockwise (end_angle < start_angle) covers the same quadrant
  AnnularSector cw = a;
  cw.phi0 = kPi / 2;
  cw.phi1 = 0.0;
  const ShellMesh q = annulus(cw, 3, 4, "quarter");
  expect_valid(q);
  for (int i = 0; i < q.node_count(); ++i) {
    EXPECT_GE(q.points[i].x(), -1e-12);
    EXPECT_GE(q.points[i].y(), -1e-12);
  }
  EXPECT_GT(total_area(q), 0.95 * kPi * 1.5 * 1.5 / 4);
  AnnularSector bad = a;
  bad.phi1 = kPi / 3;  // a 60 degree sector through the centre has no pole-free quad mesh here
  try {
    annulus(bad, 4, 4);
    ADD_FAILURE() << "a 60 degree disk sector was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("90, 180 or 360"), std::string::npos) << e.what();
  }
  bad = a;
  try {
    annulus(bad, 4, 12);  // 12 is not a multiple of 8
    ADD_FAILURE() << "n_rim = 12 on a full disk was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("multiple of 8"), std::string::npos) << e.what();
  }
}

TEST(MeshGenerators, SlitAnnulusKeepsTwoLipsAndClosedOneMergesThem) {
  AnnularSector a;
  a.r_inner = 6.0;
  a.r_outer = 10.0;
  a.phi0 = 0.0;
  a.phi1 = 2 * kPi;
  const ShellMesh closed = annulus(a, 5, 40, "ring");
  EXPECT_EQ(closed.node_count(), 6 * 40);
  a.slit = true;
  const ShellMesh slit = annulus(a, 5, 40, "ring");
  EXPECT_EQ(slit.node_count(), 6 * 41);  // the 6 lip nodes twice
  expect_valid(slit);
  const NodeSet lip0 = patch_edge_nodes(slit, "ring", resolve_patch_edge(slit, "ring", "start_angle"));
  const NodeSet lip1 = patch_edge_nodes(slit, "ring", resolve_patch_edge(slit, "ring", "end_angle"));
  ASSERT_EQ(lip0.size(), 6u);
  ASSERT_EQ(lip1.size(), 6u);
  for (std::size_t k = 0; k < 6; ++k) {
    EXPECT_NE(lip0[k], lip1[k]);
    EXPECT_LT((slit.points[lip0[k]] - slit.points[lip1[k]]).norm(), 1e-12);  // coincident, separate
  }
  // no quad joins the lips: every quad has its corners on one side of the slit
  for (const auto& q : slit.quads) {
    int on0 = 0, on1 = 0;
    for (int c : q) on0 += std::count(lip0.begin(), lip0.end(), c), on1 += std::count(lip1.begin(), lip1.end(), c);
    EXPECT_FALSE(on0 > 0 && on1 > 0);
  }
  CylinderPatch c;
  c.phi0 = 0;
  c.phi1 = 2 * kPi;
  c.slit = true;
  EXPECT_EQ(cylindrical_patch(c, 8, 2).node_count(), 9 * 3);
  c.slit = false;
  EXPECT_EQ(cylindrical_patch(c, 8, 2).node_count(), 8 * 3);
}

TEST(MeshGenerators, EdgeNamesSelectTheSameNodesAsParameterEdges) {
  CylinderPatch c;
  c.phi0 = 0.2;
  c.phi1 = 1.3;
  const ShellMesh m = cylindrical_patch(c, 4, 3, "panel");
  const std::pair<const char*, PatchEdge> names[] = {{"start_angle", PatchEdge::u_min},
                                                     {"end_angle", PatchEdge::u_max},
                                                     {"bottom", PatchEdge::v_min},
                                                     {"top", PatchEdge::v_max}};
  for (const auto& [name, edge] : names) {
    EXPECT_EQ(resolve_patch_edge(m, "panel", name), edge) << name;
    EXPECT_EQ(resolve_patch_edge(m, "panel", to_string(edge)), edge);
  }
  try {
    resolve_patch_edge(m, "panel", "rim");
    ADD_FAILURE() << "a cylinder has no rim";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("\"start_angle\" (u=0)"), std::string::npos) << e.what();
  }
  EXPECT_THROW(resolve_patch_edge(m, "nope", "top"), std::invalid_argument);
  const ShellMesh p = axis_aligned_plate(2, 1, Vector3d(1, 2, 3), 4, 2);
  for (int i : patch_edge_nodes(p, "plate", resolve_patch_edge(p, "plate", "x_max"))) { EXPECT_DOUBLE_EQ(p.points[i].x(), 3.0); }
  for (int i : patch_edge_nodes(p, "plate", resolve_patch_edge(p, "plate", "y_min"))) { EXPECT_DOUBLE_EQ(p.points[i].y(), 2.0); }
}

TEST(MeshGenerators, FoldedPlateAtAnyAngleAndLPlateWithUnequalLegs) {
  FoldedPlate f;
  f.a = 2.0;
  f.b = 1.0;
  f.width = 0.5;
  const ShellMesh right = folded_plate(f, 4, 2, 1);
  const ShellMesh old = right_angle_folded_plate(2.0, 1.0, 0.5, 4, 2, 1);
  ASSERT_EQ(right.node_count(), old.node_count());
  for (int i = 0; i < old.node_count(); ++i) { EXPECT_EQ(right.points[i], old.points[i]); }
  f.fold_angle = 135.0 * kPi / 180;
  f.origin = Vector3d(1, 1, 1);
  const ShellMesh m = folded_plate(f, 4, 2, 1);
  expect_valid(m);
  int folds = 0;
  for (int i = 0; i < m.node_count(); ++i) folds += m.fold[i];
  EXPECT_EQ(folds, 2);  // the fold line has width + 1 = 2 nodes
  const NodeSet end = patch_edge_nodes(m, "leg2", resolve_patch_edge(m, "leg2", "end"));
  for (int i : end) {
    EXPECT_NEAR(m.points[i].x(), 1 + 2.0 + std::cos(f.fold_angle), 1e-12);
    EXPECT_NEAR(m.points[i].z(), 1 + std::sin(f.fold_angle), 1e-12);
  }
  f.fold_angle = kPi;
  EXPECT_THROW(folded_plate(f, 2, 2, 1), std::invalid_argument);

  LPlate l;
  l.leg1 = 100;
  l.leg2 = 60;
  l.width = 10;
  l.origin = Vector3d(0, 0, 2);
  const ShellMesh L = l_plate(l, 6, 2);
  expect_valid(L);
  EXPECT_NEAR(total_area(L), 10 * (95 + 10 + 55), 1e-9);
  for (int i : patch_edge_nodes(L, "arm2", resolve_patch_edge(L, "arm2", "end"))) { EXPECT_NEAR(L.points[i].y(), 65.0, 1e-12); }
  for (int i : patch_edge_nodes(L, "arm1", resolve_patch_edge(L, "arm1", "end"))) { EXPECT_NEAR(L.points[i].x(), 0.0, 1e-12); }
  l.leg2 = 4;  // shorter than half the width
  EXPECT_THROW(l_plate(l, 2, 2), std::invalid_argument);
}
