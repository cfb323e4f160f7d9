// A scene with mesh.generator = "file" (assets/scenes/clamped_plate_pressure_obj.toml) runs on the
// mesh assimp imports from assets/meshes/plate_8x8_unit.obj and gives the same answer as the same
// plate built by the generator (clamped_plate_pressure.toml); the OBJ is the generator's mesh as
// ff::io::write_shell_mesh_obj writes it; without a reader or with a bad file the scene error is
// located at mesh.file. Scratch files go to ${FF_BINARY_DIR}/test_out/mesh_import_scene/.
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "app/io/mesh_import.h"
#include "core/mesh/generators.h"
#include "core/scene/mesh_file.h"
#include "core/scene/scene.h"

namespace fs = std::filesystem;

namespace {

std::string scene_file(const std::string& name) { return std::string(FF_SOURCE_DIR) + "/assets/scenes/" + name + ".toml"; }

std::string scratch(const std::string& name) {
  const fs::path dir = fs::path(FF_BINARY_DIR) / "test_out" / "mesh_import_scene";
  fs::create_directories(dir);
  return (dir / name).string();
}

std::string read_text(const std::string& path) {
  std::ifstream f(path);
  std::stringstream s;
  s << f.rdbuf();
  return s.str();
}

double w_centre(const std::string& scene) {
  ff::scene::LoadedScene s = ff::scene::load_scene(scene_file(scene), {}, ff::io::scene_context());
  std::atomic<bool> stop{false};
  const ff::RunOutcome o = s.simulation->run([](ff::Frame&&) {}, stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << o.reason;
  for (const auto& [k, v] : s.simulation->metrics())
    if (k == "w_centre") return v;
  ADD_FAILURE() << scene << ": metric w_centre missing";
  return NAN;
}

// the issues of the SceneError thrown by loading `path` with `overrides`, or none
std::vector<ff::scene::Issue> load_issues(const std::string& path, const std::vector<std::string>& overrides = {},
                                         const ff::scene::SceneContext& ctx = ff::io::scene_context()) {
  try {
    ff::scene::load_scene(path, overrides, ctx);
  } catch (const ff::scene::SceneError& e) {
    return e.issues;
  }
  return {};
}

}  // namespace

// assets/meshes/plate_8x8_unit.obj is write_shell_mesh_obj(rectangular_plate(1, 1, 8, 8)), byte for
// byte; regenerate it by copying the file this test writes (see assets/meshes/README.md).
TEST(MeshImportScene, PlateObjIsTheGeneratorMeshAsWritten) {
  const std::string written = scratch("plate_8x8_unit.obj");
  std::string err;
  ASSERT_TRUE(ff::io::write_shell_mesh_obj(written, ff::mesh::rectangular_plate(1.0, 1.0, 8, 8), &err)) << err;
  EXPECT_EQ(read_text(std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_unit.obj"), read_text(written))
      << "assets/meshes/plate_8x8_unit.obj is out of date: cp " << written << " assets/meshes/";
}

// Same plate, same loads, two mesh sources: the importer numbers nodes by first use and computes the
// directors from the quads (area-weighted, here exactly +z), so the two runs assemble different
// equation orders; the centre deflection agrees to round-off (bound 1e-9 relative).
TEST(MeshImportScene, ImportedPlateMatchesGeneratorPlate) {
  const double w_gen = w_centre("clamped_plate_pressure");
  const double w_obj = w_centre("clamped_plate_pressure_obj");
  std::printf("w_centre: generator %.15e, imported %.15e, rel. diff %.2e\n", w_gen, w_obj, std::abs(w_obj / w_gen - 1));
  EXPECT_GT(w_gen, 1e-6);  // a real deflection (Kirchhoff: 6.55e-6 m)
  EXPECT_LT(std::abs(w_obj / w_gen - 1), 1e-9);
}

TEST(MeshImportScene, MeshFileErrorsAreLocatedAtTheKey) {
  const std::string scene = scene_file("clamped_plate_pressure_obj");
  // no reader passed (a program built on core alone)
  std::vector<ff::scene::Issue> issues = load_issues(scene, {}, ff::scene::SceneContext{});
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].key, "mesh.file");
  EXPECT_GT(issues[0].line, 0);
  EXPECT_NE(issues[0].message.find("no reader"), std::string::npos) << issues[0].message;
  // a missing file: the importer's sentence, at the key
  issues = load_issues(scene, {"mesh.file=no_such_mesh.obj"});
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].key, "mesh.file");
  EXPECT_NE(issues[0].message.find("no_such_mesh.obj' does not exist"), std::string::npos) << issues[0].message;
  // generator = file without a file
  issues = load_issues(scene_file("clamped_plate_pressure"), {"mesh.generator=file"});
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].key, "mesh.generator");
  EXPECT_NE(issues[0].message.find("needs mesh.file"), std::string::npos) << issues[0].message;
}
