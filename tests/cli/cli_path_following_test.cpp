// Path following that is right or says it is not (core/solve/static_solvers.md §4.4, §6): a run
// whose step budget ends before the end reports 'incomplete' with exit 4 and names where it
// stopped; a path through limit points records them as events in summary.json and results.h5;
// errors of a support entry name that entry at its own line.
#include <gtest/gtest.h>

#include "tests/cli/cli_support.h"

namespace ff::cli::test {
namespace {

TEST(CliPathFollowing, BudgetBeforeTheEndIsIncompleteAndExitsFour) {
  const std::string out = fresh_test_dir() + "/roof";
  const ProcResult r = run_flexframe({"run", "hinged_roof_h127", "--out", out, "--set", "output.frames=false", "--set",
                                      "output.plots=false", "--set", "solver.max_steps=3"},
                                     out + "_log");
  EXPECT_EQ(r.exit_code, 4) << r.out << r.err;
  std::string why;
  const std::optional<Json> s = read_summary(out, &why);
  ASSERT_TRUE(s) << why;
  EXPECT_EQ(summary_string(*s, "status"), "incomplete");
  const std::string reason = summary_string(*s, "reason");
  EXPECT_NE(reason.find("step budget of 3"), std::string::npos) << reason;
  EXPECT_NE(reason.find("(step 3)"), std::string::npos) << reason;
  EXPECT_NE(reason.find("before solver.end = 1"), std::string::npos) << reason;  // the scene's key, not λ_max
  EXPECT_LT(summary_number(*s, "stop_time"), 1.0);
  EXPECT_NE(r.out.find("incomplete"), std::string::npos) << r.out;
}

TEST(CliPathFollowing, SnapThroughAndSnapBackAreEvents) {
  const std::string out = fresh_test_dir() + "/roof635";
  const ProcResult r = run_flexframe(
      {"run", "hinged_roof_h635", "--out", out, "--set", "output.frames=false", "--set", "output.plots=false"}, out + "_log");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  std::string why;
  const std::optional<Json> s = read_summary(out, &why);
  ASSERT_TRUE(s) << why;
  const Json* events = s->get("events");
  ASSERT_TRUE(events && events->kind == Json::Kind::array);
  std::vector<double> limit_loads;
  for (const Json& e : events->array) {
    ASSERT_TRUE(e.get("kind") && e.get("kind")->is_string());
    ASSERT_TRUE(e.get("step") && e.get("step")->is_number());
    ASSERT_TRUE(e.get("detail") && e.get("detail")->is_string());
    if (e.get("kind")->string == "limit_point") limit_loads.push_back(e.get("load_factor")->number);
  }
  // Sze et al. (2004) §3.8d: a maximum near P = 600 (lambda 0.2) and a minimum near P = -390
  ASSERT_EQ(limit_loads.size(), 2u);
  EXPECT_NEAR(limit_loads[0], 0.195, 0.01);
  EXPECT_NEAR(limit_loads[1], -0.128, 0.01);
  EXPECT_NE(r.out.find("2 limit_points"), std::string::npos) << r.out;
}

TEST(CliPathFollowing, ASupportErrorNamesItsOwnEntry) {
  // a fourth [[bc]] is a symmetry plane that crosses the 5-DoF directors (z = 0 plane of a
  // hemisphere whose directors are radial there): the error names bc[3], at its own line
  const std::string dir = fresh_test_dir();
  std::string text = read_text(scene_path("hemisphere_18deg_h004"));
  // without its reference curves (their CSV paths are relative to the bundled scene)
  const auto ref = text.find("[[reference]]"), solver = text.find("[solver]");
  ASSERT_TRUE(ref != std::string::npos && solver != std::string::npos && ref < solver);
  text.erase(ref, solver - ref);
  const std::string extra = "\n[[bc]]\ntype = \"symmetry\"\nselect = \"plane\"\npoint = [0.0, 0.0, 5.0]\nnormal = [0.0, 0.3, 1.0]\n"
                            "tolerance = 10.0\n";
  const auto at = text.find("[[load]]");
  ASSERT_NE(at, std::string::npos);
  text.insert(at, extra.substr(1) + "\n");
  write_text(dir + "/scene.toml", text);
  // the same line count up to the new entry tells its line
  int line = 1;
  for (std::size_t k = 0; k < at; ++k) line += text[k] == '\n';
  const ProcResult r = run_flexframe({"check", dir + "/scene.toml"}, dir + "/log");
  EXPECT_EQ(r.exit_code, 2) << r.out << r.err;
  const std::string all = r.out + r.err;
  EXPECT_NE(all.find("bc[3].type"), std::string::npos) << all;
  EXPECT_NE(all.find("scene.toml:" + std::to_string(line + 1)), std::string::npos) << all << " (expected line " << line + 1 << ")";
  EXPECT_NE(all.find("crosses"), std::string::npos) << all;
}

}  // namespace
}  // namespace ff::cli::test

namespace ff::cli::test {
namespace {

// The final state is always a frame, whatever frame_every: frames 0, 5, 10, ... and the last step.
TEST(CliPathFollowing, TheFinalStateIsAlwaysAFrame) {
  const std::string out = fresh_test_dir() + "/roof";
  const ProcResult r = run_flexframe({"run", "hinged_roof_h127", "--out", out, "--frame-every", "5", "--width", "160",
                                      "--height", "120", "--set", "output.plots=false"},
                                     out + "_log");
  ASSERT_EQ(r.exit_code, 0) << r.out << r.err;
  std::string why;
  const std::optional<Json> s = read_summary(out, &why);
  ASSERT_TRUE(s) << why;
  const int steps = static_cast<int>(summary_number(*s, "steps"));
  ASSERT_GT(steps % 5, 0) << "choose a cadence that does not divide the " << steps << " steps";
  EXPECT_EQ(static_cast<int>(pngs_in(out + "/frames").size()), steps / 5 + 2);
}

// issue 30, item 6: a metric the path never reaches used to vanish from summary.json; it stays
// there as null, "metrics_unreached" says why (the load asked for, how far the path got), and
// the console warns. Load control ending at lambda = 0.4 before the rollup's at_load metrics at
// lambda = 0.5 (completed, exit 0); the roof's budget of 3 steps before its limit point.
TEST(CliPathFollowing, AMetricThePathNeverReachesIsNullWithTheReason) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/rollup";
  const ProcResult r = run_flexframe({"run", "cantilever_rollup", "--out", out, "--no-frames", "--no-plots", "--set",
                                      "solver.end=0.4"},
                                     out + "_log");
  EXPECT_EQ(r.exit_code, 0) << r.describe();
  std::string why;
  std::optional<Json> s = read_summary(out, &why);
  ASSERT_TRUE(s) << why;
  expect_summary_shape(*s);
  const Json* metrics = s->get("metrics");
  const Json* unreached = s->get("metrics_unreached");
  ASSERT_TRUE(metrics && unreached);
  for (const char* name : {"tip_u_half", "tip_w_half"}) {
    const Json* m = metrics->get(name);
    ASSERT_TRUE(m) << name << " left out of summary.json";
    EXPECT_EQ(m->kind, Json::Kind::null) << name;
    const Json* reason = unreached->get(name);
    ASSERT_TRUE(reason && reason->is_string()) << name;
    EXPECT_NE(reason->string.find("end moment M 1488.99 never reached"), std::string::npos) << reason->string;
    EXPECT_NE(reason->string.find("ended at 1191.19"), std::string::npos) << reason->string;
    EXPECT_NE(r.err.find(std::string("warning: metric '") + name + "' has no value: end moment M 1488.99 never reached"),
              std::string::npos)
        << r.describe();
  }

  const std::string roof = dir + "/roof";
  const ProcResult cut = run_flexframe({"run", "hinged_roof_h127", "--out", roof, "--no-frames", "--no-plots", "--set",
                                        "solver.max_steps=3"},
                                       roof + "_log");
  EXPECT_EQ(cut.exit_code, 4) << cut.describe();
  s = read_summary(roof, &why);
  ASSERT_TRUE(s) << why;
  expect_summary_shape(*s);
  for (const char* name : {"limit_load", "w_at_limit", "min_load_after_limit"}) {
    const Json* reason = s->get("metrics_unreached")->get(name);
    ASSERT_TRUE(reason && reason->is_string()) << name;
    EXPECT_NE(reason->string.find("no limit point"), std::string::npos) << reason->string;
  }
  EXPECT_TRUE(s->get("metrics")->get("w_final")->is_number());
}

}  // namespace
}  // namespace ff::cli::test
