// scene::scene_selections (what `check --picture` draws): every entry's nodes as the builders
// select them, with a label and an extent that say what the entry acts on. A displacement probe
// reads one node (the first its selector returns), a reaction probe all it selects, a pressure the
// quads whose four corners are selected; a model without a shell structure has none.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/scene/scene.h"
#include "core/scene/scene_selections.h"

namespace ff::scene {
namespace {

std::string write_scene(const std::string& name, const std::string& text) {
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out/unit/scene_selections";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + name + ".toml";
  std::ofstream(path) << text;
  return path;
}

// a 4 x 2 plate on [0, 2] x [0, 1]: node (i, j) = 5 j + i
const char* kPlate = R"([scene]
name = "selections"
model = "shell"
analysis = "static"
effects = ["elastic"]

[[part]]
name = "plate"
generator = "rectangular_plate"
length = 2.0
width = 1.0
n1 = 4
n2 = 2

[[material]]
youngs_modulus = 1.0
thickness = 0.1

[[bc]]
type = "fix"
fix = ["ux", "uz"]
select = "plane"
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]

[[load]]
type = "pressure"
pressure = 1.0
select = "box"
box_min = [0.9, -1.0, -1.0]
box_max = [2.1, 2.0, 1.0]

[[probe]]
name = "edge_w"
direction = [0.0, 0.0, 1.0]
select = "plane"
point = [2.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]

[[probe]]
name = "support"
quantity = "reaction"
direction = [0.0, 0.0, 1.0]
select = "plane"
point = [0.0, 0.0, 0.0]
normal = [1.0, 0.0, 0.0]

[solver]
method = "linear"
)";

TEST(SceneSelections, EachEntrySaysWhatItActsOn) {
  const std::optional<SceneSelections> s = scene_selections(write_scene("plate", kPlate), {}, {});
  ASSERT_TRUE(s.has_value());
  EXPECT_EQ(s->scene_name, "selections");
  EXPECT_EQ(s->mesh.node_count(), 15);
  EXPECT_EQ(s->part_names, std::vector<std::string>{"plate"});
  ASSERT_EQ(s->entries.size(), 4u);

  const EntrySelection& bc = s->entries[0];
  EXPECT_EQ(bc.label, "bc[0] fix ux, uz");
  EXPECT_EQ(bc.extent, "3 nodes");
  EXPECT_EQ(bc.nodes, (std::vector<int>{0, 5, 10}));

  // the box holds the nodes with x >= 1 (9 of them); the pressure acts on the 4 quads within
  const EntrySelection& load = s->entries[1];
  EXPECT_EQ(load.label, "load[0] pressure");
  EXPECT_EQ(load.quads, (std::vector<int>{2, 3, 6, 7}));
  EXPECT_EQ(load.extent, "4 quads of 9 nodes");

  // a displacement probe reads the first node its plane returns, not the three
  const EntrySelection& probe = s->entries[2];
  EXPECT_EQ(probe.label, "probe[0] edge_w");
  ASSERT_EQ(probe.nodes.size(), 1u);
  EXPECT_EQ(probe.extent, "node " + std::to_string(probe.nodes[0]) + " (the first of 3 selected)");
  EXPECT_NEAR(s->mesh.points[probe.nodes[0]].x(), 2.0, 1e-12);

  const EntrySelection& reaction = s->entries[3];
  EXPECT_EQ(reaction.label, "probe[1] support (reaction)");
  EXPECT_EQ(reaction.extent, "summed over 3 nodes");
  EXPECT_EQ(reaction.nodes, (std::vector<int>{0, 5, 10}));

  // a stress probe reads one node too, and its label names the field it reads
  const std::optional<SceneSelections> stress = scene_selections(
      write_scene("plate", kPlate), {"probe[0].quantity=stress", "probe[0].field=N11"}, {});
  ASSERT_TRUE(stress.has_value());
  EXPECT_EQ(stress->entries[2].label, "probe[0] edge_w (N11)");
  EXPECT_EQ(stress->entries[2].nodes, probe.nodes);

  // --set reaches the selections as it reaches the model
  const std::optional<SceneSelections> moved =
      scene_selections(write_scene("plate", kPlate), {"bc[0].point=[2.0, 0.0, 0.0]"}, {});
  ASSERT_TRUE(moved.has_value());
  EXPECT_EQ(moved->entries[0].nodes, (std::vector<int>{4, 9, 14}));
}

TEST(SceneSelections, DynamicScenesListJointsAndArcsAndAHubBeamHasNone) {
  const std::string scenes = std::string(FF_SOURCE_DIR) + "/assets/scenes/";
  const std::optional<SceneSelections> pendulum = scene_selections(scenes + "double_pendulum_shells.toml", {}, {});
  ASSERT_TRUE(pendulum.has_value());
  EXPECT_EQ(pendulum->part_names, (std::vector<std::string>{"I", "II"}));
  std::vector<std::string> labels;
  for (const EntrySelection& e : pendulum->entries) labels.push_back(e.label);
  EXPECT_EQ(labels, (std::vector<std::string>{"probe[0] pointF_z", "joint[0] simple_support to ground",
                                              "joint[1] revolute to 'II'", "arc[0] I", "arc[1] II"}));
  EXPECT_EQ(pendulum->entries[1].nodes.size(), 16u);

  EXPECT_FALSE(scene_selections(scenes + "hub_beam_fem_tau1.toml", {}, {}).has_value());
}

}  // namespace
}  // namespace ff::scene
