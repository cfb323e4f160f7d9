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
#include <map>
#include <sstream>

#include "app/io/mesh_import.h"
#include "core/mesh/generators.h"
#include "core/scene/mesh_file.h"
#include "core/scene/mesh_generator_keys.h"
#include "core/scene/scene.h"
#include "core/scene/shell_scene.h"

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

// Runs a static scene given as text (written to the scratch folder, importer available) and
// returns its probes' final values by name, and its node count through `nodes`.
std::map<std::string, double> run_text(const std::string& name, const std::string& text) {
  const std::string path = scratch(name + ".toml");  // a name of its own per test: ctest runs them side by side
  std::ofstream(path) << text;
  ff::scene::LoadedScene s = ff::scene::load_scene(path, {}, ff::io::scene_context());
  std::atomic<bool> stop{false};
  std::vector<double> last;
  const ff::RunOutcome o = s.simulation->run([&](ff::Frame&& f) { last = f.probes; }, stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << name << ": " << o.reason;
  std::map<std::string, double> probes;
  const ff::RunInfo& info = s.simulation->info();
  for (std::size_t k = 0; k < info.probes.size() && k < last.size(); ++k) probes[info.probes[k].name] = last[k];
  return probes;
}

// A linear static shell scene around a [mesh] table and the supports, loads and probes.
std::string static_scene(const std::string& mesh, const std::string& material, const std::string& rest) {
  return "[scene]\nname = \"import\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\", \"hr\", \"ans\"]\n[[part]]\n" +
         mesh + "\n[[material]]\n" + material + "\n" + rest +
         "\n[solver]\nmethod = \"load_control\"\ninitial_step = 1.0\nmax_step = 1.0\n[output]\nframes = false\nplots = "
         "false\n";
}

// The generator's mesh for a [mesh] table, written to `file` (with normals when asked).
ff::mesh::ShellMesh write_generated(const std::string& mesh_table, const std::string& file, bool normals) {
  const std::string text = static_scene(mesh_table, "youngs_modulus = 1.0\nthickness = 1.0", "[[probe]]\nname = \"p\"\ndirection = [0.0, 0.0, 1.0]\n");
  const ff::scene::Document d = ff::scene::validate(ff::scene::shell_static_schema(), text, "generated.toml");
  ff::mesh::ShellMesh m = ff::scene::generate_mesh(d, 0);
  std::string error;
  EXPECT_TRUE(ff::io::write_shell_mesh_obj(file, m, &error, normals)) << error;
  return m;
}

std::string file_mesh(const std::string& file) { return "generator = \"file\"\nfile = \"" + file + "\"\n"; }

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
  EXPECT_EQ(issues[0].key, "part[0].file");
  EXPECT_GT(issues[0].line, 0);
  EXPECT_NE(issues[0].message.find("no reader"), std::string::npos) << issues[0].message;
  // a missing file: the importer's sentence, at the key
  issues = load_issues(scene, {"part[0].file=no_such_mesh.obj"});
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].key, "part[0].file");
  EXPECT_NE(issues[0].message.find("no_such_mesh.obj' does not exist"), std::string::npos) << issues[0].message;
  // generator = file without a file
  issues = load_issues(scene_file("clamped_plate_pressure"), {"part[0].generator=file"});
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].key, "part[0].generator");
  EXPECT_NE(issues[0].message.find("needs part.file"), std::string::npos) << issues[0].message;
}

// Issue 11 acceptance, import: an imported slit stays open. The slit annular plate (a ring cut at
// azimuth 0, clamped along one lip and lifted by a line force along the other) is built by the
// generator and, from the same mesh written as OBJ, by import. The lips touch without sharing
// nodes, which an import refuses unless the scene says so (part.keep_faces_apart, issue 48); with
// it the importer keeps both lips (same node count), `side` picks each lip apart on the seam plane y = 0 (the start lip's quads lie
// toward +y, the end lip's toward -y; the probes take the outer corner of each lip by nearest +
// side, since the importer numbers nodes differently), and the slit opens: the lifted lip rises while the
// clamped one stays. The two runs solve the same equations, so they agree to round-off (1e-9).
TEST(MeshImportScene, ImportedSlitStaysOpenUnderLoad) {
  const std::string mesh =
      "generator = \"annulus\"\nradius = 10.0\ninner_radius = 6.0\nslit = true\nn1 = 4\nn2 = 32\n";
  const std::string obj = scratch("slit_ring.obj");
  const ff::mesh::ShellMesh generated = write_generated(mesh, obj, false);
  const std::string material = "youngs_modulus = 21e6\npoisson_ratio = 0.0\nthickness = 0.03";
  auto lip = [](const char* edge, const char* side) {
    return "select = \"patch_edge\"\npatch = \"annulus\"\nedge = \"" + std::string(edge) +
           "\"\n#side " + std::string(side) + "\n";
  };
  const std::string rest = "[[bc]]\ntype = \"clamped\"\n" + lip("start_angle", "[0.0, 1.0, 0.0]") +
                           "[[load]]\ntype = \"line\"\nper_length = [0.0, 0.0, 1e-4]\n" + lip("end_angle", "[0.0, -1.0, 0.0]") +
                           "[[probe]]\nname = \"lifted\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"nearest\"\n"
                           "point = [10.0, 0.0, 0.0]\nside = [0.0, -1.0, 0.0]\n"
                           "[[probe]]\nname = \"clamped\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"nearest\"\n"
                           "point = [10.0, 0.0, 0.0]\nside = [0.0, 1.0, 0.0]\n";
  // the imported mesh has no named edges: the same lips by a plane through the seam and a side
  std::string rest_file = rest;
  for (std::size_t at; (at = rest_file.find("select = \"patch_edge\"\npatch = \"annulus\"\nedge = \"")) != std::string::npos;) {
    const std::size_t line_end = rest_file.find('\n', rest_file.find("edge = ", at));
    rest_file.replace(at, line_end + 1 - at,
                      "select = \"box\"\nbox_min = [5.9, 0.0, 0.0]\nbox_max = [10.1, 0.0, 0.0]\n");
  }
  for (std::size_t at; (at = rest_file.find("#side ")) != std::string::npos;) rest_file.replace(at, 6, "side = ");
  const auto gen = run_text("slit_generated", static_scene(mesh, material, rest));
  std::ofstream(scratch("slit_unsaid.toml")) << static_scene(file_mesh(obj), material, rest_file);
  const std::vector<ff::scene::Issue> unsaid = load_issues(scratch("slit_unsaid.toml"));
  ASSERT_EQ(unsaid.size(), 1u) << "lips that touch without being joined, and the scene does not say they are apart";
  EXPECT_EQ(unsaid[0].key, "part[0].file");
  EXPECT_NE(unsaid[0].message.find("part.keep_faces_apart = true"), std::string::npos) << unsaid[0].message;
  const auto imp = run_text("slit_imported", static_scene(file_mesh(obj) + "keep_faces_apart = true\n", material, rest_file));

  ff::scene::LoadedScene s = ff::scene::load_scene(scratch("slit_imported.toml"), {}, ff::io::scene_context());
  EXPECT_EQ(s.simulation->info().mesh.point_count(), static_cast<std::size_t>(generated.node_count())) << "the importer merged the lips";
  std::printf("slit: lifted lip w = %.9e (generator) %.9e (imported); clamped lip w = %.3e\n", gen.at("lifted"),
              imp.at("lifted"), imp.at("clamped"));
  EXPECT_GT(imp.at("lifted"), 1e-3);  // w / h ~ 0.2: the slit opened
  EXPECT_EQ(imp.at("clamped"), 0.0);
  EXPECT_LT(std::abs(imp.at("lifted") / gen.at("lifted") - 1.0), 1e-9);
}

// Issue 11 acceptance, import: an imported curved mesh with normals takes 5-DoF symmetry planes
// and gives the generator mesh's answer to round-off. A pinched cylinder octant (R = 300, L/2 =
// 300, h = 3, rigid diaphragm at the end: radial and tangential restrained; symmetry on x = 0,
// y = 0 and the mid-plane z = 0; a radial point load at (300, 0, 0)), linear range. With the file's
// exact normals every director lies in the symmetry planes through the mesh edges, so the plain
// 5-DoF symmetry condition applies; without them (averaged facet normals, tilted half a facet
// angle at the edges) the same scene is refused, which is why the normals matter.
TEST(MeshImportScene, ImportedCurvedMeshWithNormalsTakesSymmetryPlanes) {
  const std::string mesh = "generator = \"cylinder\"\nradius = 300.0\nlength = 300.0\nstart_angle = 0.0\n"
                           "end_angle = 90.0\nn1 = 8\nn2 = 8\n";
  const std::string obj = scratch("cylinder_octant_normals.obj");
  const std::string obj_plain = scratch("cylinder_octant_plain.obj");
  write_generated(mesh, obj, true);
  write_generated(mesh, obj_plain, false);
  const std::string material = "youngs_modulus = 3e6\npoisson_ratio = 0.3\nthickness = 3.0";
  const std::string rest =
      "[[bc]]\ntype = \"symmetry\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 1.0, 0.0]\n"
      "[[bc]]\ntype = \"symmetry\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"
      "[[bc]]\ntype = \"symmetry\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [0.0, 0.0, 1.0]\n"
      "[[bc]]\ntype = \"fix\"\nframe = \"cylindrical\"\naxis = [0.0, 0.0, 1.0]\naxis_point = [0.0, 0.0, 0.0]\n"
      "fix = [\"ur\", \"ut\"]\nselect = \"plane\"\npoint = [0.0, 0.0, 300.0]\nnormal = [0.0, 0.0, 1.0]\n"
      "[[load]]\ntype = \"force\"\ntotal = [-0.25, 0.0, 0.0]\nselect = \"nearest\"\npoint = [300.0, 0.0, 0.0]\n"
      "[[probe]]\nname = \"w\"\ndirection = [-1.0, 0.0, 0.0]\nselect = \"nearest\"\npoint = [300.0, 0.0, 0.0]\n";
  const auto gen = run_text("octant_generated", static_scene(mesh, material, rest));
  const auto imp = run_text("octant_imported", static_scene(file_mesh(obj), material, rest));
  std::printf("pinched octant: w = %.12e (generator) %.12e (imported, file normals)\n", gen.at("w"), imp.at("w"));
  EXPECT_GT(gen.at("w"), 0.0);
  EXPECT_LT(std::abs(imp.at("w") / gen.at("w") - 1.0), 1e-9);

  const std::string plain = scratch("octant_plain.toml");
  std::ofstream(plain) << static_scene(file_mesh(obj_plain), material, rest);
  const std::vector<ff::scene::Issue> issues = load_issues(plain);
  ASSERT_FALSE(issues.empty()) << "averaged facet normals cross the symmetry planes, yet the scene was accepted";
  EXPECT_NE(issues[0].message.find("symmetry plane"), std::string::npos) << issues[0].message;
}

// Issue 12, finding 7, for imported meshes: a mesh file whose run would not fit in the memory the
// program may use is refused at mesh.file with the estimate (FLEXFRAME_MEMORY_LIMIT_GB lowers the
// limit below the 81-node plate's ~53 MB estimate; without it the same scene is accepted).
TEST(MeshImportScene, ImportedMeshBeyondTheMemoryLimitIsRefusedAtItsFile) {
  ASSERT_TRUE(load_issues(scene_file("clamped_plate_pressure_obj")).empty());
  setenv("FLEXFRAME_MEMORY_LIMIT_GB", "0.051", 1);
  const std::vector<ff::scene::Issue> issues = load_issues(scene_file("clamped_plate_pressure_obj"));
  unsetenv("FLEXFRAME_MEMORY_LIMIT_GB");
  ASSERT_EQ(issues.size(), 1u);
  EXPECT_EQ(issues[0].key, "part[0].file");
  EXPECT_NE(issues[0].message.find("81 nodes"), std::string::npos) << issues[0].message;
  EXPECT_NE(issues[0].message.find("more than the 0.051 GB"), std::string::npos) << issues[0].message;
}

namespace {
// The plate of tests/io/data/obj (the unit square as 32 triangles) clamped at x = 0 under a
// pressure of 1000 along its directors: w at the free corner (1, 0.5), the structure's
// mesh_import text and the scene's warnings.
struct TrianglePlate {
  double w = NAN;
  std::string import;
  std::vector<std::string> warnings;
};

TrianglePlate run_triangle_plate(const std::string& name, const std::string& obj) {
  const std::string path = scratch(name + ".toml");  // a name of its own per test: ctest runs them side by side
  std::ofstream(path) << static_scene(file_mesh(obj), "youngs_modulus = 2.1e11\npoisson_ratio = 0.3\nthickness = 0.01",
                                      "[[bc]]\ntype = \"clamped\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\n"
                                      "normal = [1.0, 0.0, 0.0]\n[[load]]\ntype = \"pressure\"\npressure = 1000.0\n"
                                      "select = \"all\"\n[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\n"
                                      "select = \"nearest\"\npoint = [1.0, 0.5, 0.0]\n");
  ff::scene::LoadedScene s = ff::scene::load_scene(path, {}, ff::io::scene_context());
  std::atomic<bool> stop{false};
  std::vector<double> last;
  const ff::RunOutcome o = s.simulation->run([&](ff::Frame&& f) { last = f.probes; }, stop);
  EXPECT_EQ(o.status, ff::RunStatus::completed) << name << ": " << o.reason;
  TrianglePlate r;
  const ff::RunInfo& info = s.simulation->info();
  for (std::size_t k = 0; k < info.probes.size() && k < last.size(); ++k)
    if (info.probes[k].name == "w") r.w = last[k];
  for (const auto& [key, value] : s.simulation->info().settings)
    if (key == "mesh_import") r.import = value;
  r.warnings = s.warnings;
  return r;
}

std::string obj_data(const std::string& name) { return std::string(FF_SOURCE_DIR) + "/tests/io/data/obj/" + name; }
}  // namespace

// Issue 48, item 2 (obj_first_facet_flips_pressure): with its first triangle reversed, the plate
// was turned to agree with that one triangle, its directors pointed to -z and the pressure pushed
// it the other way (w = -0.0067 instead of +0.0067, completed). The majority's side (by area)
// stays: both files give one answer, and the first file's three quads are the ones turned.
TEST(MeshImportScene, OneReversedTriangleDoesNotTurnThePlate) {
  const TrianglePlate consistent = run_triangle_plate("plate_tri_beside_first_flipped", obj_data("plate_tri.obj"));
  const TrianglePlate first_flipped = run_triangle_plate("first_flipped", obj_data("first_flipped.obj"));
  std::printf("w: consistent %.9g, first triangle reversed %.9g\n", consistent.w, first_flipped.w);
  EXPECT_GT(consistent.w, 1e-3) << "the pressure pushes along +z (the directors of the triangles' winding)";
  EXPECT_NEAR(first_flipped.w / consistent.w, 1.0, 1e-9);
  EXPECT_EQ(consistent.import.find("turned"), std::string::npos) << consistent.import;
  EXPECT_NE(first_flipped.import.find("3 quads turned to agree with their neighbours (3 % of the area of a piece"),
            std::string::npos)
      << first_flipped.import;
  EXPECT_TRUE(first_flipped.warnings.empty()) << "one triangle of 32 is not worth a warning";
}

// ... and when a large share was wound the other way (12 of 32 triangles), the side still follows
// the majority, and the user hears it: a warning located at part.file (check prints it, run writes
// it to stderr) and WARNING in the import text (summary.json's mesh_import)
TEST(MeshImportScene, ManyReversedTrianglesAreTurnedLoudly) {
  std::ifstream in(obj_data("plate_tri.obj"));
  std::string line, text;
  int faces = 0;
  while (std::getline(in, line)) {
    if (line.rfind("f ", 0) == 0 && faces++ < 12) {
      std::istringstream f(line.substr(2));
      std::string a, b, c;
      f >> a >> b >> c;
      line = "f " + a + " " + c + " " + b;
    }
    text += line + "\n";
  }
  const std::string obj = scratch("twelve_reversed.obj");
  std::ofstream(obj) << text;
  const TrianglePlate consistent = run_triangle_plate("plate_tri_beside_twelve_reversed", obj_data("plate_tri.obj"));
  const TrianglePlate many = run_triangle_plate("twelve_reversed", obj);
  EXPECT_NEAR(many.w / consistent.w, 1.0, 1e-9) << "the 20 triangles wound counter-clockwise about +z decide";
  EXPECT_NE(many.import.find("36 quads turned to agree with their neighbours (WARNING: 38 % of the area"), std::string::npos)
      << many.import;
  ASSERT_EQ(many.warnings.size(), 1u);
  EXPECT_NE(many.warnings[0].find("part[0].file"), std::string::npos) << many.warnings[0];
  EXPECT_NE(many.warnings[0].find("part.flip_director = true"), std::string::npos) << many.warnings[0];
}
