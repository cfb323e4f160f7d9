// Mesh invariants (core/mesh/shell_mesh.h): validate() finds each kind of defect with a message
// naming it; orient_consistently() repairs flipped quads and refuses a Moebius band; frames and
// area-weighted normals.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/mesh/generators.h"

using namespace ff::mesh;
using Eigen::Vector3d;

namespace {
ShellMesh plate() { return rectangular_plate(3.0, 2.0, 3, 2); }

bool mentions(const MeshCheck& c, IssueKind kind, const std::string& text) {
  for (const auto& i : c.issues)
    if (i.kind == kind && i.message.find(text) != std::string::npos) return true;
  return false;
}

// a mesh built only from points and quads, as an importer would
ShellMesh from_points_and_quads(std::vector<Vector3d> points, std::vector<std::array<int, 4>> quads) {
  ShellMesh m;
  m.points = std::move(points);
  m.quads = std::move(quads);
  compute_area_weighted_normals(m);
  compute_frames(m);
  complete_layout(m);
  return m;
}
}  // namespace

TEST(MeshValidation, GeneratedPlateIsClean) {
  const MeshCheck c = validate(plate());
  EXPECT_TRUE(c.ok()) << c.summary();
  EXPECT_EQ(c.summary(), "");
}

TEST(MeshValidation, FlippedQuadIsReportedAsInconsistentAndMismatched) {
  ShellMesh m = plate();
  std::swap(m.quads[4][1], m.quads[4][3]);  // quad 4 now runs clockwise
  const MeshCheck c = validate(m);
  EXPECT_FALSE(c.ok());
  EXPECT_GE(c.count(IssueKind::inconsistent_orientation), 2);  // its interior edges
  EXPECT_TRUE(mentions(c, IssueKind::inconsistent_orientation, "quads"));
  EXPECT_TRUE(mentions(c, IssueKind::normal_mismatch, "quad 4"));
}

TEST(MeshValidation, OrientConsistentlyRepairsAFlippedQuad) {
  ShellMesh m = plate();
  const auto original = m.quads;
  std::swap(m.quads[4][1], m.quads[4][3]);
  std::string why;
  ASSERT_TRUE(orient_consistently(m, &why)) << why;
  EXPECT_EQ(m.quads, original);  // quad 0 was right, so quad 4 flips back
  EXPECT_TRUE(validate(m).ok()) << validate(m).summary();
}

// issue 48: one reversed element does not turn the rest; each piece keeps the side most of its
// area was wound to, and the report says how much was turned
TEST(MeshValidation, OrientConsistentlyKeepsTheSideOfTheLargerArea) {
  ShellMesh m = plate();
  const auto original = m.quads;
  std::swap(m.quads[0][1], m.quads[0][3]);  // the FIRST quad reversed
  std::string why;
  OrientationReport report;
  ASSERT_TRUE(orient_consistently(m, &why, {}, &report)) << why;
  EXPECT_EQ(m.quads, original) << "quad 0 turns back; the five others stay";
  EXPECT_EQ(report.flipped, 1);
  EXPECT_EQ(report.pieces, 1);
  EXPECT_NEAR(report.largest_turned_share, 1.0 / 6.0, 1e-12);
  EXPECT_NEAR(report.flipped_area, 1.0, 1e-12);
}

// an edge of three quads (a T): the two that continue each other agree across it, the third is a
// piece of its own, and nothing is refused when junction edges are accepted
TEST(MeshValidation, AnEdgeOfThreeQuadsJoinsTheTwoThatContinueEachOther) {
  // quads 0 and 1 continue each other in the plane z = 0 across edge 0-1; quad 2 stands on it
  ShellMesh m = from_points_and_quads(
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, -1, 0}, {0, -1, 0}, {1, 0, 1}, {0, 0, 1}},
      {{{0, 1, 2, 3}}, {{0, 1, 4, 5}}, {{0, 1, 6, 7}}});  // quad 1 runs edge 0-1 the same way as quad 0
  OrientationOptions junctions;
  junctions.junction_edges = true;
  std::string why;
  OrientationReport report;
  ASSERT_TRUE(orient_consistently(m, &why, junctions, &report)) << why;
  EXPECT_EQ(report.pieces, 2) << "the plane, and the quad standing on it";
  EXPECT_EQ(report.flipped, 1);
  EXPECT_GT(quad_normal(m, 0).dot(quad_normal(m, 1)), 0.99) << "the two halves of the plane face one side";
  EXPECT_EQ(m.quads[2], (std::array<int, 4>{0, 1, 6, 7})) << "a piece of one quad keeps its own winding";
}

TEST(MeshValidation, MoebiusBandIsNotOrientable) {
  // a strip of n quads whose ends are glued with a half twist
  const int n = 8;
  std::vector<Vector3d> pts;
  for (int i = 0; i < n; ++i) {
    const double t = 2 * std::numbers::pi * i / n;
    for (double s : {-0.3, 0.3}) {
      const double r = 1 + s * std::cos(t / 2);
      pts.emplace_back(r * std::cos(t), r * std::sin(t), s * std::sin(t / 2));
    }
  }
  std::vector<std::array<int, 4>> quads;
  for (int i = 0; i + 1 < n; ++i) quads.push_back({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
  quads.push_back({2 * (n - 1), 1, 0, 2 * (n - 1) + 1});  // the twist swaps the sides
  ShellMesh m = from_points_and_quads(pts, quads);
  EXPECT_EQ(validate(m).count(IssueKind::inconsistent_orientation), 1);
  std::string why;
  EXPECT_FALSE(orient_consistently(m, &why));
  EXPECT_NE(why.find("not orientable"), std::string::npos) << why;
}

TEST(MeshValidation, DegenerateQuadIsReported) {
  ShellMesh m = plate();
  m.points[m.quads[0][2]] = m.points[m.quads[0][1]];  // two corners coincide
  const MeshCheck c = validate(m);
  EXPECT_TRUE(mentions(c, IssueKind::degenerate_quad, "quad 0")) << c.summary();
  // a corner with a 180 degree angle (a triangle with a node on one side)
  ShellMesh t = from_points_and_quads({{0, 0, 0}, {1, 0, 0}, {2, 0, 0}, {1, 1, 0}}, {{{0, 1, 2, 3}}});
  EXPECT_TRUE(mentions(validate(t), IssueKind::degenerate_quad, "180")) << validate(t).summary();
}

TEST(MeshValidation, NonConvexQuadIsReportedAsInverted) {
  ShellMesh m = from_points_and_quads({{0, 0, 0}, {2, 0, 0}, {0.5, 0.5, 0}, {0, 2, 0}}, {{{0, 1, 2, 3}}});
  const MeshCheck c = validate(m);
  EXPECT_EQ(c.count(IssueKind::inverted_quad), 1) << c.summary();
  EXPECT_TRUE(mentions(c, IssueKind::inverted_quad, "clockwise"));
}

TEST(MeshValidation, UnusedNodeIsReported) {
  ShellMesh m = plate();
  m.points.emplace_back(10, 10, 10);
  m.normals.push_back(Vector3d::UnitZ());
  m.frames.push_back(Eigen::Matrix3d::Identity());
  m.fold.push_back(0);
  const MeshCheck c = validate(m);
  EXPECT_EQ(c.count(IssueKind::unused_node), 1);
  EXPECT_TRUE(mentions(c, IssueKind::unused_node, "node 12"));
}

TEST(MeshValidation, NonManifoldEdgeIsReported) {
  // three quads hanging off the edge 0-1 (a "T" junction of sheets)
  ShellMesh m = from_points_and_quads(
      {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, -1, 0}, {0, -1, 0}, {1, 0, 1}, {0, 0, 1}},
      {{{0, 1, 2, 3}}, {{1, 0, 5, 4}}, {{0, 1, 6, 7}}});
  const MeshCheck c = validate(m);
  EXPECT_EQ(c.count(IssueKind::non_manifold_edge), 1) << c.summary();
  EXPECT_TRUE(mentions(c, IssueKind::non_manifold_edge, "edge 0-1"));
  std::string why;
  EXPECT_FALSE(orient_consistently(m, &why));
  EXPECT_NE(why.find("non-manifold"), std::string::npos);
}

TEST(MeshValidation, LayoutAndNormalErrors) {
  ShellMesh m = plate();
  m.quads[1][2] = 99;
  EXPECT_TRUE(mentions(validate(m), IssueKind::layout, "node 99"));
  m = plate();
  m.normals.pop_back();
  EXPECT_TRUE(mentions(validate(m), IssueKind::layout, "normals"));
  m = plate();
  m.normals[3] *= 2;
  EXPECT_EQ(validate(m).count(IssueKind::bad_normal), 1);
  m = plate();
  m.frames[2] = Eigen::Matrix3d::Identity() * 2;
  EXPECT_EQ(validate(m).count(IssueKind::bad_frame), 1);
  m = plate();
  m.points[0].x() = std::nan("");
  EXPECT_EQ(validate(m).count(IssueKind::non_finite), 1);
}

TEST(MeshValidation, SummaryIsBounded) {
  ShellMesh m = plate();
  for (int k = 0; k < 30; ++k) {
    m.points.emplace_back(10 + k, 0, 0);
    m.normals.push_back(Vector3d::UnitZ());
    m.frames.push_back(Eigen::Matrix3d::Identity());
    m.fold.push_back(0);
  }
  const std::string s = validate(m).summary(5);
  EXPECT_NE(s.find("... and 25 more"), std::string::npos) << s;
}

TEST(MeshFrames, OrthonormalWithE3AlongTheNormalAndE1FromTheReference) {
  const Vector3d ref(1, 0, 0);
  for (const Vector3d& n_raw : {Vector3d(0, 0, 1), Vector3d(1, 2, 3), Vector3d(-1, 0.1, 0), Vector3d(1, 0, 0),
                               Vector3d(1, 1e-5, 0), Vector3d(0, -1, 0)}) {
    const Vector3d n = n_raw.normalized();
    const Eigen::Matrix3d R = frame_from_normal(n, ref);
    EXPECT_LT((R.transpose() * R - Eigen::Matrix3d::Identity()).norm(), 1e-14);
    EXPECT_NEAR(R.determinant(), 1.0, 1e-14);
    EXPECT_LT((R.col(2) - n).norm(), 1e-15);
    const Vector3d proj = ref - ref.dot(n) * n;
    if (proj.norm() > 1e-3) { EXPECT_LT((R.col(0) - proj.normalized()).norm(), 1e-14); }
    else {
      // fallback: the global axis least aligned with n, projected
      int axis = 0;
      n.cwiseAbs().minCoeff(&axis);
      const Vector3d want = (Vector3d::Unit(axis) - n[axis] * n).normalized();
      EXPECT_LT((R.col(0) - want).norm(), 1e-14);
    }
  }
  // exactly parallel: the fallback is the global axis least aligned with n
  const Eigen::Matrix3d R = frame_from_normal(Vector3d::UnitX(), ref);
  EXPECT_LT((R.col(0) - Vector3d::UnitY()).norm(), 1e-15);
}

TEST(MeshNormals, AreaWeightedAverageOnAKinkedSheet) {
  // two unit quads meeting at a 90 degree ridge along x = 1: shared nodes get the bisector
  ShellMesh m = from_points_and_quads({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, -1}, {1, 1, -1}},
                                      {{{0, 1, 2, 3}}, {{1, 4, 5, 2}}});
  EXPECT_LT((m.normals[0] - Vector3d::UnitZ()).norm(), 1e-15);
  EXPECT_LT((m.normals[4] - Vector3d::UnitX()).norm(), 1e-15);
  EXPECT_LT((m.normals[1] - Vector3d(1, 0, 1).normalized()).norm(), 1e-15);
  EXPECT_EQ(m.fold_count(), 0);
  // a bigger second quad pulls the shared normal towards it
  ShellMesh w = from_points_and_quads({{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0}, {1, 0, -3}, {1, 1, -3}},
                                      {{{0, 1, 2, 3}}, {{1, 4, 5, 2}}});
  EXPECT_LT((w.normals[1] - Vector3d(3, 0, 1).normalized()).norm(), 1e-15);
  EXPECT_TRUE(validate(w).ok()) << validate(w).summary();
}
