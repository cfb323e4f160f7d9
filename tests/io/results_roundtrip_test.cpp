// Round trips through results.h5: RunInfo, every frame bitwise, outcome, metrics, attributes,
// and the flush cadence of append().

#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "app/io/results.h"
#include "results_test_data.h"

namespace ff::io {
namespace {

using test::make_frame;
using test::make_info;
using test::out_path;

void expect_same_info(const RunInfo& want, const RunInfo& got) {
  EXPECT_EQ(got.scene_name, want.scene_name);
  EXPECT_EQ(got.scene_path, want.scene_path);
  EXPECT_EQ(got.scene_text, want.scene_text);
  EXPECT_EQ(got.effects, want.effects);
  EXPECT_EQ(got.settings, want.settings);
  EXPECT_EQ(got.time_unit, want.time_unit);
  EXPECT_TRUE(test::bitwise_equal(got.mesh.reference_points, want.mesh.reference_points));
  EXPECT_EQ(got.mesh.lines, want.mesh.lines);
  EXPECT_EQ(got.mesh.triangles, want.mesh.triangles);
  EXPECT_EQ(got.mesh.quads, want.mesh.quads);
  ASSERT_EQ(got.probes.size(), want.probes.size());
  for (std::size_t k = 0; k < want.probes.size(); ++k) {
    EXPECT_EQ(got.probes[k].name, want.probes[k].name);
    EXPECT_EQ(got.probes[k].unit, want.probes[k].unit);
    EXPECT_EQ(got.probes[k].label, want.probes[k].label);
  }
  ASSERT_EQ(got.fields.size(), want.fields.size());
  for (std::size_t k = 0; k < want.fields.size(); ++k) {
    EXPECT_EQ(got.fields[k].name, want.fields[k].name);
    EXPECT_EQ(got.fields[k].unit, want.fields[k].unit);
    EXPECT_EQ(got.fields[k].label, want.fields[k].label);
  }
}

TEST(ResultStore, RoundTripRunInfoAndFramesBitwise) {
  const std::string path = out_path("roundtrip.h5");
  RunInfo info = make_info(60, 3, 2);
  // probe order differs from name order: the reader must keep the RunInfo order
  info.probes[0].name = "z_hub_angle";
  constexpr std::int64_t kFrames = 317;  // not a multiple of the flush block or chunk
  std::string error;
  {
    auto w = ResultWriter::create(path, info, &error);
    ASSERT_TRUE(w) << error;
    w->set_attribute("render_backend", "egl");
    w->set_attribute("git_hash", "0123abc");
    for (std::int64_t i = 0; i < kFrames; ++i) { ASSERT_TRUE(w->append(make_frame(info, i), &error)) << error; }
    w->set_attribute("render_backend", "osmesa");  // repeated key: last value wins, first place
    EXPECT_EQ(w->frames_appended(), static_cast<std::size_t>(kFrames));
    RunOutcome done;
    done.stop_time = make_frame(info, kFrames - 1).time;
    done.steps = kFrames - 1;
    done.wall_time_s = 1.25;
    ASSERT_TRUE(w->finish(done, {{"max_tip_deflection_m", 0.123}}, &error)) << error;
  }

  auto r = ResultReader::open(path, &error);
  ASSERT_TRUE(r) << error;
  expect_same_info(info, r->info());
  ASSERT_EQ(r->frame_count(), static_cast<std::size_t>(kFrames));
  std::vector<double> times = r->times();
  std::vector<StepStats> stats = r->stats();
  ASSERT_EQ(times.size(), static_cast<std::size_t>(kFrames));
  ASSERT_EQ(stats.size(), static_cast<std::size_t>(kFrames));
  std::vector<std::vector<double>> series(info.probes.size());
  for (std::size_t k = 0; k < info.probes.size(); ++k) series[k] = r->probe_series(info.probes[k].name);
  for (std::int64_t i = 0; i < kFrames; ++i) {
    const Frame want = make_frame(info, i);
    const std::size_t u = static_cast<std::size_t>(i);
    ASSERT_TRUE(test::same_frame(want, r->frame(u)));
    EXPECT_TRUE(test::bitwise_equal(times[u], want.time));
    EXPECT_EQ(stats[u].iterations, want.stats.iterations);
    EXPECT_EQ(stats[u].converged, want.stats.converged);
    EXPECT_TRUE(test::bitwise_equal(stats[u].residual_norm, want.stats.residual_norm));
    for (std::size_t k = 0; k < info.probes.size(); ++k) {
      ASSERT_EQ(series[k].size(), static_cast<std::size_t>(kFrames));
      EXPECT_TRUE(test::bitwise_equal(series[k][u], want.probes[k]));
    }
  }
  EXPECT_TRUE(r->probe_series("no_such_probe").empty());
  EXPECT_THROW(r->frame(kFrames), std::out_of_range);

  RunOutcome o = r->outcome();
  EXPECT_EQ(o.status, RunStatus::completed);
  EXPECT_EQ(o.reason, "");
  EXPECT_EQ(o.steps, kFrames - 1);
  EXPECT_DOUBLE_EQ(o.wall_time_s, 1.25);
  using Attr = std::pair<std::string, std::string>;
  EXPECT_EQ(r->attributes(), (std::vector<Attr>{{"render_backend", "osmesa"}, {"git_hash", "0123abc"}}));
}

TEST(ResultStore, EmptyMeshNoProbesNoEffects) {
  const std::string path = out_path("empty_mesh.h5");
  RunInfo info = make_info(0, 0, 1);  // a field over zero points still has a data set
  info.effects.clear();
  info.settings.clear();
  info.scene_text.clear();
  std::string error;
  {
    auto w = ResultWriter::create(path, info, &error);
    ASSERT_TRUE(w) << error;
    for (int i = 0; i < 7; ++i) { ASSERT_TRUE(w->append(make_frame(info, i), &error)) << error; }
    ASSERT_TRUE(w->finish({}, {}, &error)) << error;
  }
  auto r = ResultReader::open(path, &error);
  ASSERT_TRUE(r) << error;
  expect_same_info(info, r->info());
  ASSERT_EQ(r->frame_count(), 7u);
  for (int i = 0; i < 7; ++i) { EXPECT_TRUE(test::same_frame(make_frame(info, i), r->frame(i))); }
  EXPECT_TRUE(r->metrics().empty());
  EXPECT_TRUE(r->attributes().empty());
  EXPECT_EQ(r->outcome().status, RunStatus::completed);
}

TEST(ResultStore, FinishDivergedWithReasonAndMetrics) {
  const std::string path = out_path("diverged.h5");
  const RunInfo info = make_info(12, 1, 0);
  std::string error;
  RunOutcome diverged;
  diverged.status = RunStatus::diverged;
  diverged.reason = "non-finite residual at step 42 (DoF 17, node 3 theta_2); last converged t = 0.041 s";
  diverged.stop_time = 0.041;
  diverged.steps = 41;
  diverged.wall_time_s = 3.5;
  const std::vector<std::pair<std::string, double>> metrics{
      {"tip_deflection_m", 1.0 / 3.0}, {"energy_drift", -2.5e-12}, {"a_first_by_name_last", 7.0}};
  {
    auto w = ResultWriter::create(path, info, &error);
    ASSERT_TRUE(w) << error;
    for (int i = 0; i <= 41; ++i) { ASSERT_TRUE(w->append(make_frame(info, i), &error)) << error; }
    ASSERT_TRUE(w->finish(diverged, metrics, &error)) << error;
    // the writer is closed now
    EXPECT_FALSE(w->append(make_frame(info, 42), &error));
    EXPECT_NE(error.find("after finish"), std::string::npos) << error;
    EXPECT_FALSE(w->finish(diverged, metrics, &error));
  }
  auto r = ResultReader::open(path, &error);
  ASSERT_TRUE(r) << error;
  EXPECT_EQ(r->frame_count(), 42u);
  RunOutcome o = r->outcome();
  EXPECT_EQ(o.status, RunStatus::diverged);
  EXPECT_EQ(o.reason, diverged.reason);
  EXPECT_TRUE(test::bitwise_equal(o.stop_time, diverged.stop_time));
  EXPECT_EQ(o.steps, 41);
  EXPECT_TRUE(test::bitwise_equal(o.wall_time_s, 3.5));
  auto got = r->metrics();
  ASSERT_EQ(got.size(), metrics.size());
  for (std::size_t k = 0; k < metrics.size(); ++k) {  // in the order given, values bitwise
    EXPECT_EQ(got[k].first, metrics[k].first);
    EXPECT_TRUE(test::bitwise_equal(got[k].second, metrics[k].second));
  }
}

TEST(ResultStore, AppendFlushesEvery50FramesOrOneSecond) {
  const std::string path = out_path("cadence.h5");
  const RunInfo info = make_info(6, 1, 0);
  std::string error;
  auto w = ResultWriter::create(path, info, &error);
  ASSERT_TRUE(w) << error;
  std::int64_t i = 0;
  for (; i < 49; ++i) { ASSERT_TRUE(w->append(make_frame(info, i), &error)) << error; }
  // 49 appends take microseconds: nothing written yet unless this machine stalled for 1 s
  const auto started = std::chrono::steady_clock::now();
  ASSERT_TRUE(w->append(make_frame(info, i++), &error)) << error;
  EXPECT_EQ(w->frames_flushed(), 50u);
  ASSERT_TRUE(w->append(make_frame(info, i++), &error)) << error;
  if (std::chrono::steady_clock::now() - started < std::chrono::milliseconds(500)) {
    EXPECT_EQ(w->frames_flushed(), 50u);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(1100));
  ASSERT_TRUE(w->append(make_frame(info, i++), &error)) << error;
  EXPECT_EQ(w->frames_flushed(), 52u);  // more than 1 s since the last flush
  EXPECT_EQ(w->frames_appended(), 52u);
}

TEST(ResultStore, RejectsFramesThatDoNotMatchRunInfo) {
  const std::string path = out_path("mismatch.h5");
  const RunInfo info = make_info(10, 2, 1);
  std::string error;
  {
    auto w = ResultWriter::create(path, info, &error);
    ASSERT_TRUE(w) << error;
    ASSERT_TRUE(w->append(make_frame(info, 0), &error)) << error;
    Frame bad = make_frame(info, 1);
    bad.points.pop_back();
    EXPECT_FALSE(w->append(bad, &error));
    EXPECT_NE(error.find("points has 29 values, expected 3 x 10"), std::string::npos) << error;
    EXPECT_NE(error.find(path), std::string::npos) << error;
    bad = make_frame(info, 1);
    bad.probes.push_back(1.0);
    EXPECT_FALSE(w->append(bad, &error));
    bad = make_frame(info, 1);
    bad.fields[0].resize(3);
    EXPECT_FALSE(w->append(bad, &error));
    EXPECT_NE(error.find("field 'field_0'"), std::string::npos) << error;
    ASSERT_TRUE(w->append(make_frame(info, 1), &error)) << error;
    ASSERT_TRUE(w->finish({}, {}, &error)) << error;
  }
  auto r = ResultReader::open(path, &error);
  ASSERT_TRUE(r) << error;
  ASSERT_EQ(r->frame_count(), 2u);  // the rejected frames left no trace
  EXPECT_TRUE(test::same_frame(make_frame(info, 1), r->frame(1)));
}

// The per-step convergence log: frames that carry the steps since the previous frame give one
// /steps row per step, in order and bitwise; a frame without a log is its own single step; the
// initial frame (step 0) is no step.
TEST(ResultStore, StepLogKeepsEveryStepBetweenFrames) {
  const std::string path = out_path("step_log.h5");
  const RunInfo info = make_info(8, 1, 1);
  std::vector<StepRecord> want;
  std::string error;
  {
    auto w = ResultWriter::create(path, info, &error);
    ASSERT_TRUE(w) << error;
    ASSERT_TRUE(w->append(make_frame(info, 0), &error)) << error;
    std::int64_t step = 0;
    for (int frame = 1; frame <= 120; ++frame) {  // more than one flush block of frames
      Frame f = make_frame(info, frame);
      if (frame % 7 == 0) {  // no log: the frame is a single step
        f.step = ++step;
        want.push_back({f.step, f.time, f.stats});
      } else {
        for (int k = 0; k <= frame % 4; ++k) {
          ++step;
          f.step_log.push_back({step, 1e-3 * static_cast<double>(step),
                                StepStats{1e-3, 1 + static_cast<int>(step % 5), static_cast<int>(step % 2),
                                          1e-9 * static_cast<double>(step), 1e-7 / static_cast<double>(step), true}});
          want.push_back(f.step_log.back());
        }
        f.step = step;
      }
      ASSERT_TRUE(w->append(f, &error)) << error;
    }
    ASSERT_TRUE(w->finish(RunOutcome{}, {}, &error)) << error;
  }
  auto r = ResultReader::open(path, &error);
  ASSERT_TRUE(r) << error;
  const std::vector<StepRecord> got = r->step_log();
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    EXPECT_EQ(got[i].step, want[i].step) << i;
    EXPECT_TRUE(test::bitwise_equal(got[i].time, want[i].time)) << i;
    EXPECT_EQ(got[i].stats.iterations, want[i].stats.iterations) << i;
    EXPECT_EQ(got[i].stats.jacobian_updates, want[i].stats.jacobian_updates) << i;
    EXPECT_TRUE(test::bitwise_equal(got[i].stats.residual_norm, want[i].stats.residual_norm)) << i;
    EXPECT_TRUE(test::bitwise_equal(got[i].stats.increment_norm, want[i].stats.increment_norm)) << i;
    EXPECT_EQ(got[i].stats.converged, want[i].stats.converged) << i;
  }
}

}  // namespace
}  // namespace ff::io
