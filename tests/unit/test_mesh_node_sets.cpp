// Node selection (core/mesh/node_sets.h) on meshes whose numbering is known.
#include <gtest/gtest.h>

#include "core/mesh/generators.h"
#include "core/mesh/node_sets.h"

using namespace ff::mesh;
using Eigen::Vector3d;

namespace {
// 4 x 2 plate, 2 x 1: node (i, j) = 5 j + i at (i/2, j/2, 0)
ShellMesh plate() { return rectangular_plate(2.0, 1.0, 4, 2); }
}  // namespace

TEST(NodeSets, PlanePicksTheNodesOnIt) {
  const ShellMesh m = plate();
  EXPECT_EQ(nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitX()), (NodeSet{0, 5, 10}));
  EXPECT_EQ(nodes_on_plane(m, Vector3d(2, 0, 0), Vector3d(-3, 0, 0)), (NodeSet{4, 9, 14}));
  EXPECT_EQ(nodes_on_plane(m, Vector3d(0, 0.5, 0), Vector3d::UnitY()), (NodeSet{5, 6, 7, 8, 9}));
  // diagonal plane x - 2y = 0 through nodes (0,0), (1,0.5), (2,1)
  EXPECT_EQ(nodes_on_plane(m, Vector3d::Zero(), Vector3d(1, -2, 0)), (NodeSet{0, 7, 14}));
  // a plane between rows picks nothing with the automatic tolerance ...
  EXPECT_TRUE(nodes_on_plane(m, Vector3d(0.25, 0, 0), Vector3d::UnitX()).empty());
  // ... and the neighbours with a tolerance that reaches them
  EXPECT_EQ(nodes_on_plane(m, Vector3d(0.25, 0, 0), Vector3d::UnitX(), 0.25), (NodeSet{0, 1, 5, 6, 10, 11}));
  EXPECT_THROW(nodes_on_plane(m, Vector3d::Zero(), Vector3d::Zero()), std::invalid_argument);
}

TEST(NodeSets, BoxSphereNearest) {
  const ShellMesh m = plate();
  EXPECT_EQ(nodes_in_box(m, Vector3d(0.9, -1, -1), Vector3d(2.1, 0.6, 1)), (NodeSet{2, 3, 4, 7, 8, 9}));
  EXPECT_EQ(nodes_in_box(m, Vector3d(1, 0, 0), Vector3d(1, 1, 0)), (NodeSet{2, 7, 12}));  // flat box = a line
  EXPECT_EQ(nodes_in_sphere(m, Vector3d(1, 0.5, 0), 0.5), (NodeSet{2, 6, 7, 8, 12}));
  EXPECT_EQ(nodes_in_sphere(m, Vector3d(1, 0.5, 0), 0.4), (NodeSet{7}));
  EXPECT_EQ(nearest_node(m, Vector3d(1.9, 0.9, 3)), (NodeSet{14}));
  EXPECT_EQ(nearest_node(m, Vector3d(0.25, 0, 0)), (NodeSet{0}));  // tie: lowest id
  EXPECT_TRUE(nearest_node(ShellMesh{}, Vector3d::Zero()).empty());
}

TEST(NodeSets, PatchEdgesMatchTheGeometricBoundary) {
  const ShellMesh m = plate();
  EXPECT_EQ(patch_edge_nodes(m, "plate", PatchEdge::u_min), (NodeSet{0, 5, 10}));
  EXPECT_EQ(patch_edge_nodes(m, "plate", PatchEdge::u_max), (NodeSet{4, 9, 14}));
  EXPECT_EQ(patch_edge_nodes(m, "plate", PatchEdge::v_min), (NodeSet{0, 1, 2, 3, 4}));
  EXPECT_EQ(patch_edge_nodes(m, "plate", PatchEdge::v_max), (NodeSet{10, 11, 12, 13, 14}));
  EXPECT_EQ(patch_nodes(m, "plate").size(), 15u);
  try {
    patch_edge_nodes(m, "leg1", PatchEdge::u_min);
    ADD_FAILURE() << "no throw for an unknown patch";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("'plate'"), std::string::npos) << e.what();  // lists what exists
  }
  ShellMesh unstructured = m;
  unstructured.patches[0].nu = unstructured.patches[0].nv = 0;
  unstructured.patches[0].grid.clear();
  EXPECT_THROW(patch_edge_nodes(unstructured, "plate", PatchEdge::u_min), std::invalid_argument);
  EXPECT_EQ(parse_patch_edge("u=1"), PatchEdge::u_max);
  EXPECT_EQ(parse_patch_edge("v0"), PatchEdge::v_min);
  EXPECT_FALSE(parse_patch_edge("w=0").has_value());
}

TEST(NodeSets, BooleanCombinations) {
  const NodeSet a{1, 3, 5, 7}, b{3, 4, 5};
  EXPECT_EQ(set_union(a, b), (NodeSet{1, 3, 4, 5, 7}));
  EXPECT_EQ(set_intersection(a, b), (NodeSet{3, 5}));
  EXPECT_EQ(set_difference(a, b), (NodeSet{1, 7}));

  const ShellMesh m = plate();
  const auto left = NodeSelector::plane(Vector3d::Zero(), Vector3d::UnitX());
  const auto bottom = NodeSelector::patch_edge("plate", PatchEdge::v_min);
  EXPECT_EQ(NodeSelector::union_of({left, bottom}).select(m), (NodeSet{0, 1, 2, 3, 4, 5, 10}));
  EXPECT_EQ(NodeSelector::intersection_of({left, bottom}).select(m), (NodeSet{0}));
  EXPECT_EQ(NodeSelector::difference(left, bottom).select(m), (NodeSet{5, 10}));
  EXPECT_EQ(NodeSelector::all().select(m).size(), 15u);
  EXPECT_EQ(NodeSelector::ids({9, 2, 2}).select(m), (NodeSet{2, 9}));
  EXPECT_THROW(NodeSelector::ids({15}).select(m), std::invalid_argument);
  EXPECT_EQ(NodeSelector::nearest(Vector3d(2, 1, 0)).select(m), (NodeSet{14}));
  EXPECT_EQ(NodeSelector::box(Vector3d(-1, -1, -1), Vector3d(0.1, 0.1, 1)).select(m), (NodeSet{0}));
  EXPECT_EQ(NodeSelector::sphere(Vector3d(2, 1, 0), 0.5).select(m), (NodeSet{9, 13, 14}));
  EXPECT_EQ(NodeSelector::patch("plate").select(m).size(), 15u);
}

TEST(NodeSets, DescriptionsAndEmptyMessagesSayWhatWasAsked) {
  const ShellMesh m = plate();
  const auto sel = NodeSelector::plane(Vector3d(5, 0, 0), Vector3d::UnitX(), 1e-6);
  EXPECT_TRUE(sel.select(m).empty());
  EXPECT_EQ(sel.describe(), "nodes within 1e-06 of the plane through (5, 0, 0) with normal (1, 0, 0)");
  const std::string msg = empty_selection_message("clamped", sel, m);
  EXPECT_NE(msg.find("node set 'clamped' is empty"), std::string::npos) << msg;
  EXPECT_NE(msg.find("(5, 0, 0)"), std::string::npos) << msg;
  EXPECT_NE(msg.find("x in [0, 2]"), std::string::npos) << msg;  // where the mesh actually is
  EXPECT_NE(msg.find("15 nodes"), std::string::npos) << msg;

  const auto combo = NodeSelector::intersection_of(
      {NodeSelector::patch_edge("plate", PatchEdge::u_max), NodeSelector::sphere(Vector3d(2, 0, 0), 0.1)});
  EXPECT_EQ(combo.describe(),
            "(the nodes on edge u=1 of patch 'plate') and (nodes within distance 0.1 of (2, 0, 0) (tolerance auto))");
  EXPECT_EQ(NodeSelector::difference(NodeSelector::all(), NodeSelector::nearest(Vector3d(1, 2, 3))).describe(),
            "(all nodes) but not (the node nearest to (1, 2, 3))");
  EXPECT_NE(empty_selection_message("x", NodeSelector::all(), ShellMesh{}).find("no nodes"), std::string::npos);
}

TEST(NodeSets, AutomaticToleranceScalesWithTheMesh) {
  // a large mesh (roof, R = 2540): round-off in positions is ~1e-13 * 2540, far below the
  // automatic tolerance, and the symmetry planes select exactly one grid line each
  const ShellMesh m = hinged_roof_quarter(6, 5);
  EXPECT_NEAR(resolve_tolerance(m, kAutoTolerance), 1e-3 * min_edge_length(m), 1e-15);
  EXPECT_EQ(nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitX()), patch_edge_nodes(m, "roof", PatchEdge::v_min));
  EXPECT_EQ(nodes_on_plane(m, Vector3d::Zero(), Vector3d::UnitY()), patch_edge_nodes(m, "roof", PatchEdge::u_max));
  EXPECT_EQ(nodes_on_plane(m, Vector3d(254, 0, 0), Vector3d::UnitX()).size(), 7u);
}

// side: a node is facing a direction when every quad it belongs to lies that way from it. On the
// 4 x 2 plate the x_min column faces +x, the x_max column -x, interior nodes face nowhere; and two
// plates sharing the line x = 1 without sharing nodes (a slit) are told apart on that line.
TEST(NodeSets, FacingPicksOneLipOfCoincidentEdges) {
  const ShellMesh m = plate();
  EXPECT_EQ(nodes_facing(m, Vector3d::UnitX()), (NodeSet{0, 5, 10}));
  EXPECT_EQ(nodes_facing(m, -Vector3d::UnitX()), (NodeSet{4, 9, 14}));
  EXPECT_EQ(nodes_facing(m, Vector3d(1, 1, 0)), (NodeSet{0}));  // the corner whose quad lies up and right
  EXPECT_THROW(nodes_facing(m, Vector3d::Zero()), std::invalid_argument);
  EXPECT_THROW(nodes_facing(m, Vector3d(NAN, 0, 0)), std::invalid_argument);

  // left plate [0,1] x [0,1] (nodes 0..3), right plate [1,2] x [0,1] (nodes 4..7): x = 1 holds 1, 3, 5, 7
  ShellMesh slit;
  slit.points = {Vector3d(0, 0, 0), Vector3d(1, 0, 0), Vector3d(0, 1, 0), Vector3d(1, 1, 0),
                 Vector3d(1, 0, 0), Vector3d(2, 0, 0), Vector3d(1, 1, 0), Vector3d(2, 1, 0)};
  slit.quads = {{0, 1, 3, 2}, {4, 5, 7, 6}};
  const NodeSelector seam = NodeSelector::plane(Vector3d(1, 0, 0), Vector3d::UnitX());
  EXPECT_EQ(seam.select(slit), (NodeSet{1, 3, 4, 6}));
  EXPECT_EQ(NodeSelector::facing(seam, -Vector3d::UnitX()).select(slit), (NodeSet{1, 3}));
  EXPECT_EQ(NodeSelector::facing(seam, Vector3d::UnitX()).select(slit), (NodeSet{4, 6}));
  // nearest picks among the facing nodes: the lowest id would be 1 whatever the side
  EXPECT_EQ(NodeSelector::facing(NodeSelector::nearest(Vector3d(1, 0, 0)), Vector3d::UnitX()).select(slit), (NodeSet{4}));
  EXPECT_NE(NodeSelector::facing(seam, Vector3d::UnitX()).describe().find("toward"), std::string::npos);
}
