// Stability of the hard static and hub-beam cases (issue 6), each with explicit pass criteria:
//  - the thin hemisphere, R/h = 1000 (the shell paper, Zhang, Liu, Zhang & Liu 2022, example 2, h = 0.01, F to 5): reaches the full load,
//    every step converged within 15 Newton iterations, a smooth path (no increment jumps) and every
//    published value finite;
//  - the hinged roof h = 6.35 (Sze et al. 2004 §3.8d) through its snap-back: the arc length follows
//    the load down below zero and back up (no jump across the branch), to the final load;
//  - the first-order hub-beam (the hub-beam paper, Xie & Jian 2017) at tau0 = 10, 12 and 15: bounded below one beam length at
//    dt = 0.05 and 0.005, the two steps agreeing on the largest deflection within 10 %;
//  - beyond: at tau0 = 20 the deflection leaves the model's small-deformation range; the run is
//    reported as diverged, with the reason, at the same time for both steps (so it is the model, not
//    the integrator), and every frame published before is finite;
//  - the known-unstable zero-order hub-beam at tau0 = 10: reported as diverged at its critical speed,
//    never as NaN in what was published.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "core/model/simulation.h"
#include "core/scene/scene.h"

using namespace ff;

namespace {

struct Recorded {
  RunOutcome outcome;
  Metrics metrics;
  RunInfo info;
  std::vector<Frame> frames;
};

Recorded run(const std::string& scene, std::vector<std::string> overrides = {}) {
  scene::LoadedScene s = scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/" + scene + ".toml", overrides);
  Recorded r;
  r.info = s.simulation->info();
  std::atomic<bool> stop{false};
  r.outcome = s.simulation->run([&](Frame&& f) { r.frames.push_back(std::move(f)); }, stop);
  r.metrics = s.simulation->metrics();
  return r;
}

double metric(const Recorded& r, const std::string& name) {
  const std::optional<double> v = find_metric(r.metrics, name);
  if (!v) ADD_FAILURE() << "no metric " << name;
  return v.value_or(std::nan(""));
}

std::size_t probe_index(const Recorded& r, const std::string& name) {
  for (std::size_t i = 0; i < r.info.probes.size(); ++i)
    if (r.info.probes[i].name == name) return i;
  ADD_FAILURE() << "no probe " << name;
  return 0;
}

/// Every number of every published frame and every metric is finite.
void expect_all_finite(const Recorded& r, const std::string& what) {
  for (const Frame& f : r.frames) {
    bool ok = std::isfinite(f.time) && std::isfinite(f.load_factor);
    for (double v : f.points) ok = ok && std::isfinite(v);
    for (double v : f.probes) ok = ok && std::isfinite(v);
    for (const auto& field : f.fields)
      for (double v : field) ok = ok && std::isfinite(v);
    ASSERT_TRUE(ok) << what << ": non-finite value in the frame of step " << f.step;
  }
  for (const auto& [k, v] : r.metrics) { EXPECT_TRUE(std::isfinite(v)) << what << ": metric " << k; }
}

TEST(StabilityStatics, ThinHemisphereRh1000ReachesTheFullLoadSmoothly) {
  const Recorded r = run("hemisphere_18deg_h001", {"output.frames=false"});
  ASSERT_EQ(r.outcome.status, RunStatus::completed) << r.outcome.reason;
  expect_all_finite(r, "hemisphere h = 0.01");
  ASSERT_GE(r.frames.size(), 3u);
  EXPECT_NEAR(r.frames.back().load_factor, 1.0, 1e-12);
  const std::size_t out = probe_index(r, "disp_outward"), in = probe_index(r, "disp_inward");
  double largest_increment = 0.0, total = 0.0;
  for (std::size_t k = 1; k < r.frames.size(); ++k) {
    const Frame& f = r.frames[k];
    EXPECT_TRUE(f.stats.converged) << "step " << f.step;
    EXPECT_LE(f.stats.iterations, 15) << "step " << f.step;
    const double d = std::hypot(f.probes[out] - r.frames[k - 1].probes[out], f.probes[in] - r.frames[k - 1].probes[in]);
    largest_increment = std::max(largest_increment, d);
    total += d;
  }
  // 20 load steps over a path of this length: no single step may carry a third of it (a jump)
  EXPECT_LT(largest_increment, total / 3.0);
  // both loaded points move the way they are pushed, the inward one more (as at h = 0.04)
  EXPECT_GT(r.frames.back().probes[out], 0.0);
  EXPECT_GT(r.frames.back().probes[in], r.frames.back().probes[out]);
}

TEST(StabilityStatics, HingedRoofH635FollowsItsSnapBack) {
  const Recorded r = run("hinged_roof_h635", {"output.frames=false"});
  ASSERT_EQ(r.outcome.status, RunStatus::completed) << r.outcome.reason;
  expect_all_finite(r, "hinged roof h = 6.35");
  // the load factor falls below zero after the limit point and rises again: an arc length that
  // jumped across the branch would skip the negative loads (ranges over the unstable part of the
  // path, from the start until the load is positive again)
  const std::size_t w = probe_index(r, "minus_w_centre");
  double lambda_limit = -INFINITY, lambda_min_after = INFINITY, w_lo = INFINITY, w_hi = -INFINITY;
  int negative_frames = 0;
  std::size_t end = r.frames.size();
  for (std::size_t k = 1; k < r.frames.size(); ++k) {
    const double l = r.frames[k].load_factor;
    EXPECT_TRUE(r.frames[k].stats.converged) << "step " << r.frames[k].step;
    if (end < r.frames.size()) continue;
    if (lambda_min_after < 0.0 && l > 0.0) end = k;  // back above zero after the snap-back
    if (l < r.frames[k - 1].load_factor && lambda_limit == -INFINITY) lambda_limit = r.frames[k - 1].load_factor;
    if (lambda_limit > -INFINITY) lambda_min_after = std::min(lambda_min_after, l);
    if (l < 0.0) ++negative_frames;
    w_lo = std::min(w_lo, r.frames[k].probes[w]);
    w_hi = std::max(w_hi, r.frames[k].probes[w]);
  }
  ASSERT_LT(end, r.frames.size()) << "the load never came back above zero";
  EXPECT_LT(lambda_min_after, 0.0);
  EXPECT_GE(negative_frames, 3);
  // one continuous path: every computed (w, lambda) lies on the same model's path traced with short
  // steps (target turn 1.5 deg), within 1 % of the ranges; a step that jumped across the branch
  // would land off it. Both limit points are reported as events.
  const Recorded fine = run("hinged_roof_h635", {"output.frames=false", "solver.target_turn=1.5", "solver.max_growth=1.25"});
  ASSERT_EQ(fine.outcome.status, RunStatus::completed) << fine.outcome.reason;
  ASSERT_GT(fine.frames.size(), 2 * r.frames.size());
  double farthest = 0.0;
  std::string path;
  for (std::size_t k = 1; k < end; ++k) {
    const double w_k = r.frames[k].probes[w], l_k = r.frames[k].load_factor;
    double nearest = INFINITY;
    for (std::size_t j = 1; j < fine.frames.size(); ++j) {
      // distance to the segment (j-1, j) of the fine path in the scaled (w, lambda) plane
      const double ax = fine.frames[j - 1].probes[w] / (w_hi - w_lo), ay = fine.frames[j - 1].load_factor / (lambda_limit - lambda_min_after);
      const double bx = fine.frames[j].probes[w] / (w_hi - w_lo), by = fine.frames[j].load_factor / (lambda_limit - lambda_min_after);
      const double px = w_k / (w_hi - w_lo), py = l_k / (lambda_limit - lambda_min_after);
      const double dx = bx - ax, dy = by - ay, len2 = dx * dx + dy * dy;
      const double t = len2 > 0 ? std::clamp(((px - ax) * dx + (py - ay) * dy) / len2, 0.0, 1.0) : 0.0;
      nearest = std::min(nearest, std::hypot(px - ax - t * dx, py - ay - t * dy));
    }
    farthest = std::max(farthest, nearest);
    path += " (" + std::to_string(w_k) + ", " + std::to_string(l_k) + ")";
  }
  EXPECT_LT(farthest, 0.01) << "path (w, lambda):" << path;
  int limit_points = 0;
  for (const PathEvent& e : r.outcome.events) limit_points += e.kind == "limit_point";
  EXPECT_EQ(limit_points, 2);
  EXPECT_LT(metric(r, "min_load_after_limit"), 0.0);
}

class FirstOrderHubBeam : public ::testing::TestWithParam<double> {};

TEST_P(FirstOrderHubBeam, StaysBoundedAtBothSteps) {
  const std::string tau = "torque.amplitude=" + std::to_string(GetParam());
  const Recorded coarse = run("hub_beam_first_order_tau10", {tau, "solver.dt=0.05"});
  const Recorded fine = run("hub_beam_first_order_tau10", {tau, "solver.dt=0.005"});
  for (const Recorded* r : {&coarse, &fine}) {
    ASSERT_EQ(r->outcome.status, RunStatus::completed) << r->outcome.reason;
    expect_all_finite(*r, tau);
    EXPECT_LT(metric(*r, "tip_transverse_max_m"), 1.8) << tau;  // below one beam length
  }
  const double a = metric(coarse, "tip_transverse_max_m"), b = metric(fine, "tip_transverse_max_m");
  EXPECT_LT(std::abs(a - b), 0.1 * b) << tau << ": dt 0.05 gives " << a << ", dt 0.005 gives " << b;
}

INSTANTIATE_TEST_SUITE_P(Tau0, FirstOrderHubBeam, ::testing::Values(10.0, 12.0, 15.0),
                         [](const auto& info) { return "tau" + std::to_string(static_cast<int>(info.param)); });

TEST(StabilityHubBeam, FirstOrderBeyondItsRangeIsReportedNotNaN) {
  const Recorded coarse = run("hub_beam_first_order_tau10", {"torque.amplitude=20", "solver.dt=0.05"});
  const Recorded fine = run("hub_beam_first_order_tau10", {"torque.amplitude=20", "solver.dt=0.005"});
  for (const Recorded* r : {&coarse, &fine}) {
    ASSERT_EQ(r->outcome.status, RunStatus::diverged);
    EXPECT_NE(r->outcome.reason.find("small-deformation model no longer valid"), std::string::npos)
        << r->outcome.reason;
    expect_all_finite(*r, "tau0 = 20");
  }
  // the same physical moment at both steps: the model's range ends, not the integrator's stability
  EXPECT_NEAR(coarse.outcome.stop_time, fine.outcome.stop_time, 0.1);
}

TEST(StabilityHubBeam, ZeroOrderTau10IsReportedAsDivergedNeverAsNaN) {
  const Recorded r = run("hub_beam_zero_order_tau10");
  ASSERT_EQ(r.outcome.status, RunStatus::diverged);
  EXPECT_NE(r.outcome.reason.find("critical speed"), std::string::npos) << r.outcome.reason;
  EXPECT_GT(r.frames.size(), 10u);  // it got somewhere before stopping
  expect_all_finite(r, "zero-order tau0 = 10");
  EXPECT_NEAR(r.frames.back().time, r.outcome.stop_time, 1e-12);  // the last frame is the last converged step
}

}  // namespace
