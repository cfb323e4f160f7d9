// Bad input: `flexframe check` and `flexframe run` reject a broken scene or --set with exit code 2,
// say where (file:line: or the --set), which key and what was expected, and write nothing.

#include <gtest/gtest.h>

#include <map>

#include "cli_support.h"

namespace ff::cli::test {
namespace {

// A small valid scene; the cases below replace single lines, so line numbers stay put.
const std::vector<std::string> kBase = {
    "# scene for the cli bad-input tests",                        // 1
    "[scene]",                                                    // 2
    "name = \"cli_bad\"",                                         // 3
    "model = \"hub_beam\"",                                       // 4
    "effects = [\"inertia\", \"bending\", \"axial\", \"hub_torque\"]",  // 5
    "",                                                           // 6
    "[beam]",                                                     // 7
    "length = 1.8",                                               // 8
    "",                                                           // 9
    "[discretization]",                                           // 10
    "method = \"efg\"",                                           // 11
    "",                                                           // 12
    "[efg]",                                                      // 13
    "scale = 2.5",                                                // 14
    "",                                                           // 15
    "[solver]",                                                   // 16
    "dt = 0.05",                                                  // 17
    "end = 1.0",                                                  // 18
    "newmark_beta = 0.25",                                        // 19
    "newmark_gamma = 0.5",                                        // 20
};

struct BadCase {
  std::string name;
  std::map<int, std::string> edits;     ///< 1-based line -> replacement text
  std::vector<std::string> overrides;   ///< --set values
  int exit_code = 2;
  std::string where;                    ///< "bad.toml" or "--set solver.dtt=0.1"
  int line = 0;                         ///< expected line in `where`; 0: no line (a --set, a missing table)
  std::string key;                      ///< expected key, "" for none (syntax error)
  std::vector<std::string> fragments;   ///< parts of the expectation that must appear in stderr
};

std::ostream& operator<<(std::ostream& o, const BadCase& c) { return o << c.name; }

std::string scene_text(const BadCase& c) {
  std::string text;
  for (std::size_t i = 0; i < kBase.size(); ++i) {
    const auto e = c.edits.find(static_cast<int>(i) + 1);
    text += (e != c.edits.end() ? e->second : kBase[i]) + "\n";
  }
  return text;
}

std::vector<BadCase> bad_cases() {
  return {
      // sanity: the base scene and the boundary values are accepted, so the errors below come
      // from the edits alone
      {"base_scene_is_valid", {}, {}, 0, "", 0, "", {"cli_bad: valid"}},
      {"efg_scale_10_is_valid", {{14, "scale = 10.0"}}, {}, 0, "", 0, "", {"cli_bad: valid"}},
      {"newmark_beta_gamma_half_is_valid", {{19, "newmark_beta = 0.3"}, {20, "newmark_gamma = 0.6"}}, {}, 0, "", 0,
       "", {"cli_bad: valid"}},

      {"unknown_key_with_suggestion", {{8, "lenght = 1.8"}}, {}, 2, "bad.toml", 8, "beam.lenght",
       {"unknown key", "did you mean 'beam.length'"}},
      {"wrong_type", {{8, "length = \"long\""}}, {}, 2, "bad.toml", 8, "beam.length", {"expected a number", "string"}},
      {"negative_length", {{8, "length = -1.8"}}, {}, 2, "bad.toml", 8, "beam.length", {"> 0", "-1.8"}},
      {"dt_zero", {{17, "dt = 0"}}, {}, 2, "bad.toml", 17, "solver.dt", {"> 0", "got 0"}},
      {"dt_negative", {{17, "dt = -0.01"}}, {}, 2, "bad.toml", 17, "solver.dt", {"> 0", "-0.01"}},
      {"efg_scale_1", {{14, "scale = 1.0"}}, {}, 2, "bad.toml", 14, "efg.scale", {"(1, 10]"}},
      {"efg_scale_above_10", {{14, "scale = 10.5"}}, {}, 2, "bad.toml", 14, "efg.scale", {"(1, 10]", "10.5"}},
      // a missing key is reported at its table's header
      {"missing_solver_dt", {{17, "# no dt"}}, {}, 2, "bad.toml", 16, "solver.dt", {"missing required key"}},
      // a missing table has no line to point at
      {"missing_solver_table", {{16, "#"}, {17, "#"}, {18, "#"}, {19, "#"}, {20, "#"}}, {}, 2, "bad.toml", 0,
       "solver", {"missing required table [solver]"}},
      {"bad_choice", {{11, "method = \"fe\""}}, {}, 2, "bad.toml", 11, "discretization.method",
       {"expected one of efg, fem", "'fe'", "did you mean 'fem'"}},
      {"unknown_effect", {{5, "effects = [\"inertia\", \"bending\", \"axial\", \"hub_torqe\"]"}}, {}, 2, "bad.toml", 5,
       "scene.effects", {"hub_torqe", "did you mean 'hub_torque'"}},
      {"missing_effect_bending", {{5, "effects = [\"inertia\", \"axial\", \"hub_torque\"]"}}, {}, 2, "bad.toml", 5,
       "scene.effects", {"needs the effect 'bending'"}},
      {"toml_syntax_error", {{18, "end = = 1.0"}}, {}, 2, "bad.toml", 18, "", {"TOML syntax error"}},
      {"newmark_beta_below_gamma_half", {{19, "newmark_beta = 0.2"}}, {}, 2, "bad.toml", 19, "solver.newmark_beta",
       {"beta >= gamma / 2"}},
      // the issue belongs to beta's line even when gamma's value makes beta too small
      {"newmark_gamma_raises_bound", {{19, "newmark_beta = 0.3"}, {20, "newmark_gamma = 0.8"}}, {}, 2, "bad.toml", 19,
       "solver.newmark_beta", {"beta >= gamma / 2", "0.4"}},

      {"set_unknown_key", {}, {"solver.dtt=0.1"}, 2, "--set solver.dtt=0.1", 0, "solver.dtt",
       {"unknown key", "did you mean 'solver.dt'"}},
      {"set_wrong_type", {}, {"solver.dt=abc"}, 2, "--set solver.dt=abc", 0, "solver.dt", {"expected a number"}},
      {"set_out_of_range", {}, {"efg.scale=0.5"}, 2, "--set efg.scale=0.5", 0, "efg.scale", {"(1, 10]"}},
      {"set_without_equals", {}, {"solver.dt"}, 2, "--set solver.dt", 0, "solver.dt", {"missing '=value'"}},
  };
}

class CliBadInput : public ::testing::TestWithParam<BadCase> {};

// Each case through `check` and `run`, both from an empty working folder that must stay empty
// (run also gets an --out folder there that must not appear).
TEST_P(CliBadInput, RejectedWithLocationKeyAndExpectation) {
  const BadCase& c = GetParam();
  const std::string dir = fresh_test_dir();
  const std::string scene = dir + "/bad.toml";
  write_text(scene, scene_text(c));
  const std::string cwd = dir + "/cwd";
  fs::create_directories(cwd);
  const std::string out = cwd + "/out";

  std::vector<std::string> set_args;
  for (const std::string& o : c.overrides) set_args.insert(set_args.end(), {"--set", o});
  std::vector<std::string> check_args{"check", scene};
  check_args.insert(check_args.end(), set_args.begin(), set_args.end());
  // (no extra --set here: it would create a missing [solver] table and change the message)
  std::vector<std::string> run_args{"run", scene, "--out", out, "--no-frames", "--no-plots", "--quiet"};
  run_args.insert(run_args.end(), set_args.begin(), set_args.end());

  for (const auto& [verb, args] : {std::pair{"check", check_args}, std::pair{"run", run_args}}) {
    SCOPED_TRACE(std::string("flexframe ") + verb);
    const ProcResult r = run_flexframe(args, dir + "/" + verb, cwd);
    ASSERT_EQ(r.signal, 0) << r.describe();
    EXPECT_EQ(r.exit_code, c.exit_code) << r.describe();
    if (c.exit_code == 0) {
      if (std::string(verb) == "check") {
        for (const std::string& f : c.fragments) { EXPECT_NE(r.out.find(f), std::string::npos) << r.describe(); }
      }
      continue;
    }
    if (c.line > 0) {
      const std::string at = c.where + ":" + std::to_string(c.line) + ":";
      EXPECT_NE(r.err.find(at), std::string::npos) << "stderr lacks '" << at << "'\n" << r.describe();
    } else {
      EXPECT_NE(r.err.find(c.where), std::string::npos) << "stderr lacks '" << c.where << "'\n" << r.describe();
    }
    if (!c.key.empty()) {
      EXPECT_NE(r.err.find("'" + c.key + "'"), std::string::npos) << "stderr lacks the key\n" << r.describe();
    }
    for (const std::string& f : c.fragments)
      EXPECT_NE(r.err.find(f), std::string::npos) << "stderr lacks '" << f << "'\n" << r.describe();
    EXPECT_EQ(r.out.find("valid;"), std::string::npos) << r.describe();
    EXPECT_TRUE(tree(cwd).empty()) << "bad input created files: " << ::testing::PrintToString(tree(cwd));
  }
}

INSTANTIATE_TEST_SUITE_P(Table, CliBadInput, ::testing::ValuesIn(bad_cases()),
                         [](const ::testing::TestParamInfo<BadCase>& i) { return i.param.name; });

TEST(CliBadInputFile, NonExistentSceneIsNamed) {
  const std::string dir = fresh_test_dir();
  const std::string cwd = dir + "/cwd";
  fs::create_directories(cwd);
  const std::string missing = dir + "/does_not_exist.toml";
  for (const auto& args : {std::vector<std::string>{"check", missing},
                           std::vector<std::string>{"run", missing, "--out", cwd + "/out", "--quiet"}}) {
    SCOPED_TRACE("flexframe " + args[0]);
    const ProcResult r = run_flexframe(args, dir + "/" + args[0], cwd);
    EXPECT_EQ(r.exit_code, 2) << r.describe();
    EXPECT_NE(r.err.find("does_not_exist.toml"), std::string::npos) << r.describe();
    EXPECT_TRUE(tree(cwd).empty()) << ::testing::PrintToString(tree(cwd));
  }
}

// Command-line usage errors (no verb, unknown option, option value out of range) are rejected
// and write nothing.
TEST(CliBadInputFile, UsageErrorsAreRejected) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  const std::vector<std::vector<std::string>> cases = {
      {},
      {"run", "hub_beam_fem_tau1", "--bogus", "--out", out},
      {"run", "hub_beam_fem_tau1", "--frame-every", "0", "--out", out},
      {"run", "hub_beam_fem_tau1", "--width", "10", "--out", out},
      {"check"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    SCOPED_TRACE(::testing::PrintToString(cases[i]));
    const ProcResult r = run_flexframe(cases[i], dir + "/usage" + std::to_string(i));
    EXPECT_EQ(r.signal, 0) << r.describe();
    EXPECT_NE(r.exit_code, 0) << r.describe();
    EXPECT_FALSE(r.err.empty()) << r.describe();
    EXPECT_FALSE(fs::exists(out)) << r.describe();
  }
}

// KNOWN BUG (reported, not fixed here): usage errors exit with CLI11's own codes (105 value out
// of range, 106 missing subcommand/argument, 109 unknown option) instead of the documented 2 for
// bad input. Enable once main.cpp maps CLI::ParseError to 2 (--help must stay 0).
TEST(CliBadInputFile, UsageErrorsExitWith2) {
  const std::string dir = fresh_test_dir();
  const std::vector<std::vector<std::string>> cases = {
      {"run", "hub_beam_fem_tau1", "--bogus", "--out", dir + "/out"},
      {"run", "hub_beam_fem_tau1", "--frame-every", "0", "--out", dir + "/out"},
      {"check"},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const ProcResult r = run_flexframe(cases[i], dir + "/usage" + std::to_string(i));
    EXPECT_EQ(r.exit_code, 2) << ::testing::PrintToString(cases[i]) << "\n" << r.describe();
  }
  const ProcResult help = run_flexframe({"run", "--help"}, dir + "/help");
  EXPECT_EQ(help.exit_code, 0) << help.describe();
}

}  // namespace
}  // namespace ff::cli::test

namespace ff::cli::test {
namespace {

// Issue 12, findings 4-6: an error raised while the model is built names the key that caused it
// (not a neighbour, not the first [[bc]]); a repeated name that `run` would refuse when it
// creates results.h5, and a step count no run could finish, are refused by `check` already. Each case is the smallest
// --set on a bundled scene that showed the wrong key.
struct WrongKeyCase {
  std::string name, scene;
  std::vector<std::string> overrides;
  std::string key;       ///< the key the message must name
  std::string fragment;  ///< part of the explanation
};

class CliErrorKey : public ::testing::TestWithParam<WrongKeyCase> {};

TEST_P(CliErrorKey, CheckNamesTheKeyThatCausedIt) {
  const WrongKeyCase& c = GetParam();
  const std::string dir = fresh_test_dir();
  std::vector<std::string> args{"check", c.scene};
  for (const std::string& o : c.overrides) args.insert(args.end(), {"--set", o});
  const ProcResult r = run_flexframe(args, dir + "/check", dir);
  ASSERT_EQ(r.signal, 0) << r.describe();
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("key '" + c.key + "'"), std::string::npos) << "stderr lacks key '" << c.key << "'\n" << r.describe();
  EXPECT_NE(r.err.find(c.fragment), std::string::npos) << "stderr lacks '" << c.fragment << "'\n" << r.describe();
}

INSTANTIATE_TEST_SUITE_P(
    Findings, CliErrorKey,
    ::testing::Values(
        WrongKeyCase{"StaticThicknessNotBc", "hinged_roof_h635", {"material[0].thickness=1e9"}, "material[0].thickness",
                     "thicker than its radius of curvature"},
        WrongKeyCase{"BodyThicknessNotEffects", "double_pendulum_shells", {"material[0].thickness=1e9"},
                     "material[0].thickness", "thicker than its radius of curvature"},
        WrongKeyCase{"BeamLengthNotEfgScale", "hub_beam_efg_tau1", {"beam.length=1e308"}, "beam.length",
                     "outside double precision"},
        WrongKeyCase{"TinyBeamLength", "hub_beam_fem_tau1", {"beam.length=1e-300"}, "beam.length", "outside double precision"},
        WrongKeyCase{"JointPatchHasALocation", "double_pendulum_shells", {"joint[0].patch=\"Z\""}, "joint[0].patch",
                     "no patch named 'Z'"},
        WrongKeyCase{"ZeroPlaneNormal", "pulled_cylinder", {"bc[1].normal=[0.0, 0.0, 0.0]"}, "bc[1].normal",
                     "finite non-zero"},
        WrongKeyCase{"ReferenceColumnNotFile", "pulled_cylinder", {"reference[0].y_column=\"nope\""},
                     "reference[0].y_column", "no column 'nope'"},
        WrongKeyCase{"AbsurdEndTime", "hub_beam_efg_tau1", {"solver.end=1e300"}, "solver.end",
                     "2e+301 steps, more than"},
        WrongKeyCase{"AbsurdTimeStep", "double_pendulum_shells", {"solver.dt=1e-300"}, "solver.dt", "steps, more than"},
        // issue 14: one vocabulary; the old names are refused with their new ones
        WrongKeyCase{"RenamedEndTime", "hub_beam_efg_tau1", {"solver.t_end=2"}, "solver.t_end",
                     "was renamed to 'solver.end'"},
        WrongKeyCase{"RenamedTimeTable", "double_pendulum_shells", {"time.dt=0.001"}, "time.dt",
                     "was renamed to 'solver.dt'"},
        WrongKeyCase{"RenamedIntegratorTable", "double_pendulum_shells", {"integrator.policy=\"full\""},
                     "integrator.policy", "was renamed to 'solver.policy'"},
        WrongKeyCase{"RenamedLoadFactorEnd", "pulled_cylinder", {"solver.lambda_end=0.5"}, "solver.lambda_end",
                     "was renamed to 'solver.end'"},
        WrongKeyCase{"RenamedDrillingFactor", "l_plate_moment", {"drilling.factor=2"}, "drilling.factor",
                     "was renamed to 'material.drilling_factor'"},
        WrongKeyCase{"RepeatedProbeName", "pulled_cylinder", {"probe[2].name=\"w_A\""}, "probe[2].name",
                     "already called 'w_A'"},
        // a key of the other path-following method would be ignored: refused instead
        WrongKeyCase{"ArcLengthKeyUnderLoadControl", "cantilever_rollup", {"solver.max_steps=10"}, "solver.max_steps",
                     "belongs to method = \"arc_length\""},
        WrongKeyCase{"LoadControlKeyUnderArcLength", "pulled_cylinder", {"solver.stop_at_limit_point=false"},
                     "solver.stop_at_limit_point", "belongs to method = \"load_control\""}),
    [](const ::testing::TestParamInfo<WrongKeyCase>& i) { return i.param.name; });

}  // namespace
}  // namespace ff::cli::test

#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>

#include "core/shell/shell_model.h"

extern char** environ;

namespace ff::cli::test {
namespace {

// Issue 12, finding 7: `check` refuses a mesh that cannot fit, with the estimate in the message,
// before generating it (the 10 s limit is a hang guard: 1024 x 1024 used to take 15 s and end in
// bad_alloc), and the estimate it uses is a real one: the peak resident size
// of an actual run is within 35 % of shell::estimated_peak_bytes (its fit is +-10 % on 4k-26k
// nodes; the margin covers allocator and library differences between machines).
TEST(CliMemoryEstimate, OversizedMeshIsRefusedWithTheEstimate) {
  const std::string dir = fresh_test_dir();
  const ProcResult r = run_flexframe(
      {"check", "clamped_plate_pressure", "--set", "part[0].n1=1024", "--set", "part[0].n2=1024"}, dir + "/check", dir, 10.0);
  ASSERT_FALSE(r.timed_out) << r.describe();
  if (r.exit_code == 0) GTEST_SKIP() << "this machine has room for 1024 x 1024 (" << r.out << ")";
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE(r.err.find("key 'part[0].n1'"), std::string::npos) << r.describe();
  EXPECT_NE(r.err.find(" GB, more than the "), std::string::npos) << r.describe();
}

TEST(CliMemoryEstimate, EstimateMatchesAMeasuredPeak) {
#if defined(__SANITIZE_ADDRESS__)
  // scripts/sanitize: the child is instrumented too, and ASan's shadow memory and quarantine
  // (measured: 1274 MB against 539 MB estimated) are not what the estimate is for
  GTEST_SKIP() << "AddressSanitizer build: resident memory is not the program's";
#endif
  const std::string dir = fresh_test_dir();
  const std::string exe = flexframe_exe(), out = dir + "/out";
  std::vector<std::string> args{exe, "run", "clamped_plate_pressure", "--out", out, "--no-frames", "--no-plots", "--quiet",
                                "--set", "part[0].n1=96", "--set", "part[0].n2=96"};
  std::vector<char*> argv;
  for (std::string& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, exe.c_str(), nullptr, nullptr, argv.data(), environ), 0);
  int status = 0;
  rusage usage{};
  ASSERT_EQ(wait4(pid, &status, 0, &usage), pid);  // this child's own peak, not the test's others
  ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "the run failed";
  const double measured = usage.ru_maxrss * 1024.0, estimated = shell::estimated_peak_bytes(97 * 97, 0.0);
  std::printf("96 x 96 plate: peak %.0f MB, estimate %.0f MB\n", measured / 1e6, estimated / 1e6);
  EXPECT_LT(std::abs(estimated / measured - 1.0), 0.35);
}

// Issue 33, laminated sections through the executable: `check` refuses a ply of zero thickness
// and a file part of orthotropic plies without a fibre vector (a file has no u grid) with exit 2
// at file:line and key, and accepts angles that look like radians with a located warning line.
TEST(CliLaminate, BadLayupInputIsLocatedAndRadiansWarn) {
  const std::string dir = fresh_test_dir();
  const std::string obj = std::string(FF_SOURCE_DIR) + "/assets/meshes/plate_8x8_unit.obj";
  auto scene = [&](const std::string& angles, const std::string& thicknesses, const std::string& part) {
    return "[scene]\nname = \"cli_laminate\"\nmodel = \"shell\"\nanalysis = \"static\"\neffects = [\"elastic\"]\n"  // 1-5
           "[[material]]\nname = \"ply\"\ne1 = 140e9\ne2 = 10e9\ng12 = 5e9\ng13 = 5e9\ng23 = 4e9\nnu12 = 0.3\n"  // 6-13
           "[[layup]]\nname = \"cross\"\nplies = [\"ply\", \"ply\"]\n"                                              // 14-16
           "ply_thicknesses = " + thicknesses + "\n"                                                               // 17
           "ply_angles = " + angles + "\n"                                                                         // 18
           "[[part]]\nlayup = \"cross\"\n" + part +                                                               // 19-
           "[[bc]]\ntype = \"clamped\"\nselect = \"plane\"\npoint = [0.0, 0.0, 0.0]\nnormal = [1.0, 0.0, 0.0]\n"
           "[[load]]\ntype = \"pressure\"\npressure = 1000.0\nselect = \"all\"\n"
           "[[probe]]\nname = \"w\"\ndirection = [0.0, 0.0, 1.0]\nselect = \"nearest\"\npoint = [1.0, 0.5, 0.0]\n[solver]\n";
  };
  // orthotropic plies need their reference direction (issue 48): 0 degrees along x
  const std::string plate =
      "generator = \"rectangular_plate\"\nlength = 1.0\nwidth = 1.0\nn1 = 4\nn2 = 4\nfibre_reference = \"u\"\n";
  struct Case {
    std::string name, text;
    int exit_code, line;
    std::string key, fragment;
  };
  const std::vector<Case> cases = {
      {"zero_ply", scene("[0.0, 90.0]", "[0.005, 0.0]", plate), 2, 17, "layup[0].ply_thicknesses", "entry 2"},
      {"file_part_u", scene("[0.0, 90.0]", "[0.005, 0.005]", "generator = \"file\"\nfile = \"" + obj + "\"\n"), 2, 19,
       "part[0].fibre_reference", "fibre_reference = \"vector\""},
      {"file_part_vector",
       scene("[0.0, 90.0]", "[0.005, 0.005]",
             "generator = \"file\"\nfile = \"" + obj + "\"\nfibre_reference = \"vector\"\nfibre_vector = [1.0, 0.0, 0.0]\n"),
       0, 0, "", ""},
      {"radians", scene("[0.0, 1.5708]", "[0.005, 0.005]", plate), 0, 18, "layup[0].ply_angles", "look like radians"},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string path = dir + "/" + c.name + ".toml";
    write_text(path, c.text);
    const ProcResult r = run_flexframe({"check", path}, dir + "/" + c.name);
    EXPECT_EQ(r.exit_code, c.exit_code) << r.describe();
    if (c.key.empty()) continue;
    // an error on stderr, a warning in check's report on stdout
    const std::string& text = c.exit_code == 0 ? r.out : r.err;
    const std::string where = c.name + ".toml:" + std::to_string(c.line) + ":";
    EXPECT_NE(text.find(where), std::string::npos) << r.describe();
    EXPECT_NE(text.find("key '" + c.key + "'"), std::string::npos) << r.describe();
    EXPECT_NE(text.find(c.fragment), std::string::npos) << r.describe();
    if (c.exit_code == 0) { EXPECT_NE(r.out.find("\nwarning: "), std::string::npos) << r.describe(); }
  }
}

// Issue 36: a modal analysis about the unloaded structure does not apply the scene's loads; check
// says so at the first [[load]] (a warning, exit 0), and says nothing when the loads preload it.
TEST(CliEigen, LoadsOfAReferenceModalAnalysisWarn) {
  const std::string dir = fresh_test_dir();
  const ProcResult reference = run_flexframe({"check", "modal_tensioned_strip", "--set", "modal.about=reference"},
                                             dir + "/reference");
  EXPECT_EQ(reference.exit_code, 0) << reference.describe();
  EXPECT_NE(reference.out.find("key 'load[0].type'"), std::string::npos) << reference.describe();
  EXPECT_NE(reference.out.find("have no effect"), std::string::npos) << reference.describe();
  const ProcResult preload = run_flexframe({"check", "modal_tensioned_strip"}, dir + "/preload");
  EXPECT_EQ(preload.exit_code, 0) << preload.describe();
  EXPECT_EQ(preload.out.find("have no effect"), std::string::npos) << preload.describe();
}

}  // namespace
}  // namespace ff::cli::test
