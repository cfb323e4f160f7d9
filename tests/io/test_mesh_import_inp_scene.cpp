// Abaqus decks as scene parts (app/io/abaqus_inp.h through ff::io::read_mesh_file): the sample
// deck assets/meshes/plate_8x8_s4r.inp is rectangular_plate(1, 1, 8, 8) node for node, so a
// cantilever supported and loaded on its *NSETs by name gives the generator scene's answer,
// supported and loaded by planes, to round-off. Scratch files go to
// ${FF_BINARY_DIR}/test_out/mesh_import_inp/.
#include <gtest/gtest.h>

#include "tests/support/scratch_files.h"

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "app/io/mesh_import.h"
#include "core/scene/scene.h"

namespace fs = std::filesystem;

namespace {

std::string write_text(const std::string& name, const std::string& text) {
  return ff::testing::write_scratch("mesh_import_inp", name, text);
}

const std::string kDeck = std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_s4r.inp";

double tip(const std::string& part, const std::string& support, const std::string& load) {
  const std::string text =
      "[scene]\nname = \"inp\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\", \"hr\", \"ans\"]\n"
      "[[part]]\n" + part + "[[material]]\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.3\nthickness = 0.01\n"
      "[[bc]]\ntype = \"clamped\"\n" + support + "[[load]]\ntype = \"line\"\nper_length = [0.0, 0.0, 1.0e-3]\n" + load +
      "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"nearest\"\npoint = [1.0, 0.5, 0.0]\n"
      "[[metric]]\nname = \"w\"\nkind = \"final\"\nprobe = \"w\"\n[solver]\nmethod = \"linear\"\n";
  ff::scene::LoadedScene s = ff::scene::load_scene(write_text("cantilever.toml", text), {}, ff::io::scene_context());
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run([](ff::Frame&&) {}, stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << o.reason;
  for (const auto& [k, v] : s.simulation->metrics())
    if (k == "w") return v;
  return NAN;
}

}  // namespace

TEST(InpScene, TheSampleDecksSetsAreNamedGroups) {
  ff::scene::MeshFileRequest q;
  q.path = kDeck;
  ff::mesh::ShellMesh m;
  ff::scene::MeshFileError e;
  ASSERT_TRUE(ff::io::read_mesh_file(q, m, e)) << e.message;
  EXPECT_EQ(m.quad_count(), 64);
  EXPECT_EQ(m.node_count(), 81);
  ASSERT_GE(m.find_group("CLAMPED"), 0);
  ASSERT_GE(m.find_group("LOADED"), 0);
  ASSERT_GE(m.find_group("PLATE"), 0);
  EXPECT_EQ(m.groups[m.find_group("CLAMPED")].nodes.size(), 9u);
  for (int i : m.groups[m.find_group("CLAMPED")].nodes) { EXPECT_EQ(m.points[i].x(), 0.0); }
  EXPECT_EQ(m.groups[m.find_group("PLATE")].quads.size(), 64u);
  EXPECT_NE(m.patches[0].description.find("Abaqus"), std::string::npos) << m.patches[0].description;
}

TEST(InpScene, ACantileverOnTheDecksSetsMatchesTheGeneratorScene) {
  const double from_deck = tip("generator = \"file\"\nfile = \"" + kDeck + "\"\n", "select = \"group\"\ngroup = \"CLAMPED\"\n",
                               "select = \"group\"\ngroup = \"LOADED\"\n");
  const double generated = tip("generator = \"rectangular_plate\"\nlength = 1.0\nwidth = 1.0\nn1 = 8\nn2 = 8\n",
                               "select = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n",
                               "select = \"plane\"\npoint = [1.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n");
  ASSERT_GT(generated, 0.0);
  EXPECT_NEAR(from_deck / generated, 1.0, 1e-9) << from_deck << " vs " << generated;
}

// Abaqus keeps node and element sets apart and tools write both under one name: one group
TEST(InpScene, ANodeSetAndAnElementSetOfOneNameAreOneGroup) {
  const std::string deck = write_text("same_name.inp",
                                      "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n5, 2, 0, 0\n6, 2, 1, 0\n"
                                      "*ELEMENT, TYPE=S4R, ELSET=Set-1\n1, 1, 2, 3, 4\n*ELEMENT, TYPE=S4R\n2, 2, 5, 6, 3\n"
                                      "*NSET, NSET=Set-1\n5, 6\n");
  ff::scene::MeshFileRequest q;
  q.path = deck;
  ff::mesh::ShellMesh m;
  ff::scene::MeshFileError e;
  ASSERT_TRUE(ff::io::read_mesh_file(q, m, e)) << e.message;
  ASSERT_EQ(m.groups.size(), 1u);
  EXPECT_EQ(m.groups[0].name, "Set-1");
  EXPECT_EQ(m.groups[0].quads.size(), 1u);
  EXPECT_EQ(m.groups[0].nodes.size(), 6u) << "the element's 4 corners and the node set's 2 nodes";
}

TEST(InpScene, AKeywordOutsideTheSubsetIsRefusedAtItsLineThroughTheScene) {
  const std::string deck = write_text("material.inp", "*NODE\n1, 0, 0, 0\n2, 1, 0, 0\n3, 1, 1, 0\n4, 0, 1, 0\n"
                                                      "*ELEMENT, TYPE=S4R\n1, 1, 2, 3, 4\n*MATERIAL, NAME=steel\n");
  const std::string scene = write_text(
      "material.toml", "[scene]\nname = \"inp\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\"]\n"
                       "[[part]]\ngenerator = \"file\"\nfile = \"" + deck + "\"\n"
                       "[[material]]\nyoungs_modulus = 1.0e6\npoisson_ratio = 0.3\nthickness = 0.01\n"
                       "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"all\"\n[solver]\nmethod = \"linear\"\n");
  try {
    ff::scene::load_scene(scene, {}, ff::io::scene_context());
    ADD_FAILURE() << "accepted";
  } catch (const ff::scene::SceneError& err) {
    ASSERT_FALSE(err.issues.empty());
    EXPECT_EQ(err.issues[0].key, "part[0].file");
    EXPECT_NE(err.issues[0].message.find("line 8: *MATERIAL is not read"), std::string::npos) << err.issues[0].message;
  }
}
