// Verification of the hub-beam against the hub-beam paper (Xie & Jian 2017) and against analysis.
// Reference: Xie & Jian (2017), J. Vib. Eng. 30(4), section 3.1 text and
// Table 1 (FEM row): hub angle ~20.77 deg (tau0 = 1) and ~147.1 deg (tau0 = 7) after the torque,
// tip vibration ~1.31 Hz, FEM tip transverse displacement -0.0195 m at t = 2 s (tau0 = 1).
// The bundled scenes use the paper's settings (dt = 0.05 s, Newmark beta = 3/4, gamma = 1/2,
// 10 EFG nodes / scale 2.5 / 4 Gauss points, 9 finite elements).
#include <gtest/gtest.h>

#include <cmath>

#include "core/hubbeam/hub_beam_simulation.h"
#include "core/scene/scene.h"

namespace {

struct Result {
  ff::RunOutcome outcome;
  ff::Metrics metrics;
};

Result run(const std::string& scene, const std::vector<std::string>& overrides = {}) {
  ff::scene::LoadedScene s =
      ff::scene::load_scene(std::string(FF_SOURCE_DIR) + "/assets/scenes/" + scene + ".toml", overrides);
  std::atomic<bool> stop{false};
  Result r;
  r.outcome = s.simulation->run([](ff::Frame&&) {}, stop);
  r.metrics = s.simulation->metrics();
  return r;
}

double metric(const Result& r, const std::string& name) {
  for (const auto& [k, v] : r.metrics)
    if (k == name) return v;
  ADD_FAILURE() << "metric " << name << " missing";
  return NAN;
}

// relative error in percent
double err(double value, double reference) { return 100.0 * std::abs(value - reference) / std::abs(reference); }

}  // namespace

class PaperScene : public ::testing::TestWithParam<const char*> {};

// tau0 = 1: all three numbers the paper states, for EFG and FEM
TEST_P(PaperScene, Tau1MatchesThePaper) {
  const Result r = run(std::string("hub_beam_") + GetParam() + "_tau1");
  ASSERT_EQ(r.outcome.status, ff::RunStatus::completed) << r.outcome.reason;
  EXPECT_LT(err(metric(r, "hub_angle_mean_after_T_deg"), 20.77), 1.0);  // measured 0.2 %
  EXPECT_LT(err(metric(r, "tip_frequency_hz"), 1.31), 2.0);            // measured 0.8 %
  EXPECT_LT(err(metric(r, "tip_transverse_at_2s_m"), -0.0195), 2.0);   // measured 0.4 % FEM, 0.7 % EFG
  EXPECT_NEAR(metric(r, "beam_inertia_kg_m2"), 1.46, 0.005);            // J_b ~ 1.46 kg m^2 (text)
}

TEST_P(PaperScene, Tau7MatchesThePaper) {
  const Result r = run(std::string("hub_beam_") + GetParam() + "_tau7");
  ASSERT_EQ(r.outcome.status, ff::RunStatus::completed) << r.outcome.reason;
  EXPECT_LT(err(metric(r, "hub_angle_mean_after_T_deg"), 147.1), 1.0);  // measured 0.3 %
  EXPECT_LT(err(metric(r, "tip_frequency_hz"), 1.31), 2.0);
}

INSTANTIATE_TEST_SUITE_P(EfgAndFem, PaperScene, ::testing::Values("efg", "fem"));

// EFG and FEM agree with each other much more closely than with the paper's rounded numbers
TEST(HubBeamPaper, EfgAgreesWithFem) {
  const Result e = run("hub_beam_efg_tau1"), f = run("hub_beam_fem_tau1");
  EXPECT_LT(err(metric(e, "tip_transverse_at_2s_m"), metric(f, "tip_transverse_at_2s_m")), 1.0);
  EXPECT_LT(err(metric(e, "hub_angle_mean_after_T_deg"), metric(f, "hub_angle_mean_after_T_deg")), 0.05);
}

// Why the paper's 1.31 Hz differs from the 1.38 Hz mode: Newmark's period elongation, eq. (27)
// of core/hubbeam/hub_beam.md, cos(w_num h) = 1 - (w h)^2 / (2 (1 + beta (w h)^2)).
TEST(HubBeamPaper, PaperFrequencyIsNewmarkPeriodElongationOfTheMode) {
  for (double beta : {0.75, 0.25}) {
    const Result r = run("hub_beam_fem_tau1", {"solver.newmark_beta=" + std::to_string(beta)});
    const double w = 2 * M_PI * metric(r, "modal_frequency_hz"), h = 0.05, wh2 = w * w * h * h;
    const double predicted = std::acos(1.0 - wh2 / (2.0 * (1.0 + beta * wh2))) / h / (2 * M_PI);
    EXPECT_LT(err(metric(r, "tip_frequency_hz"), predicted), 0.6) << "beta " << beta;  // measured 0.3 %
  }
}

// The converged scene agrees with the linear modal analysis the code performs (eq. 28): at
// tau0 = 1 the response after the torque is small and the nonlinear terms negligible.
TEST(HubBeamConverged, FrequencyMatchesModalAnalysis) {
  const Result r = run("hub_beam_converged_tau1");
  ASSERT_EQ(r.outcome.status, ff::RunStatus::completed);
  EXPECT_LT(err(metric(r, "tip_frequency_hz"), metric(r, "modal_frequency_hz")), 0.1);  // measured 0.002 %
  // average acceleration, dt = 2 ms: energy and angular momentum are conserved after the torque (eq. 14)
  EXPECT_LT(metric(r, "energy_drift_rel"), 1e-5);               // measured 6.5e-7
  EXPECT_LT(metric(r, "angular_momentum_drift_rel"), 1e-7);     // measured 4.6e-9
}

// Converged means converged: halving dt and refining the mesh by 1.5 changes the metrics by < 0.1 %
TEST(HubBeamConverged, MetricsStopChangingUnderRefinement) {
  const Result a = run("hub_beam_converged_tau1", {"solver.end=4"});
  const Result b = run("hub_beam_converged_tau1", {"solver.end=4", "solver.dt=0.001", "fem.elements=36"});
  for (const char* m : {"tip_transverse_at_2s_m", "hub_angle_mean_after_T_deg", "tip_frequency_hz"})
    EXPECT_LT(err(metric(a, m), metric(b, m)), 0.1) << m;
}

// Angular momentum after the torque ends is conserved by the equations (eq. 14). Newmark conserves
// it only up to its O(h^2) truncation error for this nonlinear system, so the test checks the
// size at the paper's step and the second-order decay under step halving.
TEST(HubBeamConservation, AngularMomentumAfterTorque) {
  for (const char* scene : {"hub_beam_efg_tau7", "hub_beam_fem_tau1"}) {
    const Result paper = run(scene);
    EXPECT_LT(metric(paper, "angular_momentum_drift_rel"), 5e-3) << scene;  // measured 1.2e-3 (tau7)
    const Result coarse = run(scene, {"solver.newmark_beta=0.25", "solver.dt=0.02"});
    const Result fine = run(scene, {"solver.newmark_beta=0.25", "solver.dt=0.01"});
    const double dc = metric(coarse, "angular_momentum_drift_rel"), df = metric(fine, "angular_momentum_drift_rel");
    EXPECT_LT(df, 1e-5) << scene;                                     // measured 2.8e-6 (tau7)
    EXPECT_GT(dc / df, 3.0) << scene << ": drift should fall ~4x when dt halves";
    EXPECT_LT(metric(fine, "energy_drift_rel"), 1e-3) << scene;
  }
}

// The paper: "the zero-order model diverges at tau0 = 10 while the first-order model stays stable".
TEST(HubBeamStability, ZeroOrderTau10DivergesAtItsCriticalSpeed) {
  const Result r = run("hub_beam_zero_order_tau10");
  EXPECT_EQ(r.outcome.status, ff::RunStatus::diverged);
  EXPECT_NE(r.outcome.reason.find("critical speed"), std::string::npos) << r.outcome.reason;
  EXPECT_GT(r.outcome.stop_time, 1.6);
  EXPECT_LT(r.outcome.stop_time, 1.9);
  for (const auto& [k, v] : r.metrics) { EXPECT_TRUE(std::isfinite(v)) << k; }
}

TEST(HubBeamStability, FirstOrderTau10StaysBounded) {
  const Result r = run("hub_beam_first_order_tau10");
  EXPECT_EQ(r.outcome.status, ff::RunStatus::completed) << r.outcome.reason;
  EXPECT_LT(metric(r, "tip_transverse_max_m"), 0.8 * 1.8);
  // and it is not just luck of the step: also bounded at dt = 0.01
  const Result fine = run("hub_beam_first_order_tau10", {"solver.dt=0.01"});
  EXPECT_EQ(fine.outcome.status, ff::RunStatus::completed) << fine.outcome.reason;
}

// The first-order model has no critical speed (D1 outweighs M2); the zero-order one has the
// lowest clamped bending frequency, 1.875^2 sqrt(EI / (rho A L^4)) (Euler-Bernoulli cantilever).
TEST(HubBeamStability, CriticalSpeeds) {
  using namespace ff::hubbeam;
  HubBeamParams p;
  HubBeamEffects zero, first;
  zero.first_order_coupling = false;
  const HubBeamSystem z(p, zero, make_fem_basis(p.length, FemOptions{}));
  const HubBeamSystem f(p, first, make_fem_basis(p.length, FemOptions{}));
  const double beta1 = 1.8751040687, ei = p.youngs_modulus * p.second_moment, rho_a = p.density * p.area;
  const double w1 = beta1 * beta1 * std::sqrt(ei / (rho_a * std::pow(p.length, 4)));
  EXPECT_LT(err(z.critical_speed(), w1), 0.01);
  EXPECT_TRUE(std::isinf(f.critical_speed()));
}
