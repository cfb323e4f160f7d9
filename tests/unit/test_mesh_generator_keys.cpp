// The [mesh] keys of static shell scenes (core/scene/mesh_generator_keys.h): the bundled paper
// scenes, now written with generator dimensions, build exactly the meshes of the benchmark
// functions they replaced (same node order, bit-identical coordinates), and bad [mesh] input is a
// located error at the exact key.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/mesh/generators.h"
#include "core/scene/mesh_generator_keys.h"
#include "core/scene/shell_scene.h"

using namespace ff;

namespace {

scene::Document scene_document(const std::string& name, const std::vector<std::string>& overrides = {}) {
  return scene::validate_file(scene::shell_static_schema(), std::string(FF_SOURCE_DIR) + "/assets/scenes/" + name + ".toml",
                              overrides);
}

void expect_identical(const mesh::ShellMesh& a, const mesh::ShellMesh& b, const std::string& what) {
  ASSERT_EQ(a.node_count(), b.node_count()) << what;
  ASSERT_EQ(a.quad_count(), b.quad_count()) << what;
  int differ = 0;
  for (int i = 0; i < a.node_count(); ++i)
    differ += a.points[i] != b.points[i] || a.normals[i] != b.normals[i] || a.frames[i] != b.frames[i] || a.fold[i] != b.fold[i];
  EXPECT_EQ(differ, 0) << what << ": nodes differ";
  EXPECT_EQ(a.quads, b.quads) << what;
  ASSERT_EQ(a.patches.size(), b.patches.size()) << what;
  for (std::size_t k = 0; k < a.patches.size(); ++k) {
    EXPECT_EQ(a.patches[k].name, b.patches[k].name) << what;
    EXPECT_EQ(a.patches[k].grid, b.patches[k].grid) << what;
  }
}

std::string mesh_issue(const std::string& toml_mesh) {
  const std::string text = "[scene]\nname = \"t\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\"]\n[[part]]\n" + toml_mesh +
                           "\n[[material]]\nyoungs_modulus = 1.0\nthickness = 0.1\n[[probe]]\nname = \"w\"\n"
                           "direction = [0.0, 0.0, 1.0]\n[solver]\n";
  try {
    const scene::Document d = scene::validate(scene::shell_static_schema(), text, "t.toml");
    if (scene::mesh_from_file(d, 0)) return "file";
    scene::generate_mesh(d, 0);
  } catch (const scene::SceneError& e) {
    return e.issues.at(0).key + ": " + e.issues.at(0).message;
  }
  return "";
}

}  // namespace

TEST(MeshGeneratorKeys, PaperScenesBuildTheBenchmarkMeshesBitForBit) {
  expect_identical(scene::generate_mesh(scene_document("cantilever_rollup"), 0), mesh::cantilever_strip(20, 2), "rollup");
  expect_identical(scene::generate_mesh(scene_document("hemisphere_18deg_h001"), 0), mesh::hemisphere_quarter(16, 16),
                   "hemisphere h001");
  expect_identical(scene::generate_mesh(scene_document("hemisphere_18deg_h004"), 0), mesh::hemisphere_quarter(16, 16),
                   "hemisphere h004");
  expect_identical(scene::generate_mesh(scene_document("pulled_cylinder"), 0), mesh::open_cylinder_octant(24, 16),
                   "pulled cylinder");
  expect_identical(scene::generate_mesh(scene_document("hinged_roof_h127"), 0), mesh::hinged_roof_quarter(16, 16), "roof h127");
  expect_identical(scene::generate_mesh(scene_document("hinged_roof_h635"), 0), mesh::hinged_roof_quarter(16, 16), "roof h635");
  expect_identical(scene::generate_mesh(scene_document("l_plate_force"), 0), mesh::l_plate_simo_fox_rifai(16, 2), "l_plate force");
  expect_identical(scene::generate_mesh(scene_document("l_plate_moment"), 0), mesh::l_plate_simo_fox_rifai(16, 2), "l_plate moment");
  expect_identical(scene::generate_mesh(scene_document("clamped_plate_pressure"), 0), mesh::rectangular_plate(1.0, 1.0, 8, 8),
                   "clamped plate");
  // overrides of the element counts (studies refine mesh.n1 / mesh.n2) reach the generator
  expect_identical(scene::generate_mesh(scene_document("hemisphere_18deg_h004", {"part[0].n1=8", "part[0].n2=4"}), 0),
                   mesh::hemisphere_quarter(8, 4), "hemisphere 8 x 4");
}

TEST(MeshGeneratorKeys, EveryGeneratorBuildsFromItsKeys) {
  EXPECT_EQ(mesh_issue("generator = \"rectangular_plate\"\nlength = 2.0\nwidth = 1.0\norigin = [1.0, 0.0, 0.0]"), "");
  EXPECT_EQ(mesh_issue("generator = \"l_plate\"\nlength = 10.0\nlength2 = 5.0\nwidth = 1.0\nn1 = 4\nn2 = 1"), "");
  EXPECT_EQ(mesh_issue("generator = \"folded_plate\"\nlength = 2.0\nlength2 = 1.0\nwidth = 1.0\nfold_angle = 60.0\nn3 = 3"), "");
  EXPECT_EQ(mesh_issue("generator = \"cylinder\"\nradius = 1.0\nlength = 2.0\nn1 = 12\nn2 = 2"), "");
  EXPECT_EQ(mesh_issue("generator = \"cylinder\"\nradius = 1.0\nlength = 2.0\nslit = true\nn1 = 12\nn2 = 2"), "");
  EXPECT_EQ(mesh_issue("generator = \"annulus\"\nradius = 10.0\ninner_radius = 6.0\nslit = true\nn1 = 2\nn2 = 12"), "");
  EXPECT_EQ(mesh_issue("generator = \"annulus\"\nradius = 1.0\nn1 = 2\nn2 = 16"), "");  // disk
  EXPECT_EQ(mesh_issue("generator = \"spherical_cap\"\nradius = 1.0\npolar_end = 60.0\nn1 = 3\nn2 = 16"), "");
  EXPECT_EQ(mesh_issue("generator = \"spherical_cap\"\nradius = 1.0\npolar_start = 10.0\npolar_end = 60.0\n"
                       "start_angle = 0.0\nend_angle = 45.0\nn1 = 3\nn2 = 3"),
            "");
  EXPECT_EQ(mesh_issue("generator = \"file\"\nfile = \"x.obj\""), "file");
}

TEST(MeshGeneratorKeys, BadMeshInputNamesTheExactKey) {
  auto starts = [](const std::string& s, const std::string& key) { return s.rfind(key, 0) == 0; };
  std::string e = mesh_issue("generator = \"rectangular_plate\"\nlength = 2.0\nwidth = 1.0\nradius = 3.0");
  EXPECT_TRUE(starts(e, "part[0].radius: part.radius does not belong to generator = \"rectangular_plate\"")) << e;
  e = mesh_issue("generator = \"cylinder\"\nlength = 2.0");
  EXPECT_TRUE(starts(e, "part[0].generator: generator = \"cylinder\" needs part.radius")) << e;
  e = mesh_issue("generator = \"spherical_cap\"\nradius = 1.0");
  EXPECT_TRUE(starts(e, "part[0].generator: generator = \"spherical_cap\" needs part.polar_end")) << e;
  e = mesh_issue("generator = \"annulus\"\nradius = 10.0\ninner_radius = 6.0\nend_angle = 180.0\nslit = true");
  EXPECT_TRUE(starts(e, "part[0].slit: a slit is the seam of a closed 360 degree surface")) << e;
  e = mesh_issue("generator = \"annulus\"\nradius = 1.0\ninner_radius = 2.0");
  EXPECT_TRUE(starts(e, "part[0].inner_radius:")) << e;
  e = mesh_issue("generator = \"cylinder\"\nradius = 1.0\nlength = 1.0\nstart_angle = 10.0\nend_angle = 10.0");
  EXPECT_TRUE(starts(e, "part[0].end_angle:")) << e;
  e = mesh_issue("generator = \"cylinder\"\nradius = 1.0\nlength = 1.0\nend_angle = 400.0");
  EXPECT_TRUE(starts(e, "part[0].end_angle:")) << e;
  e = mesh_issue("generator = \"cylinder\"\nradius = 1.0\nlength = 1.0\nreference = [0.0, 0.0, 2.0]");
  EXPECT_TRUE(starts(e, "part[0].reference:")) << e;
  e = mesh_issue("generator = \"spherical_cap\"\nradius = 1.0\npolar_start = 50.0\npolar_end = 40.0");
  EXPECT_TRUE(starts(e, "part[0].polar_end:")) << e;
  e = mesh_issue("generator = \"spherical_cap\"\nradius = 1.0\npolar_end = 40.0\nend_angle = 60.0\nn2 = 4");
  EXPECT_TRUE(starts(e, "part[0].generator:") && e.find("90, 180 or 360") != std::string::npos) << e;
  e = mesh_issue("generator = \"l_plate\"\nlength = 10.0\nwidth = 30.0");
  EXPECT_TRUE(starts(e, "part[0].length:")) << e;
  e = mesh_issue("generator = \"file\"\nfile = \"x.obj\"\nn1 = 3");
  EXPECT_TRUE(starts(e, "part[0].n1: part.n1 does not belong to generator = \"file\"")) << e;
  e = mesh_issue("generator = \"cylinder\"\nradius = 1.0\nlength = 1.0\nfile = \"x.obj\"");
  EXPECT_TRUE(starts(e, "part[0].file:")) << e;
}

// Issue 30: shapes that were accepted and then ended "singular matrix" (or were swept backwards,
// or overflowed into an empty selection) are refused at the key that made them
TEST(MeshGeneratorKeys, ShapesThatCannotBeSolvedNameTheirKey) {
  auto starts = [](const std::string& s, const std::string& key) { return s.rfind(key, 0) == 0; };
  const std::string cyl = "generator = \"cylinder\"\nradius = 1.0\nlength = 1.0\n";
  std::string e = mesh_issue(cyl + "n1 = 1\nn2 = 2");
  EXPECT_TRUE(starts(e, "part[0].n1:") && e.find("at least 3") != std::string::npos) << e;
  e = mesh_issue(cyl + "n1 = 2\nn2 = 2\nslit = true");
  EXPECT_TRUE(starts(e, "part[0].n1:")) << e;
  EXPECT_EQ(mesh_issue(cyl + "n1 = 3\nn2 = 2"), "");  // 120 degrees an element: the fewest around
  e = mesh_issue("generator = \"annulus\"\nradius = 1.0\ninner_radius = 0.5\nslit = true\nn1 = 2\nn2 = 2");
  EXPECT_TRUE(starts(e, "part[0].n2:")) << e;
  e = mesh_issue("generator = \"annulus\"\nradius = 1.0\ninner_radius = 0.5\nn1 = 2\nn2 = 1");
  EXPECT_TRUE(starts(e, "part[0].n2:")) << e;
  e = mesh_issue("generator = \"cylinder\"\nradius = 1.0\nlength = 1e-12");
  EXPECT_TRUE(starts(e, "part[0].length:") && e.find("times longer") != std::string::npos) << e;
  e = mesh_issue(cyl + "end_angle = 1e-10");
  EXPECT_TRUE(starts(e, "part[0].end_angle:")) << e;
  e = mesh_issue("generator = \"cylinder\"\nradius = 1e-12\nlength = 1.0");
  EXPECT_TRUE(starts(e, "part[0].radius:")) << e;
  e = mesh_issue("generator = \"rectangular_plate\"\nlength = 1.0\nwidth = 1e-9");
  EXPECT_TRUE(starts(e, "part[0].width:")) << e;
  e = mesh_issue("generator = \"l_plate\"\nlength = 10.0\nlength2 = 0.5000001\nwidth = 1.0\nn1 = 4\nn2 = 1");
  EXPECT_TRUE(starts(e, "part[0].length2:")) << e;
  e = mesh_issue("generator = \"folded_plate\"\nlength = 1.0\nlength2 = 1e-9\nwidth = 1.0");
  EXPECT_TRUE(starts(e, "part[0].length2:")) << e;
  e = mesh_issue("generator = \"annulus\"\nradius = 1.0\ninner_radius = 0.9999999999\nn1 = 2\nn2 = 16");
  EXPECT_TRUE(starts(e, "part[0].inner_radius:")) << e;
  e = mesh_issue(cyl + "start_angle = 90.0\nend_angle = 0.0");
  EXPECT_TRUE(starts(e, "part[0].end_angle:") && e.find("runs backwards") != std::string::npos) << e;
  e = mesh_issue("generator = \"cylinder\"\nradius = 1e200\nlength = 1e200");
  EXPECT_TRUE(starts(e, "part[0].length:") || starts(e, "part[0].radius:")) << e;
  e = mesh_issue("generator = \"cylinder\"\nradius = 1e200\nlength = 1.0");
  EXPECT_TRUE(starts(e, "part[0].radius:") && e.find("outside the lengths") != std::string::npos) << e;
  e = mesh_issue("generator = \"rectangular_plate\"\nlength = 1.0\nwidth = 1.0\norigin = [0.0, 1e300, 0.0]");
  EXPECT_TRUE(starts(e, "part[0].origin:")) << e;
  e = mesh_issue("generator = \"spherical_cap\"\nradius = 1.0\npolar_start = 1e-12\npolar_end = 90.0");
  EXPECT_TRUE(starts(e, "part[0].polar_start:")) << e;
  e = mesh_issue("generator = \"spherical_cap\"\nradius = 1.0\npolar_start = 1e-5\npolar_end = 90.0");
  EXPECT_TRUE(starts(e, "part[0].polar_start:") && e.find("times longer") != std::string::npos) << e;
  e = mesh_issue("generator = \"spherical_cap\"\nradius = 1.0\npolar_end = 179.9999999999");
  EXPECT_TRUE(starts(e, "part[0].polar_end:")) << e;
}

TEST(MeshGeneratorKeys, EdgeNamesSelectInScenesAndTyposNameTheEntry) {
  auto scene = [](const std::string& edge) {
    return "[scene]\nname = \"t\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\"]\n[[part]]\ngenerator = \"spherical_cap\"\n"
           "radius = 1.0\npolar_start = 30.0\npolar_end = 90.0\nend_angle = 90.0\nn1 = 2\nn2 = 2\n"
           "[[material]]\nyoungs_modulus = 1.0\nthickness = 0.1\n"
           "[[bc]]\ntype = \"clamped\"\nselect = \"patch_edge\"\npatch = \"cap\"\nedge = \"" + edge + "\"\n"
           "[[load]]\ntype = \"force\"\ntotal = [0.0, 0.0, 1e-6]\nselect = \"nearest\"\npoint = [0.5, 0.0, 0.866]\n"
           "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\npoint = [0.5, 0.0, 0.866]\n[solver]\n";
  };
  const scene::Document good = scene::validate(scene::shell_static_schema(), scene("rim"), "t.toml");
  EXPECT_NO_THROW(scene::build_shell_static(good, "t.toml", {}));
  const scene::Document bad = scene::validate(scene::shell_static_schema(), scene("rimm"), "t.toml");
  try {
    scene::build_shell_static(bad, "t.toml", {});
    ADD_FAILURE() << "edge = \"rimm\" was accepted";
  } catch (const scene::SceneError& e) {
    EXPECT_EQ(e.issues.at(0).key, "bc[0].edge");
    EXPECT_GT(e.issues.at(0).line, 0);
    EXPECT_NE(e.issues.at(0).message.find("\"rim\" (u=1)"), std::string::npos) << e.issues.at(0).message;
  }
}
