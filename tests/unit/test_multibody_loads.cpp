// External loads of the multibody model (core/shell/cb_shell_dynamics.md §8): the load term's
// part of the iteration matrix is the exact derivative of its residual with respect to the step
// (D18 times T_SE3, G9) for dead forces and moments on 5- and 6-DoF nodes, dead pressures and a
// rigid body; follower loads have constant local components (D19), which a superposed rigid
// rotation of the whole model leaves unchanged; the time history scales every load (D16); specs
// that cannot be simulated are refused with the load's index.
#include <gtest/gtest.h>

#include <limits>
#include <random>

#include "core/lie/se3.h"
#include "core/mesh/generators.h"
#include "core/shell/multibody_model.h"
#include "core/shell/shell_dynamic_simulation.h"

using namespace ff;
using namespace ff::shell;

namespace {

constexpr int kPlateNodes = 12, kPanelNodes = 12, kRigid = kPlateNodes + kPanelNodes;

// a 5-DoF plate, a 6-DoF panel (drilling) and a rigid body, no joints: the load term alone couples
// nothing, so any error in it shows in its own rows
MultibodySpec bodies(bool drilling_plate = false) {
  MultibodySpec s;
  ShellBodySpec plate;
  plate.name = "plate";
  plate.mesh = mesh::rectangular_plate(1.0, 0.6, 3, 2, "plate");
  plate.section = isotropic_section(2.0e7, 0.3, 0.02);
  plate.density = 1000;
  plate.options.drilling = drilling_plate;
  plate.options.drilling_factor = 0.1;
  ShellBodySpec panel = plate;
  panel.name = "panel";
  mesh::CylinderPatch cyl;
  cyl.radius = 0.5;
  cyl.phi0 = -0.6;
  cyl.phi1 = 0.6;
  cyl.s0 = 0;
  cyl.s1 = 0.6;
  cyl.origin = Vec3(1.5, 0, 0);
  panel.mesh = mesh::cylindrical_patch(cyl, 3, 2, "panel");
  panel.options.drilling = true;
  panel.options.drilling_factor = 0.1;
  s.shells = {plate, panel};
  RigidBodySpec rb;
  rb.name = "block";
  rb.pose.p = Vec3(0.5, 1.0, 0.2);
  rb.mass = 3.0;
  rb.inertia << 0.4, 0.05, 0.0, 0.05, 0.3, 0.02, 0.0, 0.02, 0.2;
  s.rigid = {rb};
  return s;
}

Eigen::VectorXd random_vector(int n, unsigned seed, double scale) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x[i] = scale * u(g);
  return x;
}

// on from t = 1 with a ramp to t = 2: at t = 0 every load is off, at t = 1.5 at half its value
const LoadHistory kRamp{1.0, 10.0, 1.0};
constexpr double kOff = 0.0, kOn = 1.5;

TimedNodalLoad nodal(int node, const Vec3& force, const Vec3& moment, bool follower) {
  return {NodalLoad{node, force, moment, follower}, kRamp};
}

// The load term of the residual, r(t on) − r(t off), and its iteration matrix S (stiffness weight
// only) at the configured step; both evaluations share everything else bit for bit.
struct LoadPart {
  Eigen::VectorXd r;
  Eigen::MatrixXd S;
};
LoadPart load_part(MultibodyModel& m, const Eigen::VectorXd& v, bool with_matrix) {
  const int n = m.size();
  const Eigen::VectorXd vd = Eigen::VectorXd::Zero(n), lam = Eigen::VectorXd::Zero(m.constraint_count());
  const IterationWeights stiffness{0, 0, 1};
  Eigen::VectorXd r_on, r_off, phi;
  SparseMatrixD S_on, S_off, B;
  m.evaluate(kOn, v, vd, lam, r_on, phi, with_matrix ? &stiffness : nullptr, with_matrix ? &S_on : nullptr,
             with_matrix ? &B : nullptr);
  m.evaluate(kOff, v, vd, lam, r_off, phi, with_matrix ? &stiffness : nullptr, with_matrix ? &S_off : nullptr,
             with_matrix ? &B : nullptr);
  LoadPart out{r_on - r_off, Eigen::MatrixXd()};
  if (with_matrix) out.S = Eigen::MatrixXd(S_on) - Eigen::MatrixXd(S_off);
  return out;
}

// Central differences of the load residual with respect to the step around x0 against the load
// part of S at x0 (exact matrix: position terms times T_SE3(x0), G9). Returns |S − fd| / |fd|.
double matrix_error(MultibodySpec spec, double* fd_norm) {
  // r(t on) − r(t off) cancels the other terms up to their round-off, which the differencing
  // divides by 2 ε: a soft shell keeps it far below the load's
  for (ShellBodySpec& b : spec.shells) b.section.youngs_modulus = 1.0;
  MultibodyModel m(std::move(spec));
  const int n = m.size();
  m.configure(random_vector(n, 1, 0.05));
  m.commit();
  Eigen::VectorXd x0 = random_vector(n, 9, 0.3);  // turns of 0.3-0.5 rad: T_SE3 far from 1
  const Eigen::VectorXd v = random_vector(n, 2, 1.0);
  m.configure(x0);
  const LoadPart at = load_part(m, v, true);
  Eigen::MatrixXd fd(n, n);
  const double eps = 1e-6;
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    e[k] = eps;
    m.configure(x0 + e);
    const Eigen::VectorXd rp = load_part(m, v, false).r;
    m.configure(x0 - e);
    const Eigen::VectorXd rm = load_part(m, v, false).r;
    fd.col(k) = (rp - rm) / (2 * eps);
  }
  m.rollback();
  *fd_norm = fd.norm();
  return (at.S - fd).norm() / std::max(fd.norm(), 1e-300);
}

TEST(MultibodyLoads, HistoryStepsRampsAndEnds) {
  const LoadHistory step;  // suddenly applied at t = 0 and held
  EXPECT_EQ(step.factor(-1e-9), 0.0);
  EXPECT_EQ(step.factor(0.0), 1.0);
  EXPECT_EQ(step.factor(1e9), 1.0);
  const LoadHistory pulse{0.5, 0.75, 0.0};
  EXPECT_EQ(pulse.factor(0.49), 0.0);
  EXPECT_EQ(pulse.factor(0.5), 1.0);
  EXPECT_EQ(pulse.factor(0.7), 1.0);
  EXPECT_EQ(pulse.factor(0.75), 0.0);
  EXPECT_DOUBLE_EQ(kRamp.factor(1.25), 0.25);
  EXPECT_EQ(kRamp.factor(2.0), 1.0);
  EXPECT_STREQ(step.defect(), "");
  EXPECT_STRNE(LoadHistory({1.0, 1.0, 0.0}).defect(), "");
  EXPECT_STRNE(LoadHistory({0.0, 1.0, -0.1}).defect(), "");
}

// (D17): a dead world force at a node is −Rᵀ f(t) F in its translation rows, f(t) from (D16);
// at the reference pose R = R0
TEST(MultibodyLoads, DeadForceResidualIsTheScaledWorldForceInTheNodeFrame) {
  MultibodySpec s = bodies();
  const Vec3 F(3.0, -2.0, 5.0);
  s.loads.push_back(nodal(kPlateNodes + 4, F, Vec3::Zero(), false));
  MultibodyModel m(s);
  const LoadPart p = load_part(m, Eigen::VectorXd::Zero(m.size()), false);
  const Vec3 expected = -0.5 * (m.reference_pose(kPlateNodes + 4).R.transpose() * F);
  for (int j = 0; j < 3; ++j) { EXPECT_NEAR(p.r[m.equation(kPlateNodes + 4, j)], expected[j], 1e-12); }
  EXPECT_NEAR(p.r.norm(), expected.norm(), 1e-12);  // nothing else
}

TEST(MultibodyLoads, DeadForceMatrixIsExact) {
  MultibodySpec s = bodies();
  s.loads.push_back(nodal(5, Vec3(300, -200, 500), Vec3::Zero(), false));                // 5-DoF shell node
  s.loads.push_back(nodal(kPlateNodes + 6, Vec3(-100, 400, 250), Vec3::Zero(), false));  // 6-DoF shell node
  s.loads.push_back(nodal(kRigid, Vec3(50, 60, -70), Vec3::Zero(), false));              // rigid body
  double fd_norm = 0;
  EXPECT_LT(matrix_error(s, &fd_norm), 1e-7);
  EXPECT_GT(fd_norm, 100.0);
}

TEST(MultibodyLoads, DeadMomentMatrixIsExactOnFiveAndSixDofNodes) {
  for (const int node : {5, kPlateNodes + 6, kRigid}) {
    MultibodySpec s = bodies();
    s.loads.push_back(nodal(node, Vec3::Zero(), Vec3(40, -30, 20), false));
    double fd_norm = 0;
    EXPECT_LT(matrix_error(s, &fd_norm), 1e-7) << "node " << node;
    EXPECT_GT(fd_norm, 5.0) << "node " << node;
  }
}

// (D19): constant node-frame components, no matrix part, and the finite differences agree
TEST(MultibodyLoads, FollowerLoadHasNoMatrixPart) {
  MultibodySpec s = bodies();
  s.loads.push_back(nodal(5, Vec3(300, -200, 500), Vec3(40, -30, 20), true));
  s.loads.push_back(nodal(kPlateNodes + 6, Vec3(-100, 400, 250), Vec3(10, 20, -30), true));
  MultibodyModel m(s);
  m.configure(random_vector(m.size(), 9, 0.3));
  const LoadPart p = load_part(m, random_vector(m.size(), 2, 1.0), true);
  EXPECT_EQ(p.S.norm(), 0.0);
  EXPECT_NEAR(p.r[m.equation(5, 0)], -0.5 * 300, 1e-12);
  EXPECT_NEAR(p.r[m.equation(5, 4)], -0.5 * -30, 1e-12);
  EXPECT_NEAR(p.r[m.equation(kPlateNodes + 6, 5)], -0.5 * -30, 1e-12);
  double fd_norm = 0;
  EXPECT_LT(matrix_error(s, &fd_norm), 1e-12);
}

TEST(MultibodyLoads, DeadPressureMatrixIsExactAndItsForcesAddUpToPressureTimesArea) {
  MultibodySpec s = bodies();
  for (int q = 0; q < 6; ++q) s.pressures.push_back({0, PressureLoad{q, 1.0e3, false}, kRamp});
  s.pressures.push_back({1, PressureLoad{4, -2.0e3, false}, kRamp});
  {
    // flat plate 1.0 x 0.6 in the xy plane: the total force at the reference is p A e_z
    MultibodySpec plate_only = s;
    plate_only.pressures.pop_back();
    MultibodyModel m(plate_only);
    const LoadPart p = load_part(m, Eigen::VectorXd::Zero(m.size()), false);
    Vec3 total = Vec3::Zero();
    for (int I = 0; I < kPlateNodes; ++I)
      for (int j = 0; j < 3; ++j) total += m.reference_pose(I).R.col(j) * p.r[m.equation(I, j)];
    EXPECT_LT((total - Vec3(0, 0, -0.5 * 1.0e3 * 0.6)).norm(), 1e-9) << total.transpose();
  }
  double fd_norm = 0;
  EXPECT_LT(matrix_error(s, &fd_norm), 1e-7);
  EXPECT_GT(fd_norm, 10.0);
}

// A superposed rigid motion (Q, c) of the whole model: a follower load's local residual (D19) is
// unchanged, a dead one's (D17) is not (the world load stays put while the model turns).
TEST(MultibodyLoads, FollowerLoadResidualIsInvariantUnderRigidRotation) {
  MultibodySpec spec = bodies(true);  // 6 DoF everywhere, see the invariance test of test_multibody_model.cpp
  MultibodySpec dead = spec;
  for (const int node : {5, kPlateNodes + 6, kRigid}) {
    spec.loads.push_back(nodal(node, Vec3(300, -200, 500), Vec3(40, -30, 20), true));
    dead.loads.push_back(nodal(node, Vec3(300, -200, 500), Vec3(40, -30, 20), false));
  }
  for (int q = 0; q < 3; ++q) dead.pressures.push_back({0, PressureLoad{q, 1.0e3, false}, kRamp});
  const Mat3 Q = Eigen::AngleAxisd(2.2, Vec3(0.3, -0.8, 0.5).normalized()).toRotationMatrix();
  const Vec3 c(3, -1, 2);
  for (const bool follower : {true, false}) {
    const MultibodySpec& s = follower ? spec : dead;
    MultibodyModel a(s), b(s);
    a.configure(random_vector(a.size(), 5, 0.05));
    a.commit();
    // reach Q H from the reference by local increments: H_ref exp(ξ) = Q H
    Eigen::VectorXd step = Eigen::VectorXd::Zero(b.size());
    for (int I = 0; I < b.node_count(); ++I) {
      const NodePose& H = a.poses()[I];
      const NodePose& H0 = b.reference_pose(I);
      const Eigen::Matrix<double, 6, 1> xi =
          ff::lie::log_se3(ff::lie::Pose{H0.R.transpose() * Q * H.R, H0.R.transpose() * (Q * H.p + c - H0.p)});
      for (int k = 0; k < 6; ++k)
        if (b.equation(I, k) >= 0) step[b.equation(I, k)] = xi[k];
    }
    b.configure(step);
    b.commit();
    ASSERT_LT((b.poses()[3].R - Q * a.poses()[3].R).norm(), 1e-9);
    const Eigen::VectorXd v = random_vector(a.size(), 6, 1.0);
    const Eigen::VectorXd ra = load_part(a, v, false).r, rb = load_part(b, v, false).r;
    ASSERT_GT(ra.norm(), 100.0);
    if (follower)
      EXPECT_LT((ra - rb).norm(), 1e-12 * ra.norm());
    else
      EXPECT_GT((ra - rb).norm(), 0.1 * ra.norm());
  }
}

TEST(MultibodyLoads, LoadsAreCountedAsTheirOwnEffects) {
  MultibodySpec s = bodies();
  s.loads.push_back(nodal(5, Vec3(1, 0, 0), Vec3::Zero(), false));
  s.loads.push_back(nodal(6, Vec3(1, 0, 0), Vec3::Zero(), true));
  s.pressures.push_back({0, PressureLoad{2, 1.0, false}, kRamp});
  MultibodyModel m(s);
  load_part(m, Eigen::VectorXd::Zero(m.size()), true);  // two evaluations
  long long point = 0, pressure = 0;
  for (const EffectStat& e : m.effect_stats()) {
    if (e.effect == "point_loads") point = e.evaluations;
    if (e.effect == "pressure_dead") pressure = e.evaluations;
  }
  EXPECT_EQ(point, 4);
  EXPECT_EQ(pressure, 2);
}

// Where the histories jump or bend, ascending and each once; a jump wins over a bend
TEST(MultibodyLoads, SwitchTimesOfTheHistories) {
  MultibodySpec s = bodies();
  s.loads.push_back({NodalLoad{5, Vec3(1, 0, 0)}, LoadHistory{0.0, 0.5, 0.0}});     // jumps at 0 and 0.5
  s.loads.push_back({NodalLoad{6, Vec3(1, 0, 0)}, LoadHistory{0.25, 1.0, 0.25}});   // bends at 0.25, 0.5; jumps at 1
  s.pressures.push_back({0, PressureLoad{2, 1.0, false}, LoadHistory{1.0, 2.0, 0.0}});  // jumps at 1, 2
  const std::vector<LoadSwitch> sw = MultibodyModel(s).load_switches();
  const std::vector<std::pair<double, bool>> expected = {{0.0, true}, {0.25, false}, {0.5, true}, {1.0, true}, {2.0, true}};
  ASSERT_EQ(sw.size(), expected.size());
  for (std::size_t k = 0; k < sw.size(); ++k) {
    EXPECT_DOUBLE_EQ(sw[k].time, expected[k].first) << k;
    EXPECT_EQ(sw[k].jump, expected[k].second) << k;
  }
}

// The run loop lands a step on every switch (next_change) and restarts after a jump only
// (apply_changes true); a step at t = 0 is part of the initial state
TEST(MultibodyLoads, SimulationLandsOnSwitchesAndRestartsAfterJumps) {
  MultibodySpec s = bodies();
  s.loads.push_back({NodalLoad{5, Vec3(1, 0, 0)}, LoadHistory{0.0, 0.5, 0.0}});
  s.loads.push_back({NodalLoad{6, Vec3(1, 0, 0)}, LoadHistory{0.25, 1.0, 0.25}});
  ShellDynamicSettings st;
  st.dt = 0.1;
  ShellDynamicSimulation sim(s, st, RunInfo{});
  ASSERT_EQ(sim.start(), "");
  EXPECT_EQ(sim.next_change(0.0), 0.25);
  EXPECT_FALSE(sim.apply_changes(0.25));  // a ramp's corner: no jump
  EXPECT_EQ(sim.next_change(0.25), 0.5);
  EXPECT_TRUE(sim.apply_changes(0.5));
  EXPECT_EQ(sim.next_change(0.5), 1.0);
  EXPECT_TRUE(sim.apply_changes(1.0));
  EXPECT_EQ(sim.next_change(1.0), std::numeric_limits<double>::infinity());
}

// (D21): V_ext = −f(t) F̄·(x − x0) of the dead forces; follower loads have none
TEST(MultibodyLoads, LoadPotentialOfDeadForces) {
  MultibodySpec s = bodies();
  s.loads.push_back(nodal(kRigid, Vec3(3, -2, 5), Vec3(1, 1, 1), false));
  s.loads.push_back(nodal(kRigid, Vec3(7, 7, 7), Vec3::Zero(), true));
  MultibodyModel m(s);
  Eigen::VectorXd step = Eigen::VectorXd::Zero(m.size());
  for (int j = 0; j < 3; ++j) step[m.equation(kRigid, j)] = 0.1 * (j + 1);  // body axes = W: a shift by (0.1, 0.2, 0.3)
  m.configure(step);
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(m.size());
  EXPECT_NEAR(m.summary(v, kOn).load_potential, -0.5 * (0.3 - 0.4 + 1.5), 1e-12);
  EXPECT_EQ(m.summary(v, kOff).load_potential, 0.0);
}

TEST(MultibodyLoads, UnusableLoadsAreRefusedWithTheirIndex) {
  auto refused = [](const MultibodySpec& s, LoadSpecError::Part part, int index, const std::string& words) {
    try {
      MultibodyModel m(s);
      ADD_FAILURE() << "expected a refusal: " << words;
    } catch (const LoadSpecError& e) {
      EXPECT_EQ(e.part(), part) << e.what();
      EXPECT_EQ(e.index(), index) << e.what();
      EXPECT_NE(std::string(e.what()).find(words), std::string::npos) << e.what();
    }
  };
  MultibodySpec s = bodies();
  s.loads.push_back(nodal(5, Vec3(1, 0, 0), Vec3::Zero(), false));
  MultibodySpec bad = s;
  bad.loads.push_back(nodal(kRigid + 1, Vec3(1, 0, 0), Vec3::Zero(), false));
  refused(bad, LoadSpecError::Part::nodal_load, 1, "does not exist");
  bad = s;
  bad.loads[0].history = {2.0, 1.0, 0.0};
  refused(bad, LoadSpecError::Part::nodal_load, 0, "end time");
  bad = s;
  bad.pressures.push_back({0, PressureLoad{1, 1.0, true}, LoadHistory{}});
  refused(bad, LoadSpecError::Part::pressure, 0, "follower pressure is not available in dynamics");
  bad = s;
  bad.pressures.push_back({0, PressureLoad{1, 1.0, false}, LoadHistory{}});
  bad.pressures.push_back({1, PressureLoad{6, 1.0, false}, LoadHistory{}});
  refused(bad, LoadSpecError::Part::pressure, 1, "quad 6 does not exist");
}

}  // namespace
