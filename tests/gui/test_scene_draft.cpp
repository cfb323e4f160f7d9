// Setting a problem up in the window (app/gui/scene_draft.h): every edit turns the scene text
// into a new one that validates and builds, keeps the rest of the text (comments included), drops
// what no longer applies and says so; live edits become [[timeline]] entries in their place.
#include <gtest/gtest.h>

#include <set>

#include "app/gui/scene_draft.h"
#include "app/io/mesh_import.h"
#include "app/gui/setup_panel.h"
#include "core/scene/scene.h"
#include "core/scene/scene_edit.h"
#include "core/scene/scene_selections.h"

namespace ff::app::gui {
namespace {

const std::string kScenes = std::string(FF_SOURCE_DIR) + "/assets/scenes/";
const std::string kPath = std::string(FF_BINARY_DIR) + "/test_out/gui/draft.toml";

scene::Document doc(const std::string& text) { return scene::validate(scene::schema_for_text(text), text, kPath); }

/// The text builds a model, as the solver thread would.
void expect_builds(const std::string& text) {
  try {
    scene::load_scene_text(text, kPath, {}, io::scene_context());  // with the executable's mesh reader
  } catch (const std::exception& e) {
    ADD_FAILURE() << e.what() << "\n--- text ---\n" << text;
  }
}

TEST(SceneDraft, NewProblemsBuild) {
  for (const char* analysis : {"static", "dynamic"}) {
    const std::string text = new_scene_text(analysis, "fresh");
    expect_builds(text);
    const scene::Document d = doc(text);
    EXPECT_EQ(d.string("scene.name"), "fresh");
    EXPECT_EQ(d.string("scene.analysis"), analysis);
    EXPECT_EQ(d.count("part"), 1u);
    EXPECT_EQ(d.count("bc"), 0u);  // supports are the user's to add
  }
  EXPECT_THROW(new_scene_text("modal", "x"), std::invalid_argument);
}

// A mesh file dropped on the window becomes a new problem's part; its force finds the nearest node.
TEST(SceneDraft, AMeshFileBecomesANewProblem) {
  const std::string mesh = std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_unit.obj";
  const std::string text = mesh_scene_text(mesh, "plate_8x8_unit");
  const scene::Document d = doc(text);
  EXPECT_EQ(d.string("part.generator", 0), "file");
  EXPECT_EQ(d.string("part.file", 0), mesh);
  EXPECT_FALSE(d.present("part.length", 0));
  expect_builds(text);
}

// Each template validates and builds on the new problem's plate; names stay unique.
TEST(SceneDraft, EveryAddedEntryBuilds) {
  for (const char* analysis : {"static", "dynamic"}) {
    std::string text = new_scene_text(analysis, "fresh");
    for (const std::string& table : addable_tables(scene::schema_for_text(text))) {
      if (table == "metric" && doc(text).count("probe") == 0) text = with_entry_added(text, kPath, "probe").text;
      const std::size_t before = doc(text).count(table);
      text = with_entry_added(text, kPath, table).text;
      EXPECT_EQ(doc(text).count(table), before + 1) << table;
    }
    if (std::string(analysis) == "dynamic") text = with_key_set(text, kPath, "scene.effects",
                                                                 "[\"elastic\", \"inertia\", \"gravity\", \"hr\", \"ans\", \"joints\"]").text;
    // a second part and material need naming: the parts say which material they are made of
    const scene::Document d = doc(text);
    ASSERT_EQ(d.count("part"), 2u);
    EXPECT_NE(d.string("part.name", 0), d.string("part.name", 1));
    EXPECT_NE(d.string("material.name", 0), d.string("material.name", 1));
    text = with_key_set(text, kPath, "part[0].material", d.string("material.name", 0)).text;
    text = with_key_set(text, kPath, "part[1].material", d.string("material.name", 1)).text;
    expect_builds(text);
  }
  // two probes get two names
  std::string text = new_scene_text("static", "fresh");
  text = with_entry_added(text, kPath, "probe").text;
  EXPECT_NE(doc(text).string("probe.name", 0), doc(text).string("probe.name", 1));
  EXPECT_THROW(with_entry_added(text, kPath, "rigid"), std::invalid_argument);
  EXPECT_THROW(with_entry_added(new_scene_text("dynamic", "d"), kPath, "metric"), std::invalid_argument);  // no probe
}

// Fields given with `add` replace the template's, and template keys that do not serve the final
// selection are left out (no point with select = "patch_edge").
TEST(SceneDraft, AddedFieldsReplaceTheTemplate) {
  const std::string text =
      with_entry_added(new_scene_text("static", "fresh"), kPath, "bc", {{"select", "patch_edge"}, {"edge", "x_min"}}).text;
  const scene::Document d = doc(text);
  EXPECT_EQ(d.string("bc.select", 0), "patch_edge");
  EXPECT_EQ(d.string("bc.edge", 0), "x_min");
  EXPECT_FALSE(d.present("bc.point", 0));
  EXPECT_FALSE(d.present("bc.normal", 0));
  expect_builds(text);
}

// Removing an entry keeps the others and their comments; the last part cannot go.
TEST(SceneDraft, RemovingKeepsTheRest) {
  const std::string path = kScenes + "clamped_plate_pressure.toml";
  const std::string text = scene::read_scene_text(path);
  const DraftEdit e = with_entry_removed(text, path, "bc", 1);
  const scene::Document before = doc(text), after = doc(e.text);
  ASSERT_EQ(after.count("bc"), 3u);
  for (std::size_t i : {0u, 1u, 2u}) {
    const std::size_t was = i == 0 ? 0 : i + 1;  // bc[1] is gone
    EXPECT_EQ(after.value_text("bc.point", i), before.value_text("bc.point", was));
    EXPECT_EQ(after.value_text("bc.normal", i), before.value_text("bc.normal", was));
  }
  EXPECT_NE(e.text.find("# Pa at lambda = 1, along +z"), std::string::npos) << "comments of other entries kept";
  EXPECT_NE(e.text.find("# Clamped square plate"), std::string::npos);
  EXPECT_THROW(with_entry_removed(text, path, "part", 0), std::invalid_argument);
  EXPECT_THROW(with_entry_removed(text, path, "bc", 7), std::invalid_argument);
}

// A generator switch drops the old generator's dimensions and adds the new one's required keys.
// It used to be refused: "part.polar_start does not belong to generator = cylinder".
TEST(SceneDraft, GeneratorSwitchDropsKeysThatNoLongerApply) {
  const std::string path = kScenes + "hemisphere_18deg_h004.toml";
  const std::string text = scene::read_scene_text(path);
  ASSERT_TRUE(doc(text).present("part.polar_start", 0));
  const DraftEdit e = with_key_set(text, path, "part[0].generator", "cylinder");
  const scene::Document d = doc(e.text);
  EXPECT_EQ(d.string("part.generator", 0), "cylinder");
  EXPECT_FALSE(d.present("part.polar_start", 0));
  EXPECT_FALSE(d.present("part.polar_end", 0));
  EXPECT_TRUE(d.present("part.length", 0));  // a cylinder needs it
  EXPECT_NE(e.note.find("part[0].polar_start"), std::string::npos) << e.note;
  EXPECT_NE(e.note.find("added part[0].length"), std::string::npos) << e.note;
  // the part's mesh builds (the scene's own supports name the cap's edges and are the user's to redo)
  const std::string plate = with_key_set(new_scene_text("static", "p"), kPath, "part[0].generator", "spherical_cap").text;
  EXPECT_FALSE(doc(plate).present("part.length", 0));
  EXPECT_FALSE(doc(plate).present("part.width", 0));
  EXPECT_TRUE(doc(plate).present("part.radius", 0));
  EXPECT_TRUE(doc(plate).present("part.polar_end", 0));
}

TEST(SceneDraft, SelectionSwitchDropsTheOldSelectorsKeys) {
  const std::string path = kScenes + "clamped_plate_pressure.toml";
  const DraftEdit e = with_key_set(scene::read_scene_text(path), path, "bc[0].select", "patch_edge");
  const scene::Document d = doc(e.text);
  EXPECT_FALSE(d.present("bc.point", 0));
  EXPECT_FALSE(d.present("bc.normal", 0));
  EXPECT_TRUE(d.present("bc.point", 1));  // the other supports keep theirs
  EXPECT_NE(e.note.find("bc[0].point"), std::string::npos) << e.note;
  expect_builds(e.text);  // the only patch's u=0 edge
}

// Picked nodes become select = "nodes": the support then acts on exactly those nodes.
TEST(SceneDraft, PickedNodesBecomeTheSelection) {
  std::string text = with_entry_added(new_scene_text("static", "fresh"), kPath, "bc").text;
  const std::set<int> picked = {0, 9, 18, 27};  // the plate's x = 0 edge, every other node
  text = use_picked_nodes("bc[0]", picked).op(text, kPath).text;
  const scene::Document d = doc(text);
  EXPECT_EQ(d.string("bc.select", 0), "nodes");
  EXPECT_FALSE(d.present("bc.point", 0));
  const auto sel = scene::scene_selections_of_text(text, kPath, {}, {});
  ASSERT_TRUE(sel.has_value());
  ASSERT_FALSE(sel->entries.empty());
  EXPECT_EQ(sel->entries[0].table, "bc");
  EXPECT_EQ(sel->entries[0].nodes, std::vector<int>(picked.begin(), picked.end()));
  // a node the structure does not have is refused at the key
  const std::string bad = with_key_set(text, kPath, "bc[0].nodes", "[0, 81]").text;
  try {
    scene::load_scene_text(bad, kPath);
    ADD_FAILURE() << "node 81 of an 81-node plate was accepted";
  } catch (const scene::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("bc[0].nodes"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("0 to 80"), std::string::npos) << e.what();
  }
}

// An edge picked from the list of the generators' edge names: select = "patch_edge".
TEST(SceneDraft, AnEdgeFromTheListBecomesTheSelection) {
  std::string text = with_entry_added(new_scene_text("static", "fresh"), kPath, "bc").text;
  text = use_patch_edge("bc[0]", "plate", "x_max").op(text, kPath).text;
  const scene::Document d = doc(text);
  EXPECT_EQ(d.string("bc.select", 0), "patch_edge");
  EXPECT_EQ(d.string("bc.edge", 0), "x_max");
  EXPECT_FALSE(d.present("bc.normal", 0));
  const auto sel = scene::scene_selections_of_text(text, kPath, {}, {});
  ASSERT_TRUE(sel.has_value());
  ASSERT_FALSE(sel->entries.empty());
  EXPECT_EQ(sel->entries[0].nodes.size(), 9u);  // the 9 nodes of the 8 x 8 plate's edge x = 1
  for (int n : sel->entries[0].nodes) { EXPECT_DOUBLE_EQ(sel->mesh.points[n].x(), 1.0); }
}

// What "show" marks: every entry's nodes but those of an entry acting on every node (a pressure
// on the whole plate would cover the supports' marks), one entry alone, or none.
TEST(SceneDraft, ShownNodesLeaveOutEntriesActingOnEveryNode) {
  const std::string path = kScenes + "clamped_plate_pressure.toml";  // 4 clamped edges, pressure on all
  const std::string text = scene::read_scene_text(path);
  WorkerStatus status;
  const auto sel = scene::scene_selections_of_text(text, path, {}, {});
  ASSERT_TRUE(sel.has_value());
  status.selections = std::make_shared<const std::vector<scene::EntrySelection>>(sel->entries);
  RunInfo info;
  info.mesh.reference_points.assign(3 * static_cast<std::size_t>(sel->mesh.node_count()), 0.0);
  status.info = std::make_shared<const RunInfo>(info);
  const std::vector<int> all = shown_nodes(status, "all");
  EXPECT_EQ(all.size(), 33u);  // the 32 boundary nodes of a 9 x 9 grid and the probed centre
  EXPECT_EQ(shown_nodes(status, "load[0]").size(), 81u);  // alone, the pressure marks every node
  EXPECT_EQ(shown_nodes(status, "bc[1]").size(), 9u);
  EXPECT_TRUE(shown_nodes(status, "none").empty());
}

TEST(SceneDraft, MaterialPresetsReplaceTheElasticKeys) {
  const std::string text = new_scene_text("dynamic", "fresh");
  const DraftEdit al = with_material_preset(text, kPath, 0, "aluminium");
  EXPECT_EQ(doc(al.text).number("material.youngs_modulus", 0), 7.0e10);
  EXPECT_EQ(doc(al.text).number("material.density", 0), 2700.0);
  EXPECT_EQ(doc(al.text).number("material.thickness", 0), 0.01);  // kept
  EXPECT_EQ(doc(al.text).string("material.name", 0), "aluminium");    // no part names it: renamed
  const DraftEdit ply = with_material_preset(al.text, kPath, 0, "CFRP ply (T300/5208)");
  const scene::Document d = doc(ply.text);
  EXPECT_FALSE(d.present("material.youngs_modulus", 0));
  EXPECT_FALSE(d.present("material.poisson_ratio", 0));
  EXPECT_EQ(d.number("material.e1", 0), 1.81e11);
  EXPECT_NE(ply.note.find("Tsai & Hahn"), std::string::npos) << "the preset says where its numbers come from";
  // orthotropic plies have no default fibre direction: the preset writes one and says which it is
  EXPECT_EQ(d.string("part.fibre_reference", 0), "u");
  EXPECT_TRUE(d.present("part.fibre_reference", 0));
  EXPECT_NE(ply.note.find("part[0].fibre_reference = \"u\" written"), std::string::npos) << ply.note;
  expect_builds(ply.text);
  EXPECT_THROW(with_material_preset(text, kPath, 0, "unobtainium"), std::invalid_argument);
  EXPECT_THROW(with_material_preset(text, kPath, 3, "steel"), std::invalid_argument);
}

// Live edits are [[timeline]] entries in ascending order of `at`; one at the time of an entry
// is merged into it (`at` must be strictly ascending).
TEST(SceneDraft, LiveEditsBecomeTimelineEntriesInOrder) {
  const std::string path = kScenes + "hub_beam_timeline.toml";  // entries at 0, 1.23, 2.5
  std::string text = scene::read_scene_text(path);
  const double tau0 = doc(text).number("torque.amplitude");
  text = with_live_edit(text, path, "torque.amplitude", "0.5", 0.5).text;
  text = with_live_edit(text, path, "torque.amplitude", "2", 1.23).text;
  scene::Document d = doc(text);
  ASSERT_EQ(d.count("timeline"), 4u);
  EXPECT_EQ(d.number("timeline.at", 1), 0.5);
  EXPECT_EQ(d.number("timeline.torque_scale", 1), 0.5 / tau0);
  EXPECT_EQ(d.number("timeline.at", 2), 1.23);
  EXPECT_EQ(d.number("timeline.torque_scale", 2), 2.0 / tau0);  // merged into the switch-off entry
  expect_builds(text);  // read_timeline checks the order
  EXPECT_NE(text.find("# the drive stops"), std::string::npos) << "comments kept";

  std::string shells = new_scene_text("dynamic", "fresh");
  shells = with_live_edit(shells, kPath, "gravity.g", "[0.0, 0.0, -1.0]", 0.25).text;
  d = doc(shells);
  ASSERT_EQ(d.count("timeline"), 1u);
  EXPECT_EQ(d.numbers("timeline.gravity", 0), (std::vector<double>{0.0, 0.0, -1.0}));
  expect_builds(shells);
  EXPECT_THROW(with_live_edit(shells, kPath, "solver.dt", "0.1", 0.3), scene::SceneError);
}

// A saved scene is named after its file (its own output folder) and says where it came from.
TEST(SceneDraft, SavedTextHasANameOfItsOwn) {
  const std::string path = kScenes + "clamped_plate_pressure.toml";
  const std::string opened = scene::read_scene_text(path);
  const std::string edited = with_key_set(opened, path, "material[0].thickness", "0.02").text;
  const std::string saved = text_to_save(edited, path, "/tmp/thick_plate.toml", opened, path);
  EXPECT_EQ(doc(saved).string("scene.name"), "thick_plate");
  EXPECT_EQ(saved.rfind("# Set up in the flexframe window from " + path, 0), 0u) << saved.substr(0, 200);
  // unedited: no such line
  EXPECT_EQ(text_to_save(opened, path, "/tmp/copy.toml", opened, path).find("# Set up in"), std::string::npos);
  EXPECT_THROW(text_to_save(opened, path, "/tmp/bad name\n.toml", opened, path), std::invalid_argument);
}

}  // namespace
}  // namespace ff::app::gui
