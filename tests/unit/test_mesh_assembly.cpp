// Assemblies of patches (core/mesh/generators.h assemble): coincident nodes merged with a
// tolerance relative to the mesh size, grids remapped, folds flagged with per-corner directors.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "core/mesh/generators.h"
#include "core/mesh/node_sets.h"

using namespace ff::mesh;
using Eigen::Vector3d;

TEST(MeshAssembly, TwoPlatesSharingAnEdgeMergeIt) {
  RectangularPlate left, right;
  left.a = 1;
  left.b = 1;
  right.a = 2;
  right.b = 1;
  right.origin = Vector3d(1, 0, 0);
  const ShellMesh m = assemble({rectangular_plate(left, 2, 3, "left"), rectangular_plate(right, 4, 3, "right")});
  EXPECT_EQ(m.node_count(), 3 * 4 + 5 * 4 - 4);
  EXPECT_EQ(m.quad_count(), 6 + 12);
  EXPECT_EQ(m.fold_count(), 0);
  // the grids see the same nodes on the shared edge
  EXPECT_EQ(patch_edge_nodes(m, "left", PatchEdge::u_max), patch_edge_nodes(m, "right", PatchEdge::u_min));
  EXPECT_EQ(m.patches[1].first_quad, 6);
  EXPECT_EQ(m.quad_patch.front(), 0);
  EXPECT_EQ(m.quad_patch.back(), 1);
  EXPECT_NEAR(total_area(m), 3.0, 1e-14);
  const MeshCheck c = validate(m);
  EXPECT_TRUE(c.ok()) << c.summary();
}

TEST(MeshAssembly, MergeToleranceIsRelativeToTheMeshSize) {
  for (double scale : {1e-3, 1.0, 1e4}) {
    RectangularPlate left, right;
    left.a = left.b = right.a = right.b = scale;
    right.origin = Vector3d(scale, 0, 0);
    ShellMesh r = rectangular_plate(right, 2, 2, "right");
    const double h = scale / 2;
    // round-off far below the tolerance (1e-6 h) merges
    for (auto& p : r.points) p.x() += 1e-9 * h;
    EXPECT_EQ(assemble({rectangular_plate(left, 2, 2), r}).node_count(), 9 + 9 - 3) << "scale " << scale;
    // a gap of 1e-3 h is a real gap
    for (auto& p : r.points) p.x() += 1e-3 * h;
    EXPECT_EQ(assemble({rectangular_plate(left, 2, 2), r}).node_count(), 18) << "scale " << scale;
  }
}

TEST(MeshAssembly, RightAngleFoldFlagsJunctionNodesAndKeepsCornerDirectors) {
  const int na = 4, nb = 3, nw = 2;
  const ShellMesh m = right_angle_folded_plate(2.0, 1.5, 1.0, na, nb, nw);
  EXPECT_EQ(m.node_count(), (na + 1) * (nw + 1) + (nb + 1) * (nw + 1) - (nw + 1));
  EXPECT_EQ(m.quad_count(), na * nw + nb * nw);
  const NodeSet fold_line = nodes_on_plane(m, Vector3d(2, 0, 0), Vector3d::UnitX());
  const NodeSet on_floor = nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitZ());
  const NodeSet junction = set_intersection(fold_line, on_floor);
  ASSERT_EQ(junction.size(), static_cast<std::size_t>(nw + 1));
  EXPECT_EQ(m.fold_count(), nw + 1);
  for (int i : junction) {
    EXPECT_TRUE(m.fold[i]) << "node " << i;
    EXPECT_EQ(m.normals[i], Vector3d::UnitZ()) << "the first patch's normal";
  }
  // leg2 quads carry their own director -x at the fold; leg1 quads +z
  const int leg2 = m.find_patch("leg2");
  ASSERT_GE(leg2, 0);
  int fold_corners = 0;
  for (int q = 0; q < m.quad_count(); ++q)
    for (int k = 0; k < 4; ++k) {
      const Vector3d want = m.quad_patch[q] == leg2 ? Vector3d(-1, 0, 0) : Vector3d(0, 0, 1);
      EXPECT_EQ(m.corner_normals[q][k], want) << "quad " << q << " corner " << k;
      if (m.fold[m.quads[q][k]] && m.quad_patch[q] == leg2) ++fold_corners;
    }
  EXPECT_EQ(fold_corners, 2 * nw);
  // non-fold nodes keep a director equal to every corner director that uses them
  for (int q = 0; q < m.quad_count(); ++q)
    for (int k = 0; k < 4; ++k)
      if (!m.fold[m.quads[q][k]]) {
        EXPECT_EQ(m.corner_normals[q][k], m.normals[m.quads[q][k]]);
      }
  EXPECT_NEAR(total_area(m), 2.0 + 1.5, 1e-14);
  const MeshCheck c = validate(m);
  EXPECT_TRUE(c.ok()) << c.summary();  // orientation consistent across the fold
}

TEST(MeshAssembly, SmoothJoinIsNotAFold) {
  // two cylinder patches meeting at phi = 1 share exact normals there
  CylinderPatch a, b;
  a.phi0 = 0;
  a.phi1 = 1;
  b.phi0 = 1;
  b.phi1 = 2;
  const ShellMesh m = assemble({cylindrical_patch(a, 3, 2, "a"), cylindrical_patch(b, 3, 2, "b")});
  EXPECT_EQ(m.node_count(), 4 * 3 + 4 * 3 - 3);
  EXPECT_EQ(m.fold_count(), 0);
  EXPECT_TRUE(validate(m).ok()) << validate(m).summary();
}

TEST(MeshAssembly, RepeatedPatchNamesGetSuffixes) {
  RectangularPlate far;
  far.origin = Vector3d(5, 0, 0);
  const ShellMesh m = assemble({rectangular_plate(1, 1, 1, 1), rectangular_plate(far, 1, 1), rectangular_plate(1, 1, 1, 1)});
  ASSERT_EQ(m.patches.size(), 3u);
  EXPECT_EQ(m.patches[0].name, "plate");
  EXPECT_EQ(m.patches[1].name, "plate_2");
  EXPECT_EQ(m.patches[2].name, "plate_3");
  // the third plate coincides with the first: all its nodes merge and its quad duplicates the
  // first plate's, which validation reports
  EXPECT_EQ(m.node_count(), 8);
  EXPECT_EQ(validate(m).count(IssueKind::duplicate_quad), 1);
}

TEST(MeshAssembly, FrameReferenceOption) {
  AssemblyOptions o;
  o.frame_reference = Vector3d::UnitY();
  const ShellMesh m = assemble({rectangular_plate(1, 1, 2, 2)}, o);
  EXPECT_EQ(m.frame_reference, Vector3d::UnitY());
  for (const auto& R : m.frames) {
    EXPECT_LT((R.col(0) - Vector3d::UnitY()).norm(), 1e-15);
    EXPECT_LT((R.col(1) + Vector3d::UnitX()).norm(), 1e-15);  // e2 = e3 x e1 = z x y = -x
  }
}
