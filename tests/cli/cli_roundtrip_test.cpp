// HDF5 round trip of a real run: what summary.json reports and what results.h5 holds agree
// (hub_beam_fem_tau1 cut at t_end = 2.0 s, so the 2 s metric is the last frame's probe).

#include <gtest/gtest.h>

#include "app/io/results.h"
#include "cli_support.h"

namespace ff::cli::test {
namespace {

TEST(CliRoundTrip, SummaryAndResultsAgree) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  const ProcResult r = run_flexframe(
      {"run", "hub_beam_fem_tau1", "--out", out, "--no-frames", "--no-plots", "--quiet", "--set", "solver.end=2.0"},
      dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::string err;
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err;
  expect_summary_shape(*s);
  const Json* metrics = s->get("metrics");
  ASSERT_TRUE(metrics);
  const Json* at2 = metrics->get("tip_transverse_at_2s_m");
  ASSERT_TRUE(at2 && at2->is_number()) << "no metric tip_transverse_at_2s_m";

  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  EXPECT_EQ(h5->outcome().status, RunStatus::completed) << h5->outcome().reason;
  const std::vector<double> t = h5->times();
  ASSERT_EQ(t.size(), 41u);  // t = 0, 0.05, ..., 2.0
  EXPECT_NEAR(t.back(), 2.0, 1e-9);
  EXPECT_NEAR(t.back(), summary_number(*s, "stop_time"), 1e-12);
  const std::vector<double> tip = h5->probe_series("tip_transverse");
  ASSERT_EQ(tip.size(), t.size()) << "no probe tip_transverse";
  EXPECT_NEAR(tip.back(), at2->number, 1e-12);
  EXPECT_NE(tip.back(), 0.0);

  // every summary metric is in the file with the same value, and nothing else
  const auto file_metrics = h5->metrics();
  EXPECT_EQ(file_metrics.size(), metrics->object.size());
  for (const auto& [name, v] : metrics->object) {
    const auto it = std::find_if(file_metrics.begin(), file_metrics.end(), [&](const auto& m) { return m.first == name; });
    ASSERT_NE(it, file_metrics.end()) << name << " is not in results.h5";
    EXPECT_NEAR(it->second, v.number, 1e-12 * std::max(1.0, std::abs(v.number))) << name;
  }

  // mesh and frames agree in size
  const RunInfo& info = h5->info();
  ASSERT_GT(info.mesh.point_count(), 0u);
  for (std::size_t i : {std::size_t{0}, t.size() - 1}) {
    const Frame f = h5->frame(i);
    EXPECT_EQ(info.mesh.point_count(), f.points.size() / 3) << "frame " << i;
    EXPECT_EQ(f.points.size() % 3, 0u);
    EXPECT_EQ(f.base_points.size(), f.points.size());
    EXPECT_EQ(f.probes.size(), info.probes.size());
  }

  // the file is self-contained: the scene text, name and effects
  EXPECT_EQ(info.scene_text, read_text(scene_path("hub_beam_fem_tau1")));
  EXPECT_EQ(info.scene_name, "hub_beam_fem_tau1");
  const Json* effects = s->get("effects");
  ASSERT_TRUE(effects);
  std::vector<std::string> fx;
  for (const Json& e : effects->array) fx.push_back(e.string);
  EXPECT_EQ(info.effects, fx);
}

// The shell-dynamics store keeps NOI and NOU per solver step (/steps) although it publishes a
// frame every 7th step: one row per step, summing to summary.json's totals and, between two
// frames, to that frame's aggregated stats.
TEST(CliRoundTrip, ShellDynamicsStoresEveryStepsIterations) {
  const std::string dir = fresh_test_dir();
  const std::string out = dir + "/out";
  const ProcResult r = run_flexframe({"run", "double_pendulum_shells", "--out", out, "--no-frames", "--no-plots",
                                      "--quiet", "--set", "solver.end=0.01", "--set", "solver.output_every=7", "--set",
                                      "part[0].n1=4", "--set", "part[0].n2=4", "--set", "part[1].n1=4", "--set",
                                      "part[1].n2=4"},
                                     dir + "/run");
  ASSERT_EQ(r.exit_code, 0) << r.describe();
  std::string err;
  const std::optional<Json> s = read_summary(out, &err);
  ASSERT_TRUE(s) << err;
  const std::unique_ptr<io::ResultReader> h5 = io::ResultReader::open(out + "/results.h5", &err);
  ASSERT_TRUE(h5) << err;
  const std::vector<StepRecord> log = h5->step_log();
  ASSERT_EQ(static_cast<double>(log.size()), summary_number(*s, "steps"));  // 20 steps of 5e-4
  long long noi = 0, nou = 0;
  for (std::size_t i = 0; i < log.size(); ++i) {
    EXPECT_EQ(log[i].step, static_cast<std::int64_t>(i + 1));
    EXPECT_NEAR(log[i].time, 5e-4 * static_cast<double>(i + 1), 1e-12);
    EXPECT_GE(log[i].stats.iterations, 1);
    EXPECT_TRUE(log[i].stats.converged);
    noi += log[i].stats.iterations;
    nou += log[i].stats.jacobian_updates;
  }
  EXPECT_EQ(static_cast<double>(noi), summary_number(*s, "newton_iterations"));
  EXPECT_EQ(static_cast<double>(nou), summary_number(*s, "jacobian_updates"));
  // frames at steps 0, 7, 14, 20; each frame's NOI is the sum of its steps
  const std::vector<StepStats> stats = h5->stats();
  ASSERT_EQ(stats.size(), 4u);
  std::size_t k = 0;
  for (std::size_t i = 1; i < stats.size(); ++i) {
    const std::int64_t last = h5->frame(i).step;
    int sum = 0;
    for (; k < log.size() && log[k].step <= last; ++k) sum += log[k].stats.iterations;
    EXPECT_EQ(stats[i].iterations, sum) << "frame " << i;
  }
}

}  // namespace
}  // namespace ff::cli::test
