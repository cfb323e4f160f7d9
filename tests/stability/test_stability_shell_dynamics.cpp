// Stability of hard dynamic cases (issue 6, first part), each with explicit pass criteria:
//  - the double pendulum at E = 100 GPa with the shell paper's largest step (dt = 1e-3) and the frozen
//    iteration matrix: completes 0.3 s, the joints hold to the Newton tolerance, energy never grows;
//  - a shell spinning fast (20 rad/s, ~10 turns at rho_inf = 0.8): finite state, energy never grows,
//    linear momentum kept;
//  - a nearly degenerate element (one corner angle of 3 degrees): finite force, and a tangent that
//    still matches central differences.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include "core/mesh/generators.h"
#include "core/scene/scene.h"
#include "core/shell/cb_shell.h"
#include "core/shell/multibody_model.h"
#include "core/shell/shell_dynamic_simulation.h"
#include "core/solve/generalized_alpha.h"
#include "tests/support/shell_fixtures.h"

using namespace ff;
using namespace ff::shell;

namespace {

double metric(const Metrics& m, const std::string& name) {
  const std::optional<double> v = find_metric(m, name);
  if (!v) ADD_FAILURE() << "no metric " << name;
  return v.value_or(std::nan(""));
}

TEST(Stability, StiffDoublePendulumWithFrozenMatrixAtTheLargestStep) {
  scene::LoadedScene s = scene::load_scene(
      std::string(FF_SOURCE_DIR) + "/assets/scenes/double_pendulum_shells_e100gpa.toml",
      {"solver.end=0.3", "output.frames=false", "output.plots=false"});
  std::atomic<bool> stop{false};
  const RunOutcome r = s.simulation->run([](Frame&&) {}, stop);
  ASSERT_EQ(r.status, RunStatus::completed) << r.reason;
  const Metrics m = s.simulation->metrics();
  EXPECT_LT(metric(m, "constraint_violation_max"), 1e-6);
  EXPECT_LT(metric(m, "energy_growth_max_rel"), 1e-5);
  EXPECT_LT(metric(m, "pointF_z_min"), -0.3);  // it did swing (0.3 s of near free fall: ~0.44 m)
  // one initial matrix; every other update belongs to a step redone after the stale matrix failed
  EXPECT_LE(metric(m, "NOU") - 1, metric(m, "fallback_steps") * 30);
  EXPECT_LE(metric(m, "fallback_steps"), 5);
}

// energy_growth_max_rel measures the rise of the total energy against the largest kinetic + strain
// energy of the run, so where the gravity potential is zero does not change it: a plate hinged along
// an edge and released horizontal at z = 0 (total energy 0 J at the start) and the same plate at
// z = 10 m give the same figure. Lazy matrices stopped at ||dx|| < 1e-6 leave a small rise here
// (measured ~3e-5 over 0.5 s; none at 1e-8), so the figure is not zero and the comparison can fail.
TEST(Stability, EnergyGrowthDoesNotDependOnTheGravityDatum) {
  auto growth = [](double z) {
    const std::string text =
        "[scene]\nname = \"datum\"\nmodel = \"shell\"\nanalysis = \"dynamic\"\n"
        "effects = [\"elastic\", \"inertia\", \"gravity\", \"hr\", \"ans\", \"joints\"]\n"
        "[solver]\ndt = 1e-3\nend = 0.3\npolicy = \"lazy\"\npredictor = \"previous\"\ntolerance = 1e-6\n"
        "[[material]]\nyoungs_modulus = 70e9\npoisson_ratio = 0.33\nthickness = 0.002\ndensity = 2700.0\n"
        "[[part]]\nname = \"plate\"\ngenerator = \"rectangular_plate\"\nn1 = 12\nn2 = 4\nlength = 0.6\n"
        "width = 0.2\norigin = [0.0, 0.0, " + std::to_string(z) + "]\n"
        "[[joint]]\ntype = \"revolute\"\naxis = [0.0, 1.0, 0.0]\nselect = \"patch_edge\"\n"
        "patch = \"plate\"\nedge = \"u=0\"\n"
        "[output]\nframes = false\nplots = false\n";
    const std::string dir = std::string(FF_BINARY_DIR) + "/test_out";
    std::filesystem::create_directories(dir);
    const std::string path = dir + "/datum_" + std::to_string(static_cast<int>(z)) + ".toml";
    std::ofstream(path) << text;
    scene::LoadedScene s = scene::load_scene(path, {});
    std::atomic<bool> stop{false};
    const RunOutcome r = s.simulation->run([](Frame&&) {}, stop);
    EXPECT_EQ(r.status, RunStatus::completed) << r.reason;
    return metric(s.simulation->metrics(), "energy_growth_max_rel");
  };
  const double at_zero = growth(0.0), raised = growth(10.0);
  EXPECT_GT(at_zero, 1e-7);  // a rise of the Newton tolerance's size, not zero
  EXPECT_LT(at_zero, 1e-3);  // and small against the energy that moves (no blow-up at E(0) = 0)
  EXPECT_NEAR(raised, at_zero, 0.05 * at_zero);
}

TEST(Stability, FastSpinningShellKeepsEnergyBoundedOverManyTurns) {
  MultibodySpec spec;
  ShellBodySpec b;
  b.name = "disk";
  b.mesh = mesh::rectangular_plate(0.6, 0.6, 4, 4, "disk");
  b.section = isotropic_section(5.0e6, 0.3, 0.01);
  b.density = 1000;
  spec.shells = {b};
  MultibodyModel m(spec);
  // spin at 20 rad/s about the plate normal through its centre, plus a small wobble
  const Vec3 c(0.3, 0.3, 0.0), Omega(0.5, -0.3, 20.0);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(m.size());
  for (int I = 0; I < m.node_count(); ++I) {
    const NodePose& H = m.poses()[I];
    const Vec3 xd = Omega.cross(H.p - c), w = H.R.transpose() * Omega;
    for (int k = 0; k < 3; ++k) v[m.equation(I, k)] = (H.R.transpose() * xd)[k];
    for (int k = 0; k < 2; ++k) v[m.equation(I, 3 + k)] = w[k];
  }
  GeneralizedAlphaSettings st;
  st.rho_inf = 0.8;
  st.tolerance = 1e-8;
  GeneralizedAlpha ga(m, st);
  ASSERT_EQ(ga.initialize(0.0, v), "");
  const MotionSummary e0 = m.summary(v);
  const double T = 10 * 2 * std::numbers::pi / 20.0, h = 2e-3;
  double worst_growth = 0;
  while (ga.time() < T) {
    const StepReport r = ga.step(h);
    ASSERT_TRUE(r.converged) << r.failure;
    const MotionSummary e = m.summary(ga.velocity());
    ASSERT_TRUE(std::isfinite(e.total()));
    worst_growth = std::max(worst_growth, (e.total() - e0.total()) / e0.total());
    EXPECT_LT((e.linear_momentum - e0.linear_momentum).norm(), 1e-3 * e0.kinetic / 20.0);
  }
  EXPECT_LT(worst_growth, 1e-6);
}

TEST(Stability, NearlyDegenerateElementStaysConsistent) {
  using namespace ff::shell::testing;
  // a convex sliver: the edges at corner 0 enclose 3 degrees
  ElementPoses ref;
  const double a = 3.0 * std::numbers::pi / 180.0;
  const Vec3 X[4] = {{0, 0, 0}, {1, 0, 0}, {2, 0.1, 0}, {std::cos(a), std::sin(a), 0}};
  for (int i = 0; i < 4; ++i) ref[i] = {frame(Vec3::UnitZ()), X[i]};
  // a non-convex (inverted) quad is refused with a reason, never evaluated into NaNs
  ElementPoses bad = ref;
  bad[2].p = Vec3(0.5, 0.02, 0);
  EXPECT_THROW(CbShellElement(bad, isotropic_section(2.0e5, 0.3, 0.01), ShellOptions{}), std::exception);
  for (bool drilling : {false, true}) {
    ShellOptions o;
    o.drilling = drilling;
    o.drilling_factor = 0.1;
    CbShellElement el(ref, isotropic_section(2.0e5, 0.3, 0.01), o);
    const ElementPoses cur = deformed(ref, 7, 0.02);
    Vec24 f;
    Mat24 K;
    el.evaluate(cur, f, &K);
    ASSERT_TRUE(f.allFinite() && K.allFinite());
    Mat24 fd;
    for (int k = 0; k < 24; ++k) {
      Vec24 fp, fm;
      el.evaluate(perturb(cur, k, 1e-7), fp, nullptr);
      el.evaluate(perturb(cur, k, -1e-7), fm, nullptr);
      fd.col(k) = (fp - fm) / 2e-7;
    }
    if (!drilling)  // without drilling the θ3 columns are zero in both
      for (int I = 0; I < 4; ++I) fd.col(6 * I + 5).setZero(), K.col(6 * I + 5).setZero();
    EXPECT_LT((K - fd).norm(), 1e-5 * K.norm()) << (drilling ? "6 DoF" : "5 DoF");
  }
}

}  // namespace
