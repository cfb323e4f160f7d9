// Saving an edited scene: the overrides are folded into the file's text, comments and layout
// stay, missing keys and tables are added, and the text reads back to the edited values.
#include <gtest/gtest.h>

#include <filesystem>
#include <set>
#include <fstream>
#include <sstream>

#include "app/gui/param_editor.h"
#include "core/scene/scene.h"
#include "core/scene/scene_edit.h"

namespace ff::scene {
namespace {

const std::string kScenes = std::string(FF_SOURCE_DIR) + "/assets/scenes/";

std::string write_temp(const std::string& name, const std::string& text) {
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out/gui";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + name;
  std::ofstream(path) << text;
  return path;
}

TEST(SceneEdit, ReplacesValuesInPlaceAndKeepsComments) {
  const std::string path = kScenes + "hub_beam_fem_tau1.toml";
  const std::vector<std::string> edits = {"solver.dt=0.02", "fem.elements=12", "torque.amplitude=2.5",
                                          "scene.effects=[\"inertia\", \"bending\", \"axial\", \"hub_torque\"]"};
  const std::string text = scene_text_with_overrides(path, edits);
  EXPECT_NE(text.find("dt = 0.02\n"), std::string::npos) << text;
  EXPECT_NE(text.find("elements = 12\n"), std::string::npos) << text;
  EXPECT_NE(text.find("amplitude = 2.5       # tau0 [N m]"), std::string::npos) << text;
  EXPECT_NE(text.find("# Source: Xie & Jian (2017)"), std::string::npos) << "comments kept";
  const Document d = validate(scene_schema(path), text, "saved.toml");
  EXPECT_DOUBLE_EQ(d.number("solver.dt"), 0.02);
  EXPECT_EQ(d.integer("fem.elements"), 12);
  EXPECT_EQ(d.strings("scene.effects").size(), 4u);
  // the saved file builds and runs like the original with --set
  const std::string saved = write_temp("saved_hub_beam.toml", text);
  EXPECT_NO_THROW(check_scene(saved));
}

TEST(SceneEdit, AddsMissingKeysAndTables) {
  const std::string path = write_temp("sparse.toml",
                                      "# sparse scene\n"
                                      "[scene]\n"
                                      "name = \"sparse\"\n"
                                      "model = \"hub_beam\"\n"
                                      "effects = [\"inertia\", \"bending\", \"axial\", \"hub_torque\"]\n"
                                      "\n"
                                      "[solver]\n"
                                      "dt = 0.05\n");
  const std::vector<std::string> edits = {"solver.end=2.0", "beam.length=2.0", "solver.dt=0.01"};
  const std::string text = scene_text_with_overrides(path, edits);
  const Document d = validate(scene_schema(path), text, "saved.toml");
  EXPECT_DOUBLE_EQ(d.number("solver.end"), 2.0);
  EXPECT_DOUBLE_EQ(d.number("beam.length"), 2.0);
  EXPECT_DOUBLE_EQ(d.number("solver.dt"), 0.01);
  EXPECT_NE(text.find("# sparse scene"), std::string::npos) << text;
}

TEST(SceneEdit, ArrayElementsAndBadEdits) {
  const std::string path = kScenes + "double_pendulum_shells.toml";
  const std::string text = scene_text_with_overrides(path, {"part[1].n1=8", "solver.end=0.1"});
  const Document d = validate(scene_schema(path), text, "saved.toml");
  EXPECT_EQ(d.integer("part.n1", 1), 8);
  EXPECT_EQ(d.integer("part.n1", 0), 15);
  EXPECT_DOUBLE_EQ(d.number("solver.end"), 0.1);
  EXPECT_NE(text.find("# Double pendulum of two cut cylindrical shells"), std::string::npos);
  EXPECT_THROW(scene_text_with_overrides(path, {"solver.dt=-1"}), SceneError);
}

TEST(SceneParams, EveryModelListsItsKeys) {
  for (const char* name : {"hub_beam_efg_tau1", "double_pendulum_shells", "hemisphere_18deg_h004"}) {
    const std::string path = kScenes + name + ".toml";
    const std::string text = read_scene_text(path);
    const auto items = app::gui::scene_params(text, path, text);
    ASSERT_FALSE(items.empty()) << name;
    bool has_effects = false;
    for (const auto& it : items) {
      EXPECT_NE(it.key, "scene.model");
      ASSERT_NE(it.spec, nullptr) << it.key;
      has_effects = has_effects || it.key == "scene.effects";
    }
    EXPECT_TRUE(has_effects) << name;
  }
  const std::string pendulum = kScenes + "double_pendulum_shells.toml";
  const auto shells = app::gui::scene_params(edited_scene_text(read_scene_text(pendulum), pendulum, {"part[1].n1=8"}),
                                             pendulum, read_scene_text(pendulum));
  bool found = false;
  for (const auto& it : shells) {
    if (it.key != "part[1].n1") continue;
    found = true;
    EXPECT_EQ(it.value, "8");
    EXPECT_TRUE(it.edited);
    EXPECT_EQ(it.group, "part[1]");
  }
  EXPECT_TRUE(found);
}

// Only the keys that serve an entry's choices are listed: a plate's dimensions, not a cap's; a
// plane selection's point and normal, not a box's corners or a patch edge. (Every generator key was
// listed for every generator, and every selector key for every select.)
TEST(SceneParams, ListsOnlyTheKeysOfTheChosenGeneratorAndSelection) {
  const std::string path = kScenes + "clamped_plate_pressure.toml";
  const std::string text = read_scene_text(path);
  std::set<std::string> keys;
  for (const auto& it : app::gui::scene_params(text, path, text)) keys.insert(it.key);
  for (const char* k : {"part[0].length", "part[0].width", "part[0].n1", "bc[0].point", "bc[0].normal", "load[0].select"})
    EXPECT_TRUE(keys.count(k)) << k;
  for (const char* k : {"part[0].radius", "part[0].polar_end", "part[0].file", "bc[0].box_min", "bc[0].edge",
                        "bc[0].group", "bc[0].nodes", "load[0].point"})
    EXPECT_FALSE(keys.count(k)) << k;
}

// A refused edit is reworded for the window: no "--set KEY=VALUE:" or "key '...':" CLI syntax,
// the key and value named once, the reason kept, and that nothing changed.
TEST(GuiRefusal, ReadsAsAWindowMessage) {
  const auto r = app::gui::readable_refusal(
      "set solver.dt = -1 refused:\n--set solver.dt=-1: key 'solver.dt': expected a number > 0, got -1");
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->key, "solver.dt");
  EXPECT_EQ(r->text,
            "solver.dt = -1 was not applied: expected a number > 0, got -1. Nothing changed; the run goes on as it was.");
  const auto load = app::gui::readable_refusal("load x.toml refused:\nx.toml: cannot read the file");
  ASSERT_TRUE(load.has_value());
  EXPECT_EQ(load->key, "");
  EXPECT_EQ(load->text, "Could not load x.toml: x.toml: cannot read the file. Nothing changed.");
  EXPECT_FALSE(app::gui::readable_refusal("saved a.toml").has_value());
}

// The worker's own refusal text, as the window receives it, reads without CLI syntax.
TEST(GuiRefusal, WorkerRefusalHasNoCliSyntax) {
  const std::string scene = kScenes + "hub_beam_fem_tau1.toml";
  std::string error;
  try {
    load_scene(scene, {"torque.amplitude=fast"});
  } catch (const std::exception& e) {
    error = e.what();
  }
  ASSERT_FALSE(error.empty());
  const auto r = app::gui::readable_refusal("set torque.amplitude = fast refused:\n" + error);
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->text.find("--set"), std::string::npos) << r->text;
  EXPECT_EQ(r->text.find("key '"), std::string::npos) << r->text;
  EXPECT_NE(r->text.find("torque.amplitude = fast was not applied: expected a number in [0, 1e+100]"), std::string::npos)
      << r->text;
}

}  // namespace
}  // namespace ff::scene
