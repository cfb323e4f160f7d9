// Issue 30, item 9: inputs that cannot work are refused by `check` (and `run`) at the key that
// caused them, instead of being accepted and then diverging, running silently wrong, or being
// blamed on a neighbouring key. Each case is the smallest --set on a bundled scene, or a small
// file written here, that was accepted or blamed elsewhere before.

#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

struct RefusalCase {
  std::string name, scene;
  std::vector<std::string> overrides;
  std::string key;       ///< the key the message must name
  std::string fragment;  ///< part of the explanation
};

std::ostream& operator<<(std::ostream& o, const RefusalCase& c) { return o << c.name; }

class CliRefusal : public ::testing::TestWithParam<RefusalCase> {};

// `check` refuses with exit 2 at the key's line; `run` refuses the same way and writes nothing
TEST_P(CliRefusal, CheckAndRunRefuseAtTheKey) {
  const RefusalCase& c = GetParam();
  const std::string dir = fresh_test_dir();
  const std::string cwd = dir + "/cwd";
  fs::create_directories(cwd);
  std::vector<std::string> sets;
  for (const std::string& o : c.overrides) sets.insert(sets.end(), {"--set", o});
  std::vector<std::string> check{"check", c.scene}, run{"run", c.scene, "--out", cwd + "/out", "--no-frames", "--no-plots",
                                                        "--quiet"};
  check.insert(check.end(), sets.begin(), sets.end());
  run.insert(run.end(), sets.begin(), sets.end());
  for (const auto& [verb, args] : {std::pair{"check", check}, std::pair{"run", run}}) {
    SCOPED_TRACE(std::string("flexframe ") + verb);
    const ProcResult r = run_flexframe(args, dir + "/" + verb, cwd);
    ASSERT_EQ(r.signal, 0) << r.describe();
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("key '" + c.key + "'"), std::string::npos) << "stderr lacks key '" << c.key << "'\n"
                                                                    << r.describe();
    EXPECT_NE(r.err.find(c.fragment), std::string::npos) << "stderr lacks '" << c.fragment << "'\n" << r.describe();
    EXPECT_TRUE(tree(cwd).empty()) << ::testing::PrintToString(tree(cwd));
  }
}

INSTANTIATE_TEST_SUITE_P(
    Issue30, CliRefusal,
    ::testing::Values(
        // accepted, then diverged at run time
        RefusalCase{"MaxStepBelowInitialStep", "cantilever_rollup", {"solver.max_step=0.01"}, "solver.max_step",
                    "smaller than solver.initial_step"},
        RefusalCase{"InitialStepAboveMaxStep", "hemisphere_18deg_h004", {"solver.initial_step=0.5"},
                    "solver.initial_step", "smaller than solver.initial_step"},
        RefusalCase{"CholmodWithFollowerPressure", "clamped_plate_pressure",
                    {"solver.linear_solver=\"cholmod_llt\"", "load[0].follower=true"}, "solver.linear_solver",
                    "a follower load"},
        RefusalCase{"CholmodWithMoment", "cantilever_rollup", {"solver.linear_solver=\"cholmod_llt\""},
                    "solver.linear_solver", "a moment"},
        RefusalCase{"ClosedCylinderOneElementAround", "pulled_cylinder", {"part[0].end_angle=360", "part[0].n1=1"}, "part[0].n1",
                    "at least 3"},
        RefusalCase{"ClosedCylinderTwoElementsAround", "pulled_cylinder", {"part[0].end_angle=360", "part[0].n1=2"}, "part[0].n1",
                    "at least 3"},
        RefusalCase{"TinyCylinderLength", "pulled_cylinder", {"part[0].length=1e-12"}, "part[0].length", "times longer"},
        RefusalCase{"TinyAzimuthRange", "pulled_cylinder", {"part[0].end_angle=1e-10"}, "part[0].end_angle", "times longer"},
        RefusalCase{"TinyRadius", "pulled_cylinder", {"part[0].radius=1e-12"}, "part[0].radius", "times longer"},
        // accepted and silently wrong
        RefusalCase{"CapThickerThanItsRadius", "hemisphere_18deg_h004", {"material[0].thickness=11"}, "part[0].radius",
                    "thicker than its radius"},
        RefusalCase{"CapThickerThanItsRadiusNamesTheThickness", "hemisphere_18deg_h004", {"material[0].thickness=11"},
                    "material[0].thickness", "thicker than its radius"},
        RefusalCase{"NearestBetweenTwoNodes", "clamped_plate_pressure", {"probe[0].point=[0.5625, 0.5, 0.0]"},
                    "probe[0].point", "equally near node"},
        RefusalCase{"ReversedAzimuthRange", "pulled_cylinder", {"part[0].start_angle=90", "part[0].end_angle=0"},
                    "part[0].end_angle", "runs backwards"},
        // the only load zero: nothing to follow (a zero load beside others is accepted, switched off)
        RefusalCase{"ZeroForce", "pulled_cylinder", {"load[0].total=[0.0, 0.0, 0.0]"}, "load[0].total",
                    "nothing loads the shell"},
        RefusalCase{"ZeroPressure", "clamped_plate_pressure", {"load[0].pressure=0.0"}, "load[0].pressure",
                    "nothing loads the shell"},
        // blamed on the wrong key
        RefusalCase{"ShortArmOfLPlate", "l_plate_force", {"part[0].length2=15.0001"}, "part[0].length2", "times longer"},
        RefusalCase{"WeldToleranceNotFile", "clamped_plate_pressure_obj", {"part[0].weld_tolerance=1e300"},
                    "part[0].weld_tolerance", "the weld tolerance 1e+300 is not below"},
        RefusalCase{"HugeRadius", "pulled_cylinder", {"part[0].radius=1e200"}, "part[0].radius",
                    "outside the lengths a shell mesh can use"},
        RefusalCase{"OverflowingBcAxis", "clamped_plate_pressure",
                    {"bc[0].type=\"fix\"", "bc[0].fix=[\"ur\"]", "bc[0].frame=\"cylindrical\"",
                     "bc[0].axis=[1e300, 1e300, 1e300]"},
                    "bc[0].axis", "finite non-zero"},
        RefusalCase{"PendulumShellOneElementOverItsArc", "double_pendulum_shells", {"part[0].n1=1"}, "part[0].n1",
                    "at most 120"},
        RefusalCase{"PendulumShellThickerThanItsRadius", "double_pendulum_shells", {"material[0].thickness=0.5"},
                    "part[0].radius", "thicker than its radius"},
        RefusalCase{"TinyPolarHole", "hemisphere_18deg_h004", {"part[0].polar_start=1e-12"}, "part[0].polar_start",
                    "is a point"}),
    [](const ::testing::TestParamInfo<RefusalCase>& i) { return i.param.name; });

// The degenerate-element refusal no longer names material.thickness when a mesh key caused it
TEST(CliRefusalKey, MeshCausesAreNotBlamedOnTheThickness) {
  const std::string dir = fresh_test_dir();
  for (const std::vector<std::string>& sets :
       {std::vector<std::string>{"part[0].radius=1e-12"}, std::vector<std::string>{"part[0].length2=15.0001"},
        std::vector<std::string>{"part[0].end_angle=360", "part[0].n1=1"}}) {
    const std::string scene = sets[0].rfind("part[0].length2", 0) == 0 ? "l_plate_force" : "pulled_cylinder";
    std::vector<std::string> args{"check", scene};
    for (const std::string& s : sets) args.insert(args.end(), {"--set", s});
    const ProcResult r = run_flexframe(args, dir + "/check", dir);
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_EQ(r.err.find("material.thickness"), std::string::npos) << r.describe();
  }
}

// ---- scenes written here ------------------------------------------------------------------------

std::string static_scene(const std::string& mesh, const std::string& rest) {
  return "[scene]\nname = \"refusal\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\", \"hr\", \"ans\"]\n\n[[part]]\n" +
         mesh + "\n\n[[material]]\nyoungs_modulus = 1e6\nthickness = 0.01\n\n" + rest + "\n[solver]\n";
}

// 1-based number of the first line of `text` starting with `prefix` (0: none)
int line_of(const std::string& text, const std::string& prefix) {
  std::istringstream in(text);
  std::string l;
  for (int n = 1; std::getline(in, l); ++n)
    if (l.rfind(prefix, 0) == 0) return n;
  return 0;
}

// Refused by check at `scene_file:line:` and the key
void expect_refused_at(const std::string& dir, const std::string& scene_file, int line, const std::string& key,
                       const std::string& fragment) {
  const ProcResult r = run_flexframe({"check", scene_file}, dir + "/check", dir);
  ASSERT_EQ(r.signal, 0) << r.describe();
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  const std::string at = fs::path(scene_file).filename().string() + ":" + std::to_string(line) + ":";
  EXPECT_NE(r.err.find(at), std::string::npos) << "stderr lacks '" << at << "'\n" << r.describe();
  EXPECT_NE(r.err.find("key '" + key + "'"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find(fragment), std::string::npos) << "stderr lacks '" << fragment << "'\n" << r.describe();
}

const std::string kClampedRing =
    "[[bc]]\ntype = \"clamped\"\nselect = \"patch_edge\"\npatch = \"annulus\"\nedge = \"inner\"\n\n"
    "[[load]]\ntype = \"pressure\"\npressure = 1.0\nselect = \"all\"\n\n"
    "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"patch_edge\"\npatch = \"annulus\"\nedge = \"outer\"\n";

TEST(CliRefusalFile, SlitAnnulusWithTwoElementsAround) {
  const std::string dir = fresh_test_dir();
  const std::string scene = dir + "/slit_annulus.toml";
  // line 8: n2
  write_text(scene, static_scene("generator = \"annulus\"\nradius = 1.0\ninner_radius = 0.5\nslit = true\nn2 = 2\nn1 = 2",
                                 kClampedRing));
  expect_refused_at(dir, scene, line_of(read_text(scene), "n2 = "), "part[0].n2", "at least 3");
}

// A probe on the seam of a slit cylinder: both lips are at the point, so `nearest` took the lower
// node number (the clamped lip); now refused, and `side` picks a lip.
TEST(CliRefusalFile, NearestOnASlitIsAmbiguousUnlessASideIsGiven) {
  const std::string dir = fresh_test_dir();
  const std::string mesh = "generator = \"cylinder\"\nradius = 1.0\nlength = 1.0\nslit = true\nn1 = 12\nn2 = 2";
  const std::string bcs =
      "[[bc]]\ntype = \"clamped\"\nselect = \"patch_edge\"\npatch = \"cylinder\"\nedge = \"start_angle\"\n\n"
      "[[load]]\ntype = \"force\"\ntotal = [0.0, 0.0, 1.0]\nselect = \"patch_edge\"\npatch = \"cylinder\"\nedge = "
      "\"end_angle\"\n\n"
      "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\npoint = [1.0, 0.0, 1.0]\n";
  const std::string scene = dir + "/slit.toml";
  write_text(scene, static_scene(mesh, bcs));
  expect_refused_at(dir, scene, line_of(read_text(scene), "point = "), "probe[0].point", "equally near node");
  // the free lip (its quads lie towards -y from the seam at +x, azimuth 360 deg) is accepted
  write_text(scene, static_scene(mesh, bcs + "side = [0.0, -1.0, 0.0]\n"));
  const ProcResult r = run_flexframe({"check", scene}, dir + "/check_side", dir);
  EXPECT_EQ(r.exit_code, 0) << r.describe();
}

// A zero prescribed displacement is accepted as a zero load is (it holds its DoFs, as a load of
// zero switched off with --set loads nothing); a scene where nothing at all is non-zero is refused.
TEST(CliRefusalFile, ZeroPrescribedDisplacementIsAcceptedLikeAZeroLoad) {
  const std::string dir = fresh_test_dir();
  const std::string scene = dir + "/zero_displacement.toml";
  const std::string bcs = "[[bc]]\ntype = \"clamped\"\nselect = \"plane\"\nnormal = [1.0, 0.0, 0.0]\n\n"
                          "[[bc]]\ntype = \"displacement\"\nfix = [\"uz\"]\ndisplacement = [0.0, 0.0, 0.0]\n"
                          "select = \"plane\"\npoint = [1.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n\n"
                          "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\npoint = [1.0, 0.0, 0.0]\n";
  const std::string plate = "generator = \"rectangular_plate\"\nlength = 1.0\nwidth = 1.0\nn1 = 2\nn2 = 2";
  // with a (non-zero) load beside it: accepted
  write_text(scene, static_scene(plate, bcs + "\n[[load]]\ntype = \"force\"\ntotal = [0.0, 0.0, 1.0]\n"
                                             "select = \"nearest\"\npoint = [0.5, 1.0, 0.0]\n"));
  const ProcResult r = run_flexframe({"check", scene}, dir + "/check", dir);
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  // alone: nothing loads the shell
  write_text(scene, static_scene(plate, bcs));
  const ProcResult alone = run_flexframe({"check", scene}, dir + "/alone", dir);
  EXPECT_EQ(alone.exit_code, 2) << alone.describe();
  EXPECT_NE(alone.err.find("nothing loads the shell"), std::string::npos) << alone.describe();
}

// ---- OBJ normals tilted from the surface --------------------------------------------------------

// a unit plate of n x n quads in z = 0 whose every normal is tilted `tilt_deg` about x
std::string tilted_plate_obj(int n, double tilt_deg) {
  std::ostringstream o;
  o.precision(17);
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) o << "v " << double(i) / n << " " << double(j) / n << " 0\n";
  const double t = tilt_deg * std::acos(-1.0) / 180.0;
  o << "vn 0 " << -std::sin(t) << " " << std::cos(t) << "\n";
  auto id = [n](int i, int j) { return j * (n + 1) + i + 1; };
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i)
      o << "f " << id(i, j) << "//1 " << id(i + 1, j) << "//1 " << id(i + 1, j + 1) << "//1 " << id(i, j + 1) << "//1\n";
  return o.str();
}

TEST(CliRefusalFile, TiltedObjNormalsAreRefusedWithTheVertexAndAngle) {
  const std::string dir = fresh_test_dir();
  for (double tilt : {30.0, 89.0}) {
    SCOPED_TRACE(tilt);
    const std::string obj = dir + "/tilted.obj";
    write_text(obj, tilted_plate_obj(4, tilt));
    const ProcResult r = run_flexframe({"check", "clamped_plate_pressure_obj", "--set", "part[0].file=\"" + obj + "\""},
                                       dir + "/check", dir);
    ASSERT_EQ(r.signal, 0) << r.describe();
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("key 'part[0].file'"), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find("tilted.obj"), std::string::npos) << r.describe();
    std::ostringstream angle;
    angle << "is tilted " << tilt << " deg";
    EXPECT_NE(r.err.find(angle.str()), std::string::npos) << r.describe();
    // the face's OBJ line, its corner and the node (every corner is tilted alike: any one)
    EXPECT_NE(r.err.find("the normal at line "), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find(", corner "), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find(" (node "), std::string::npos) << r.describe();
  }
}

// A small tilt is accepted, and the largest one is in the run's record (results.h5 /settings,
// mesh_import, as check prints it)
TEST(CliRefusalFile, AcceptedNormalsRecordTheirLargestTilt) {
  const std::string dir = fresh_test_dir();
  const std::string obj = dir + "/tilted.obj";
  write_text(obj, tilted_plate_obj(4, 3.0));
  const std::string out = dir + "/out";
  const ProcResult r = run_flexframe({"run", "clamped_plate_pressure_obj", "--set", "part[0].file=\"" + obj + "\"", "--out",
                                      out, "--no-frames", "--no-plots", "--quiet"},
                                     dir + "/run", dir);
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const std::string h5 = read_text(out + "/results.h5");
  EXPECT_NE(h5.find("at most 3 deg from the quads' own normals"), std::string::npos);
}

// ---- study files --------------------------------------------------------------------------------

// A study whose axis sets a key the scene refuses is refused at the study file's line (the axis
// entry), not only at the --set text it became.
TEST(CliRefusalFile, StudyVariantErrorsNameTheStudyFileLine) {
  const std::string dir = fresh_test_dir();
  const std::string study = dir + "/bad_study.toml";
  write_text(study,
             "[study]\nname = \"bad\"\nscene = \"cantilever_rollup\"\nmetric = \"tip_w\"\n\n"  // 1-5
             "[[vary]]\nkey = [\"part[0].n1\"]\nvalues = [\"8\", \"abc\"]\n\n"                      // 6-9
             "[reference]\nkind = \"finest\"\n");
  // --check refuses it; a run refuses it after the variant's own process did
  for (const auto& args : {std::vector<std::string>{"study", study, "--check"},
                           std::vector<std::string>{"study", study, "--out", dir + "/out"}}) {
    SCOPED_TRACE(args.back());
    const ProcResult r = run_flexframe(args, dir + "/study", dir);
    ASSERT_EQ(r.signal, 0) << r.describe();
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("bad_study.toml:8:"), std::string::npos) << r.describe();
    EXPECT_NE(r.err.find("key 'part[0].n1'"), std::string::npos) << r.describe();
  }
}

}  // namespace
}  // namespace ff::cli::test
