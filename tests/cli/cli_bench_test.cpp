// `flexframe bench --solve --json FILE`: the file carries the element block and one row per plate
// with the keys docs/performance.md reads (not the timings' values: those are benchmarks, not
// tests), and the counted flops are the element's, so they match count_element_flops.
// `flexframe bench --scene`: whole runs timed, with the counts `run` reports.
// `flexframe bench --error-bars`: runs with bars on and off in alternated pairs, the share the runs
// print, the target per kind of scene, and a run that fails keeps its log and fails the command.

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <filesystem>

#include "cli_support.h"
#include "core/shell/cb_shell.h"
#include "app/bench/sample_elements.h"

namespace ff::cli::test {
namespace {

TEST(CliBench, SolveWritesTheElementBlockAndThePlateRows) {
  const std::string dir = fresh_test_dir();
  const std::string json = dir + "/bench.json";
  const ProcResult r = run_flexframe({"bench", "--solve", "--max-n", "16", "--repeat", "1", "--json", json}, dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json j = nlohmann::json::parse(read_text(json));

  const nlohmann::json& e = j.at("element");
  for (const char* key : {"force_us", "force_tangent_us", "same_flop_product_us"}) { EXPECT_GT(e.at(key).get<double>(), 0.0) << key; }
  // the bench's element: the curved, deformed sample with 5 DoF, hr and ans
  shell::ShellOptions o;
  o.hr = o.ans = true;
  const shell::ElementPoses ref = shell::samples::curved();
  const shell::ElementFlops flops =
      shell::count_element_flops(shell::CbShellElement(ref, shell::isotropic_section(2.0e5, 0.3, 0.05), o), shell::samples::deformed(ref, 5));
  EXPECT_EQ(e.at("force_flops").get<long long>(), flops.force);
  EXPECT_EQ(e.at("force_tangent_flops").get<long long>(), flops.force_tangent);

  const nlohmann::json& plates = j.at("plate");
  ASSERT_EQ(plates.size(), 1u);  // --max-n 16
  const nlohmann::json& p = plates.at(0);
  EXPECT_EQ(p.at("n").get<int>(), 16);
  EXPECT_EQ(p.at("dofs").get<int>(), 1360);  // 17 x 17 nodes x 5, minus the clamped edge's 17 x 5
  EXPECT_GT(p.at("assembly_ms").get<double>(), 0.0);
  EXPECT_GT(p.at("factorize_solve_ms").get<double>(), 0.0);
  EXPECT_FALSE(p.at("backend").get<std::string>().empty());
  // which BLAS kernels the factorizations ran on ("OpenBLAS, Haswell kernels", or "not OpenBLAS")
  EXPECT_NE(j.at("blas").get<std::string>().find("BLAS"), std::string::npos) << j.at("blas");
}

// `flexframe bench --modes N`: N modes against one factorization per plate; the JSON rows carry the
// counts (one factorization, the Lanczos solves) and the first frequency of the Leissa plate
// (16 x 16: 90.68 Hz, +0.8 % above Leissa's 89.93, as modal_clamped_plate at that mesh)
TEST(CliBench, ModesTimesOneFactorizationPerPlate) {
  const std::string dir = fresh_test_dir();
  const std::string json = dir + "/bench.json";
  const ProcResult r = run_flexframe({"bench", "--modes", "4", "--max-n", "16", "--json", json}, dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_NE(r.out.find("4 natural modes against one factorization"), std::string::npos) << r.describe();
  const nlohmann::json rows = nlohmann::json::parse(read_text(json)).at("modes");
  ASSERT_EQ(rows.size(), 1u);  // --max-n 16
  const nlohmann::json& p = rows.at(0);
  EXPECT_EQ(p.at("plate").get<int>(), 16);
  EXPECT_EQ(p.at("unknowns").get<int>(), 1125);  // 15 x 15 interior nodes x 5
  EXPECT_EQ(p.at("factorizations").get<int>(), 1);
  EXPECT_GT(p.at("lanczos_solves").get<int>(), 4);
  EXPECT_NEAR(p.at("f1_hz").get<double>(), 90.678, 0.01);
}

// `flexframe bench --estimate DOFS`: MUMPS's analysis alone of the plate pattern with at least that
// many DoFs: 2000 DoFs is a 20 x 20 grid of 5-DoF nodes, whose lower triangle holds 15 entries per
// node and 25 per pair of neighbouring nodes (20·19 across, 20·19 along, 2·19² diagonal): 43 050
TEST(CliBench, EstimateAnalysesThePlatePatternOfTheSizeAsked) {
  const std::string dir = fresh_test_dir();
  const std::string json = dir + "/estimate.json";
  const ProcResult r = run_flexframe({"bench", "--estimate", "2000", "--json", json}, dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json rows = nlohmann::json::parse(read_text(json)).at("estimates");
  ASSERT_EQ(rows.size(), 1u);
  const nlohmann::json& e = rows.at(0);
  EXPECT_EQ(e.at("nodes_a_side").get<int>(), 20);
  EXPECT_EQ(e.at("dofs").get<long long>(), 2000);
  EXPECT_EQ(e.at("entries").get<double>(), 15.0 * 400 + 25.0 * (2 * 20 * 19 + 2 * 19 * 19));
  EXPECT_EQ(e.at("ranks").get<int>(), 1);
  // nested dissection of a 20 x 20 grid: a separator of about 20 nodes, 100 DoFs, at the root
  EXPECT_GE(e.at("largest_front").get<int>(), 100);
  EXPECT_GT(e.at("flops").get<double>(), 0.0);
  EXPECT_GE(e.at("factor_entries").get<double>(), 43050.0);  // at least the matrix's own entries
  EXPECT_GT(e.at("mb_max_rank").get<double>(), 0.0);

  const ProcResult bad = run_flexframe({"bench", "--estimate", "5"}, dir + "/bad");
  EXPECT_EQ(bad.exit_code, 2) << bad.describe();
  EXPECT_NE(bad.err.find("--estimate"), std::string::npos) << bad.describe();
}

// `flexframe bench --scene`: the counts it reports are those of `flexframe run` on the same scene
// (one solver, whatever verb drives it), and the JSON carries them with the timings
TEST(CliBench, SceneReportsTheCountsOfTheRunItTimes) {
  const std::string dir = fresh_test_dir();
  const std::string json = dir + "/bench.json";
  const ProcResult b =
      run_flexframe({"bench", "--scene", "cantilever_rollup", "--repeat", "2", "--json", json}, dir + "/bench");
  ASSERT_EQ(b.exit_code, 0) << b.describe();
  const ProcResult r = run_flexframe({"run", "cantilever_rollup", "--no-frames", "--no-plots", "--quiet", "--out",
                                      dir + "/run"},
                                     dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  const nlohmann::json summary = nlohmann::json::parse(read_text(dir + "/run/summary.json"));
  const nlohmann::json j = nlohmann::json::parse(read_text(json));
  EXPECT_EQ(j.at("repeat").get<int>(), 2);
  ASSERT_EQ(j.at("scenes").size(), 1u);
  const nlohmann::json& row = j.at("scenes").at(0);
  EXPECT_EQ(row.at("status").get<std::string>(), "completed");
  for (const char* key : {"steps", "newton_iterations", "jacobian_updates"})
    EXPECT_EQ(row.at(key).get<long long>(), summary.at(key).get<long long>()) << key;
  EXPECT_GT(row.at("run_s").get<double>(), 0.0);
  EXPECT_NEAR(row.at("total_s").get<double>(), row.at("setup_s").get<double>() + row.at("run_s").get<double>(), 1e-12);
  EXPECT_NE(b.out.find("| cantilever_rollup | completed |"), std::string::npos) << b.out;
}

// a scene that does not exist is refused before anything is timed; a run that stops early is
// timed, says why, and makes the command fail
TEST(CliBench, SceneRefusesAMissingSceneAndFailsOnAnUnfinishedRun) {
  const std::string dir = fresh_test_dir();
  const ProcResult missing =
      run_flexframe({"bench", "--scene", "cantilever_rollup", "--scene", "no_such_scene", "--repeat", "1"}, dir + "/m");
  EXPECT_NE(missing.exit_code, 0) << missing.describe();
  EXPECT_NE(missing.err.find("no_such_scene"), std::string::npos) << missing.describe();
  EXPECT_EQ(missing.out.find("| cantilever_rollup |"), std::string::npos) << missing.describe();

  const std::string json = dir + "/bench.json";
  const ProcResult cut = run_flexframe({"bench", "--scene", "hinged_roof_h127", "--set", "solver.max_steps=2",
                                        "--repeat", "1", "--json", json},
                                       dir + "/cut");
  EXPECT_NE(cut.exit_code, 0) << cut.describe();
  EXPECT_NE(cut.err.find("did not complete"), std::string::npos) << cut.describe();
  const nlohmann::json row = nlohmann::json::parse(read_text(json)).at("scenes").at(0);
  EXPECT_EQ(row.at("status").get<std::string>(), "incomplete");
  EXPECT_EQ(row.at("steps").get<long long>(), 2);
  EXPECT_NE(row.at("reason").get<std::string>().find("step budget"), std::string::npos) << row;
}

TEST(CliBench, ErrorBarsTimesRunsWithAndWithoutBarsInPairs) {
  const std::string dir = fresh_test_dir();
  const std::string json = dir + "/bench.json";
  const ProcResult b = run_flexframe({"bench", "--error-bars", "--scene", "clamped_plate_pressure", "--scene",
                                      "cantilever_step_load", "--repeat", "2",
                                      "--json", json},
                                     dir + "/bench");
  ASSERT_EQ(b.exit_code, 0) << b.describe();
  const nlohmann::json j = nlohmann::json::parse(read_text(json));
  EXPECT_EQ(j.at("rounds").get<int>(), 2);
  ASSERT_EQ(j.at("scenes").size(), 2u);
  for (const nlohmann::json& row : j.at("scenes")) {
    EXPECT_EQ(row.at("status").get<std::string>(), "completed") << row;
    ASSERT_EQ(row.at("off_s").size(), 2u) << row;
    ASSERT_EQ(row.at("on_s").size(), 2u) << row;
    EXPECT_GT(row.at("ratio_median").get<double>(), 0.0) << row;
    // the share the runs print is a share of work done, never 0 with twins solved
    EXPECT_GT(row.at("run_share_median").get<double>(), 0.0) << row;
  }
  EXPECT_FALSE(j.at("scenes").at(0).at("dynamic").get<bool>());
  EXPECT_EQ(j.at("scenes").at(0).at("target_share").get<double>(), 0.35);
  EXPECT_TRUE(j.at("scenes").at(1).at("dynamic").get<bool>());
  EXPECT_EQ(j.at("scenes").at(1).at("target_share").get<double>(), 0.60);
  EXPECT_NE(b.out.find("| clamped_plate_pressure | static/eigen | completed |"), std::string::npos) << b.out;
  // the rounds alternate which run goes first
  const std::size_t on1 = b.err.find("clamped_plate_pressure, round 1 of 2, bars on");
  const std::size_t off1 = b.err.find("clamped_plate_pressure, round 1 of 2, bars off");
  const std::size_t on2 = b.err.find("clamped_plate_pressure, round 2 of 2, bars on");
  const std::size_t off2 = b.err.find("clamped_plate_pressure, round 2 of 2, bars off");
  ASSERT_TRUE(on1 != std::string::npos && off1 != std::string::npos && on2 != std::string::npos &&
              off2 != std::string::npos)
      << b.describe();
  EXPECT_LT(off1, on1);
  EXPECT_LT(on2, off2);

  // a run that does not complete is not timed as if it had: the command fails and keeps the logs
  const ProcResult cut = run_flexframe({"bench", "--error-bars", "--scene", "hinged_roof_h127", "--set",
                                        "solver.max_steps=2", "--repeat", "1"},
                                       dir + "/cut");
  EXPECT_EQ(cut.exit_code, 1) << cut.describe();
  EXPECT_NE(cut.err.find("hinged_roof_h127 failed: it exited with code"), std::string::npos) << cut.describe();
  EXPECT_NE(cut.err.find("the runs' logs are kept in"), std::string::npos) << cut.describe();
  EXPECT_NE(cut.out.find("| hinged_roof_h127 | static/eigen | failed |"), std::string::npos) << cut.describe();
}

// a --json file that cannot be written fails the command (exit 1) and names the path and why:
// a folder that does not exist (open fails) and /dev/full (open succeeds, the write fails), for
// --scene and --solve
TEST(CliBench, AJsonFileThatCannotBeWrittenFailsTheCommand) {
  const std::string dir = fresh_test_dir();
  const std::string missing = dir + "/no_such_folder/bench.json";
  const ProcResult open = run_flexframe({"bench", "--scene", "cantilever_rollup", "--repeat", "1", "--json", missing},
                                        dir + "/open");
  EXPECT_EQ(open.exit_code, 1) << open.describe();
  EXPECT_NE(open.err.find("cannot write " + missing + ": No such file or directory"), std::string::npos)
      << open.describe();
  // a device is no file of the bench's to write (every output is opened so: core/frame/output_file.h)
  if (std::filesystem::exists("/dev/full")) {
    const ProcResult device = run_flexframe(
        {"bench", "--scene", "cantilever_rollup", "--repeat", "1", "--json", "/dev/full"}, dir + "/device");
    EXPECT_EQ(device.exit_code, 1) << device.describe();
    EXPECT_NE(device.err.find("cannot write /dev/full: it is not a regular file"), std::string::npos)
        << device.describe();
  }
  // a full disk: a small tmpfs filled to the last byte before the bench writes its JSON there
  SmallDisk disk(dir + "/tiny", 64);
  if (!disk.mounted()) GTEST_SKIP() << disk.why();
  {
    std::ofstream filler(dir + "/tiny/filler", std::ios::binary);
    const std::string block(4096, 'x');
    while (filler.write(block.data(), static_cast<std::streamsize>(block.size())) && filler.flush()) {
    }
  }
  {
    std::ofstream last(dir + "/tiny/last", std::ios::binary);
    for (char c = 'x'; last.put(c) && last.flush();) {
    }
  }
  const std::string full_json = dir + "/tiny/bench.json";
  const ProcResult full = run_flexframe({"bench", "--scene", "cantilever_rollup", "--repeat", "1", "--json", full_json},
                                        dir + "/full");
  EXPECT_EQ(full.exit_code, 1) << full.describe();
  EXPECT_NE(full.err.find("cannot write " + full_json + ": No space left on device"), std::string::npos)
      << full.describe();
  const ProcResult solve =
      run_flexframe({"bench", "--solve", "--max-n", "16", "--repeat", "1", "--json", full_json}, dir + "/solve");
  EXPECT_EQ(solve.exit_code, 1) << solve.describe();
  EXPECT_NE(solve.err.find("cannot write " + full_json + ": No space left on device"), std::string::npos)
      << solve.describe();
}

}  // namespace
}  // namespace ff::cli::test
