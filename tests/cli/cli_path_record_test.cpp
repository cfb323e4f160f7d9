// What a static path did is said, and every attempt is in the record (issue 30, items 7, 8 and
// the static parts of 11; core/solve/static_solvers.md §4.4-§4.5, app/io/results_layout.md):
// a path that runs into reversed load ends incomplete naming solver.min_load_factor; returns to
// the unloaded state and loops are events named in the reason of a completed run; /steps holds
// every attempt, so its corrections sum to newton_iterations on every bundled static scene, and
// static summaries count their cut-backs.
#include <gtest/gtest.h>

#include "app/io/results.h"
#include "cli_support.h"

namespace ff::cli::test {
namespace {

std::string semicylinder_scene() { return std::string(FF_SOURCE_DIR) + "/tests/cli/scenes/pinched_semicylinder.toml"; }

const Json* find_event(const Json& summary, const std::string& kind) {
  const Json* events = summary.get("events");
  if (!events || events->kind != Json::Kind::array) return nullptr;
  for (const Json& e : events->array)
    if (e.get("kind") && e.get("kind")->is_string() && e.get("kind")->string == kind) return &e;
  return nullptr;
}

// Sze et al. 3.7 at 20 x 20: the path passes a limit point, falls through zero load and runs
// into reversed load; it must not end plain 'completed'
TEST(CliPathRecord, PinchedSemiCylinderAt20x20DoesNotEndPlainCompleted) {
  const std::string out = fresh_test_dir() + "/semicyl";
  const ProcResult r = run_flexframe({"run", semicylinder_scene(), "--out", out, "--no-frames", "--no-plots", "--quiet",
                                      "--set", "part[0].n1=20", "--set", "part[0].n2=20", "--set", "solver.max_steps=3000"},
                                     out + "_log");
  // (a budget the path does not run out of: without the bound it came back and ended at λ = 1)
  std::string why;
  const std::optional<Json> s = read_summary(out, &why);
  ASSERT_TRUE(s) << why << r.describe();
  const std::string status = summary_string(*s, "status"), reason = summary_string(*s, "reason");
  EXPECT_FALSE(status == "completed" && reason.empty()) << r.describe();
  EXPECT_EQ(status, "incomplete") << reason;
  EXPECT_EQ(r.exit_code, 4) << r.describe();
  EXPECT_NE(reason.find("solver.min_load_factor = -1"), std::string::npos) << reason;
  EXPECT_NE(reason.find("at step " + std::to_string(static_cast<long long>(summary_number(*s, "steps")))),
            std::string::npos)
      << reason;
  EXPECT_LT(summary_number(*s, "stop_time"), -1.0);
  // the return to the unloaded state is an event, in the reason and on the console
  const Json* unloaded = find_event(*s, "unloaded");
  ASSERT_TRUE(unloaded) << r.out;
  EXPECT_NE(reason.find("returned to the unloaded state at step " +
                        std::to_string(static_cast<long long>(unloaded->get("step")->number))),
            std::string::npos)
      << reason;
  EXPECT_NE(r.out.find("unloaded"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("solver.min_load_factor"), std::string::npos) << r.out;
  // every correction is in /steps (the 20 x 20 run: 2202 of 4155), the rejected attempts
  // as rows that did not converge, at least one per cut-back
  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &why);
  ASSERT_TRUE(h5) << why;
  long long corrections = 0, rejected = 0;
  for (const StepRecord& row : h5->step_log()) {
    corrections += row.stats.iterations;
    rejected += !row.stats.converged;
  }
  EXPECT_EQ(static_cast<double>(corrections), summary_number(*s, "newton_iterations"));
  EXPECT_GT(summary_number(*s, "cutbacks"), 0.0);
  EXPECT_GE(static_cast<double>(rejected), summary_number(*s, "cutbacks"));
}

// the same path with the bound lowered far enough comes back, and completes: the reason and the
// console still say it returned to the unloaded state and looped
TEST(CliPathRecord, ALoopIsNamedInTheReasonOfACompletedRun) {
  const std::string out = fresh_test_dir() + "/roof635";
  const ProcResult r = run_flexframe({"run", "hinged_roof_h635", "--out", out, "--no-frames", "--no-plots"}, out + "_log");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::string why;
  const std::optional<Json> s = read_summary(out, &why);
  ASSERT_TRUE(s) << why;
  EXPECT_EQ(summary_string(*s, "status"), "completed");
  const std::string reason = summary_string(*s, "reason");
  const Json* unloaded = find_event(*s, "unloaded");
  const Json* loop = find_event(*s, "loop");
  ASSERT_TRUE(unloaded && loop) << r.out;
  EXPECT_LT(unloaded->get("step")->number, loop->get("step")->number);
  EXPECT_NE(reason.find("returned to the unloaded state"), std::string::npos) << reason;
  EXPECT_NE(reason.find("(a loop)"), std::string::npos) << reason;
  EXPECT_NE(r.out.find("reason: "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("1 loop"), std::string::npos) << r.out;
  // results.h5 holds the same events and reason
  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &why);
  ASSERT_TRUE(h5) << why;
  EXPECT_EQ(h5->outcome().reason, reason);
  bool has_loop = false;
  for (const PathEvent& e : h5->outcome().events) has_loop = has_loop || e.kind == "loop";
  EXPECT_TRUE(has_loop);
}

TEST(CliPathRecord, StopAtTheFirstLimitPointEndsThere) {
  const std::string out = fresh_test_dir() + "/roof";
  const ProcResult r = run_flexframe({"run", "hinged_roof_h127", "--out", out, "--no-frames", "--no-plots", "--quiet",
                                      "--set", "solver.stop_at_first_limit_point=true"},
                                     out + "_log");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::string why;
  const std::optional<Json> s = read_summary(out, &why);
  ASSERT_TRUE(s) << why;
  EXPECT_EQ(summary_string(*s, "status"), "completed");
  EXPECT_NE(summary_string(*s, "reason").find("first limit point"), std::string::npos) << summary_string(*s, "reason");
  const Json* events = s->get("events");
  ASSERT_TRUE(events && events->kind == Json::Kind::array);
  int limit_points = 0;
  for (const Json& e : events->array) limit_points += e.get("kind")->string == "limit_point";
  EXPECT_EQ(limit_points, 1);
  EXPECT_LT(summary_number(*s, "stop_time"), 0.8);  // the roof's first limit is at P/Pmax 0.74
}

TEST(CliPathRecord, PathKeysOfArcLengthAreRefusedUnderLoadControl) {
  const ProcResult r = run_flexframe({"check", "clamped_plate_pressure", "--set", "solver.min_load_factor=-2"},
                                     fresh_test_dir() + "/log");
  EXPECT_EQ(r.exit_code, 2) << r.describe();
  EXPECT_NE((r.out + r.err).find("solver.min_load_factor belongs to method = \"arc_length\""), std::string::npos)
      << r.describe();
}

// `check` of a static scene says its load range, not a time
TEST(CliPathRecord, CheckOfAStaticSceneSaysTheLoadRange) {
  const ProcResult r = run_flexframe({"check", "hinged_roof_h127"}, fresh_test_dir() + "/log");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  EXPECT_EQ(r.out.find("ends at t ="), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("load factor λ from 0 to 1 (solver.end"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("λ × 3000"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("λ ≥ -1 (solver.min_load_factor)"), std::string::npos) << r.out;
}

// Every bundled static scene (arc-length ones cut at 40 steps): /steps has a row per attempt,
// its corrections sum to newton_iterations, rows that did not converge are the rejected
// attempts, and summary.json and results.h5 count the cut-backs.
TEST(CliPathRecord, EveryAttemptOfEveryBundledStaticSceneIsInSteps) {
  int scenes = 0, with_rejections = 0;
  for (const std::string& name : bundled_scene_names()) {
    const std::string text = read_text(scene_path(name));
    if (text.find("model = \"shell\"\nanalysis = \"static\"") == std::string::npos) continue;
    ++scenes;
    const bool arc = text.find("method = \"arc_length\"") != std::string::npos;
    const std::string out = fresh_test_dir() + "/" + name;
    std::vector<std::string> args = {"run", name, "--out", out, "--no-frames", "--no-plots", "--quiet"};
    if (arc) args.insert(args.end(), {"--set", "solver.max_steps=40"});
    const ProcResult r = run_flexframe(args, out + "_log");
    ASSERT_TRUE(r.exit_code == 0 || r.exit_code == 4) << name << ": " << r.describe();
    std::string why;
    const std::optional<Json> s = read_summary(out, &why);
    ASSERT_TRUE(s) << name << ": " << why;
    const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &why);
    ASSERT_TRUE(h5) << name << ": " << why;
    long long corrections = 0, rejected = 0, accepted = 0;
    for (const StepRecord& row : h5->step_log()) {
      corrections += row.stats.iterations;
      (row.stats.converged ? accepted : rejected) += 1;
    }
    EXPECT_EQ(static_cast<double>(corrections), summary_number(*s, "newton_iterations")) << name;
    EXPECT_EQ(static_cast<double>(accepted), summary_number(*s, "steps")) << name;
    const double cutbacks = summary_number(*s, "cutbacks");
    ASSERT_FALSE(std::isnan(cutbacks)) << name << ": summary.json has no cutbacks";
    EXPECT_GE(static_cast<double>(rejected), cutbacks) << name;
    EXPECT_EQ(h5->outcome().cutbacks, static_cast<std::int64_t>(cutbacks)) << name;
    with_rejections += rejected > 0;
  }
  EXPECT_GE(scenes, 8);
  EXPECT_GE(with_rejections, 1);  // the check has teeth: some bundled path rejects attempts
}

// a run that dies on its first step still records the attempts it died on: /steps rows with
// converged = false after the last converged step, summing to newton_iterations
TEST(CliPathRecord, ADivergedRunKeepsTheAttemptsItEndedOn) {
  const std::string out = fresh_test_dir() + "/rollup";
  const ProcResult r = run_flexframe({"run", "cantilever_rollup", "--out", out, "--no-frames", "--no-plots", "--quiet",
                                      "--set", "solver.max_iterations=2", "--set", "solver.min_step=0.01"},
                                     out + "_log");
  EXPECT_EQ(r.exit_code, 3) << r.describe();
  std::string why;
  const std::optional<Json> s = read_summary(out, &why);
  ASSERT_TRUE(s) << why;
  EXPECT_EQ(summary_string(*s, "status"), "diverged");
  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &why);
  ASSERT_TRUE(h5) << why;
  const std::vector<StepRecord> log = h5->step_log();
  ASSERT_FALSE(log.empty());
  long long corrections = 0;
  for (const StepRecord& row : log) {
    corrections += row.stats.iterations;
    EXPECT_FALSE(row.stats.converged);
    EXPECT_EQ(row.step, static_cast<std::int64_t>(summary_number(*s, "steps")) + 1);
  }
  EXPECT_GT(corrections, 0);
  EXPECT_EQ(static_cast<double>(corrections), summary_number(*s, "newton_iterations"));
  EXPECT_GE(static_cast<double>(log.size()), summary_number(*s, "cutbacks"));
  EXPECT_GT(summary_number(*s, "cutbacks"), 0.0);
  EXPECT_EQ(h5->outcome().cutbacks, static_cast<std::int64_t>(summary_number(*s, "cutbacks")));
  // each halving is a row at half the load increment of the one before
  for (std::size_t k = 1; k < log.size(); ++k) { EXPECT_DOUBLE_EQ(log[k].stats.dt, 0.5 * log[k - 1].stats.dt); }
}

}  // namespace
}  // namespace ff::cli::test
