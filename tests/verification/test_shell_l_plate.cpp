// Right-angle cantilever plate (the shell paper, Zhang, Liu, Zhang & Liu 2022, §5.5; Argyris' right-angle frame as a flat L-shaped plate:
// centre-line legs 240, width 30, h = 0.6, E = 71240, nu = 0.31). Runs the bundled scenes
// assets/scenes/l_plate_force.toml and l_plate_moment.toml with overrides. Sources and choices are
// in the scene files. References:
// - beam theory for the linear out-of-plane compliance of the tip (bending of both arms, torsion of
//   the clamped arm): 2L^3/(3EI) + L^3/(GJ) = 474.9 with the corner a point on the centre lines,
//   439.2 with a rigid 30 x 30 corner square; the plate must lie between (measured 446.3);
// - the lateral-buckling load 1.088 of the frame as a beam (EXUDYN test model "right angle frame
//   under end load", after Nachbagauer & Gerstmayr 2013 and Simo's example). The plate's corner
//   square shortens the flexible legs to 225, which would raise a beam's load by up to
//   (240/225)^2 = 1.138; measured bifurcation of the plate 1.196 (16x2) and 1.188 (32x4).
#include <gtest/gtest.h>

#include <cmath>

#include "core/scene/scene.h"

namespace {
struct PathRun {
  ff::RunOutcome outcome;
  ff::Metrics metrics;
};
PathRun run(const std::string& scene, const std::vector<std::string>& overrides) {
  ff::scene::LoadedScene s =
      ff::scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/" + scene + ".toml", overrides);
  std::atomic<bool> stop{false};
  PathRun r;
  r.outcome = s.simulation->run([](ff::Frame&&) {}, stop);
  r.metrics = s.simulation->metrics();
  return r;
}
double get(const ff::Metrics& m, const std::string& k) {
  for (const auto& [n, v] : m)
    if (n == k) return v;
  ADD_FAILURE() << "metric " << k << " missing";
  return NAN;
}
}  // namespace

// perturbation force alone, small: the linear compliance of the tip along z lies between the two beam
// idealizations of the corner (a wrong leg length, e.g. 240 to the outer corner, falls outside)
TEST(ShellLPlate, OutOfPlaneComplianceLiesBetweenBeamBounds) {
  for (const char* scene : {"l_plate_force", "l_plate_moment"}) {
    const PathRun r = run(scene, {"load[0].total=[0,0,0]", "load[1].total=[0,0,1]", "solver.end=0.002",
                              "solver.initial_step=0.002"});
    ASSERT_EQ(r.outcome.status, ff::RunStatus::completed) << r.outcome.reason;
    const double compliance = get(r.metrics, "tip_z_full") / 0.002;
    EXPECT_GT(compliance, 439.2) << scene;
    EXPECT_LT(compliance, 474.9) << scene;
  }
}

// perfect plate (no perturbation): load control stops where det K changes sign, the bifurcation
TEST(ShellLPlate, PerfectPlateBucklesLaterallyNearTheFrameLoad) {
  const PathRun r = run("l_plate_force", {"load[1].total=[0,0,0]", "solver.min_step=1e-4"});
  EXPECT_EQ(r.outcome.status, ff::RunStatus::diverged) << "expected to stop at the bifurcation";
  const double p_cr = r.outcome.stop_time;  // load_scale 1: lambda = P
  EXPECT_GT(p_cr, 1.088);
  EXPECT_LT(p_cr, 1.088 * 1.138 * 1.01);
  // the bundled, perturbed path goes through it: small lateral motion before, large after
  const PathRun path = run("l_plate_force", {});
  ASSERT_EQ(path.outcome.status, ff::RunStatus::completed) << path.outcome.reason;
  EXPECT_LT(std::abs(get(path.metrics, "tip_z_at_P1")), 0.01 * 240);
  EXPECT_GT(std::abs(get(path.metrics, "tip_z_full")), 0.15 * 240);
  EXPECT_GT(get(path.metrics, "tip_x_full"), 0.0);
}

// the perturbation's sign picks the side: Z flips, X does not
TEST(ShellLPlate, MomentPathIsSymmetricInThePerturbationSign) {
  const PathRun up = run("l_plate_moment", {});
  const PathRun down = run("l_plate_moment", {"load[1].total=[0,0,-0.001]"});
  ASSERT_EQ(up.outcome.status, ff::RunStatus::completed) << up.outcome.reason;
  ASSERT_EQ(down.outcome.status, ff::RunStatus::completed) << down.outcome.reason;
  const double x = get(up.metrics, "tip_x_full"), z = get(up.metrics, "tip_z_full");
  EXPECT_NEAR(get(down.metrics, "tip_x_full"), x, 1e-6 * std::abs(x));
  EXPECT_NEAR(get(down.metrics, "tip_z_full"), -z, 1e-6 * std::abs(z));
  EXPECT_GT(std::abs(z), 0.1);
}
