// Mesh quality metrics (core/mesh/mesh_quality.h, definitions in core/mesh/mesh_quality.md):
// hand-computed values on single quads, the summary (worst, median, quads past a limit), the
// refusal of inverted and degenerate quads in agreement with validate(), and invariance under a
// rigid motion.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>

#include "core/mesh/generators.h"
#include "core/mesh/mesh_quality.h"

using namespace ff::mesh;
using Eigen::Vector3d;

namespace {

constexpr double deg = 180.0 / std::numbers::pi;

// a flat mesh in the plane z = 0, directors +z (set, not derived, so that a bow-tie has some)
ShellMesh flat(std::vector<Vector3d> points, std::vector<std::array<int, 4>> quads) {
  ShellMesh m;
  m.points = std::move(points);
  m.quads = std::move(quads);
  m.normals.assign(m.points.size(), Vector3d::UnitZ());
  corner_normals_from_nodes(m);
  compute_frames(m);
  complete_layout(m);
  return m;
}

// directors from the quads themselves, as an importer makes them
ShellMesh imported(std::vector<Vector3d> points, std::vector<std::array<int, 4>> quads) {
  ShellMesh m;
  m.points = std::move(points);
  m.quads = std::move(quads);
  compute_area_weighted_normals(m);
  compute_frames(m);
  complete_layout(m);
  return m;
}

ShellMesh one_quad(const Vector3d& a, const Vector3d& b, const Vector3d& c, const Vector3d& d) {
  return imported({a, b, c, d}, {{0, 1, 2, 3}});
}

}  // namespace

TEST(MeshQuality, UnitSquareIsIdeal) {
  const ShellMesh m = one_quad({0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0});
  const QuadQuality q = quad_quality(m, 0);
  EXPECT_DOUBLE_EQ(q.aspect_ratio, 1.0);
  EXPECT_NEAR(q.skew, 0.0, 1e-12);
  EXPECT_NEAR(q.warping, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(q.jacobian_ratio, 1.0);
  const MeshQuality r = measure_quality(m);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.poor_count(), 0);
  EXPECT_EQ(r.quad_count, 1);
  EXPECT_EQ(r.node_count, 4);
}

TEST(MeshQuality, FourToOneRectangle) {
  const ShellMesh m = one_quad({0, 0, 0}, {4, 0, 0}, {4, 1, 0}, {0, 1, 0});
  const QuadQuality q = quad_quality(m, 0);
  EXPECT_DOUBLE_EQ(q.aspect_ratio, 4.0);
  EXPECT_NEAR(q.skew, 0.0, 1e-12);
  EXPECT_NEAR(q.warping, 0.0, 1e-12);
  EXPECT_DOUBLE_EQ(q.jacobian_ratio, 1.0);  // every corner of a parallelogram has the same Jacobian
  EXPECT_EQ(measure_quality(m).poor_count(), 0);  // 4 < the default limit 10
  QualityThresholds strict;
  strict.max_aspect_ratio = 3.0;
  const MeshQuality r = measure_quality(m, strict);
  ASSERT_EQ(r.summary(QualityMetric::aspect_ratio).beyond, std::vector<int>{0});
  EXPECT_EQ(r.poor_count(), 1);
}

TEST(MeshQuality, ParallelogramOfSixtyDegreesHasSkewThirty) {
  // unit sides, corner angle 60 deg: the midside lines are parallel to the sides, 60 deg apart
  const double c = std::cos(60.0 / deg), s = std::sin(60.0 / deg);
  const ShellMesh m = one_quad({0, 0, 0}, {1, 0, 0}, {1 + c, s, 0}, {c, s, 0});
  const QuadQuality q = quad_quality(m, 0);
  EXPECT_NEAR(q.aspect_ratio, 1.0, 1e-12);
  EXPECT_NEAR(q.skew, 30.0, 1e-10);
  EXPECT_NEAR(q.warping, 0.0, 1e-10);
  EXPECT_NEAR(q.jacobian_ratio, 1.0, 1e-12);
  // 75 deg beyond the default limit 60: corner angle 15 deg
  const double c15 = std::cos(15.0 / deg), s15 = std::sin(15.0 / deg);
  const ShellMesh sheared = one_quad({0, 0, 0}, {1, 0, 0}, {1 + c15, s15, 0}, {c15, s15, 0});
  EXPECT_NEAR(quad_quality(sheared, 0).skew, 75.0, 1e-10);
  EXPECT_EQ(measure_quality(sheared).summary(QualityMetric::skew).beyond, std::vector<int>{0});
}

TEST(MeshQuality, TrapezoidJacobianRatioIsHalf) {
  // parallel sides 2 and 1, height 1: corner Jacobians 1/2 at the long side, 1/4 at the short
  const ShellMesh m = one_quad({0, 0, 0}, {2, 0, 0}, {1.5, 1, 0}, {0.5, 1, 0});
  const QuadQuality q = quad_quality(m, 0);
  EXPECT_DOUBLE_EQ(q.jacobian_ratio, 0.5);
  EXPECT_DOUBLE_EQ(q.aspect_ratio, 2.0);
  EXPECT_NEAR(q.skew, 0.0, 1e-12);  // its midside lines are perpendicular
  QualityThresholds t;
  t.min_jacobian_ratio = 0.6;
  EXPECT_EQ(measure_quality(m, t).summary(QualityMetric::jacobian_ratio).beyond, std::vector<int>{0});
  t.min_jacobian_ratio = 0.4;
  EXPECT_TRUE(measure_quality(m, t).summary(QualityMetric::jacobian_ratio).beyond.empty());
}

TEST(MeshQuality, TriangleSplitInThreeHasJacobianRatioOneThird) {
  // a triangle cut into three quads at its centroid and edge midpoints (what a mesh of triangles
  // becomes when split): in a right isosceles triangle the corner Jacobians of each quad are
  // 3 : 2 : 1 : 2 (vertex, midpoint, centroid, midpoint), and ratios of areas are affine
  // invariants, so every such quad of any flat triangle has Jacobian ratio exactly 1/3
  const Vector3d a(0, 0, 0), b(5, 0.4, 0), c(1.2, 2.9, 0);
  const Vector3d g = (a + b + c) / 3.0, ab = 0.5 * (a + b), bc = 0.5 * (b + c), ca = 0.5 * (c + a);
  const ShellMesh m = flat({a, b, c, g, ab, bc, ca}, {{0, 4, 3, 6}, {1, 5, 3, 4}, {2, 6, 3, 5}});
  const MeshQuality r = measure_quality(m);
  ASSERT_TRUE(r.ok());
  for (int q = 0; q < 3; ++q) { EXPECT_NEAR(r.quads[q].jacobian_ratio, 1.0 / 3.0, 1e-12) << "quad " << q; }
  EXPECT_TRUE(r.summary(QualityMetric::jacobian_ratio).beyond.empty());  // the default 0.3 lets them pass
}

TEST(MeshQuality, LiftedCornerWarps) {
  // corner 2 of the unit square lifted by h: the split along 0-2 folds by acos(1/(1+h^2)), more
  // than the split along 1-3 (acos(1/sqrt(1+2h^2))); the director of a single imported quad is
  // its diagonal normal, against which the corner Jacobians are 2, 2+h^2, 2+2h^2, 2+h^2 (/ 4|n|)
  const double h = 0.2;
  const ShellMesh m = one_quad({0, 0, 0}, {1, 0, 0}, {1, 1, h}, {0, 1, 0});
  const QuadQuality q = quad_quality(m, 0);
  EXPECT_NEAR(q.warping, std::acos(1.0 / (1.0 + h * h)) * deg, 1e-10);
  EXPECT_NEAR(q.warping, 15.9424, 1e-4);
  EXPECT_NEAR(q.jacobian_ratio, 1.0 / (1.0 + h * h), 1e-12);
  EXPECT_NEAR(q.aspect_ratio, std::sqrt(1.0 + h * h), 1e-12);
  EXPECT_NEAR(q.skew, std::asin(h * h / (4.0 + h * h)) * deg, 1e-10);
  const MeshQuality r = measure_quality(m);
  EXPECT_TRUE(r.ok());
  EXPECT_EQ(r.summary(QualityMetric::warping).beyond, std::vector<int>{0});  // > 10 deg
  QualityThresholds t;
  t.max_warping = 20.0;
  EXPECT_EQ(measure_quality(m, t).poor_count(), 0);
}

TEST(MeshQuality, BowTieIsRefusedAsDegenerate) {
  // corners 1 and 2 swapped: the edges cross, the diagonals are parallel (zero vector area)
  const ShellMesh m = flat({{0, 0, 0}, {1, 1, 0}, {1, 0, 0}, {0, 1, 0}}, {{0, 1, 2, 3}});
  const MeshQuality r = measure_quality(m);
  ASSERT_FALSE(r.ok());
  EXPECT_EQ(r.refused[0].quad, 0);
  EXPECT_EQ(r.refused[0].kind, IssueKind::degenerate_quad);
  EXPECT_LE(r.quads[0].jacobian_ratio, 0.0);
  EXPECT_EQ(r.summary(QualityMetric::aspect_ratio).worst_quad, -1);  // nothing left to summarize
}

TEST(MeshQuality, ReflexQuadIsRefusedWithItsNumber) {
  // quad 1 has a reflex corner at node 5 (0.6, 0.6) + (2, 0): inverted there
  const ShellMesh m = flat({{0, 0, 0}, {2, 0, 0}, {2, 2, 0}, {0, 2, 0}, {4, 0, 0}, {2.6, 0.6, 0}},
                           {{0, 1, 2, 3}, {1, 4, 5, 2}});
  const MeshQuality r = measure_quality(m);
  ASSERT_EQ(r.refused.size(), 1u);
  EXPECT_EQ(r.refused[0].quad, 1);
  EXPECT_EQ(r.refused[0].kind, IssueKind::inverted_quad);
  EXPECT_NE(r.refused[0].message.find("quad 1"), std::string::npos);
  EXPECT_LE(r.quads[1].jacobian_ratio, 0.0);
  // the good quad is still summarized, the refused one takes no part
  EXPECT_EQ(r.summary(QualityMetric::jacobian_ratio).worst_quad, 0);
  EXPECT_DOUBLE_EQ(r.summary(QualityMetric::jacobian_ratio).worst, 1.0);
}

TEST(MeshQuality, WorstTypicalAndBeyondOrder) {
  // a strip of rectangles 1 high and 1, 4, 12, 11 wide: aspect ratios 1, 4, 12, 11
  std::vector<Vector3d> p;
  double x = 0;
  for (double w : {0.0, 1.0, 4.0, 12.0, 11.0}) {
    x += w;
    p.push_back({x, 0, 0});
    p.push_back({x, 1, 0});
  }
  std::vector<std::array<int, 4>> quads;
  for (int i = 0; i < 4; ++i) quads.push_back({2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1});
  const ShellMesh m = flat(p, quads);
  const MeshQuality r = measure_quality(m);
  const MetricSummary& a = r.summary(QualityMetric::aspect_ratio);
  EXPECT_DOUBLE_EQ(a.worst, 12.0);
  EXPECT_EQ(a.worst_quad, 2);
  EXPECT_DOUBLE_EQ(a.typical, 7.5);  // median of 1, 4, 11, 12
  EXPECT_EQ(a.beyond, (std::vector<int>{2, 3}));  // worst first
  EXPECT_DOUBLE_EQ(a.limit, 10.0);
  EXPECT_EQ(r.poor_count(), 2);
  const MetricSummary& j = r.summary(QualityMetric::jacobian_ratio);
  EXPECT_EQ(j.worst_quad, 0);  // all equal 1: the lowest number
  EXPECT_TRUE(j.beyond.empty());
}

TEST(MeshQuality, RefusalsAgreeWithValidate) {
  // a grid with its inner nodes shaken hard: some quads turn inside out, some collapse nearly
  ShellMesh m = rectangular_plate(1.0, 1.0, 12, 12);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> shake(-0.09, 0.09);
  for (int i = 0; i < m.node_count(); ++i) {
    Vector3d& x = m.points[i];
    if (x.x() > 1e-9 && x.x() < 1 - 1e-9 && x.y() > 1e-9 && x.y() < 1 - 1e-9) x += Vector3d(shake(rng), shake(rng), 0.0);
  }
  const MeshQuality r = measure_quality(m);
  const MeshCheck check = validate(m);
  std::vector<char> flagged(m.quad_count(), 0), refused(m.quad_count(), 0);
  for (const MeshIssue& i : check.issues)
    if (i.quad >= 0 && (i.kind == IssueKind::inverted_quad || i.kind == IssueKind::degenerate_quad ||
                        i.kind == IssueKind::normal_mismatch))
      flagged[i.quad] = 1;
  for (const MeshIssue& i : r.refused) refused[i.quad] = 1;
  int inverted = 0;
  for (int q = 0; q < m.quad_count(); ++q) {
    EXPECT_EQ(refused[q], flagged[q]) << "quad " << q;
    if (r.quads[q].jacobian_ratio <= 0) {
      EXPECT_TRUE(refused[q]) << "quad " << q << " has a non-positive Jacobian";
    }
    if (!refused[q]) {
      EXPECT_GT(r.quads[q].jacobian_ratio, 0.0) << "quad " << q;
    }
    inverted += refused[q];
  }
  EXPECT_GT(inverted, 0) << "the shaking should invert some quads";
  EXPECT_LT(inverted, m.quad_count());
}

TEST(MeshQuality, RigidMotionLeavesEveryMetric) {
  // a curved, graded mesh with every node shaken a little off the sphere (its quads warp), and
  // directors from the quads as an importer makes them
  ShellMesh m = hemisphere_quarter(6, 6);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> shake(-0.03, 0.03);
  for (Vector3d& x : m.points) x += Vector3d(shake(rng), shake(rng), shake(rng));
  compute_area_weighted_normals(m);
  compute_frames(m);
  const MeshQuality before = measure_quality(m);
  ASSERT_TRUE(before.ok());
  EXPECT_GT(before.summary(QualityMetric::warping).worst, 1.0);
  EXPECT_GT(before.summary(QualityMetric::skew).worst, 1.0);
  EXPECT_LT(before.summary(QualityMetric::jacobian_ratio).worst, 0.9);
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(0.7, Vector3d(1, 2, 3).normalized()) *
                             Eigen::AngleAxisd(-1.9, Vector3d::UnitZ())).toRotationMatrix();
  const Vector3d t(12.5, -3.0, 7.25);
  for (Vector3d& x : m.points) x = R * x + t;
  for (Vector3d& n : m.normals) n = R * n;
  for (auto& c : m.corner_normals)
    for (Vector3d& n : c) n = R * n;
  for (Eigen::Matrix3d& f : m.frames) f = R * f;
  const MeshQuality after = measure_quality(m);
  ASSERT_TRUE(after.ok());
  for (int q = 0; q < m.quad_count(); ++q)
    for (int k = 0; k < quality_metric_count; ++k) {
      const QualityMetric metric = static_cast<QualityMetric>(k);
      EXPECT_NEAR(after.quads[q].value(metric), before.quads[q].value(metric), 1e-9)
          << metric_label(metric) << " of quad " << q;
    }
  for (int k = 0; k < quality_metric_count; ++k) {
    // the mesh is symmetric: the worst quad may be another of equal value (to rounding)
    EXPECT_NEAR(after.metrics[k].worst, before.metrics[k].worst, 1e-9);
    EXPECT_NEAR(before.quads[after.metrics[k].worst_quad].value(static_cast<QualityMetric>(k)), before.metrics[k].worst, 1e-9);
    EXPECT_NEAR(after.metrics[k].typical, before.metrics[k].typical, 1e-9);
  }
}
