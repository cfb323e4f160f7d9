// Effects only as asked (DESIGN.md "Effects"): every model counts what it evaluated per effect
// (EffectStat, summary.json "effect_stats"), lists only the effects that ran, and never evaluates a
// disabled one. The data a disabled effect would read (HR's H^-1, ANS tying values, drilling
// points, the hub-beam's D1 and S(L)) are NaN by construction, so a disabled term that was still
// computed -- even if multiplied by zero -- would make the result non-finite.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <random>

#include "core/hubbeam/hub_beam_system.h"
#include "core/mesh/generators.h"
#include "core/shell/cb_shell.h"
#include "core/shell/multibody_model.h"
#include "core/shell/shell_model.h"
#include "tests/support/shell_fixtures.h"

using namespace ff;
using namespace ff::shell;

namespace {

std::map<std::string, EffectStat> by_name(const std::vector<EffectStat>& stats) {
  std::map<std::string, EffectStat> m;
  for (const EffectStat& s : stats) {
    EXPECT_EQ(m.count(s.effect), 0u) << "listed twice: " << s.effect;
    EXPECT_GT(s.evaluations, 0) << s.effect << " is listed but never ran";
    m[s.effect] = s;
  }
  return m;
}

ShellOptions shell_options(int bits) {
  ShellOptions o;
  o.hr = bits & 1;
  o.ans = bits & 2;
  o.drilling = bits & 4;
  o.drilling_factor = 0.1;
  return o;
}

std::string label(const ShellOptions& o) {
  return std::string(o.hr ? "hr" : "nohr") + (o.ans ? " ans" : " noans") + (o.drilling ? " drilling" : " 5dof");
}

}  // namespace

// the element reads nothing of a disabled term: its reference data are NaN, the results finite
TEST(EffectsOnlyAsAsked, ElementNeverReadsDisabledTerms) {
  const ElementPoses ref = ff::shell::testing::curved();
  for (int bits = 0; bits < 8; ++bits) {
    const ShellOptions o = shell_options(bits);
    const CbShellElement el(ref, isotropic_section(2.0e5, 0.3, 0.05), o);
    for (unsigned seed : {1u, 2u}) {
      const ElementPoses cur = ff::shell::testing::deformed(ref, seed);
      Vec24 F, F_only;
      Mat24 K;
      el.evaluate(cur, F, &K);
      el.evaluate(cur, F_only, nullptr);
      EXPECT_TRUE(F.allFinite()) << label(o);
      EXPECT_TRUE(K.allFinite()) << label(o);
      EXPECT_TRUE(F_only.allFinite()) << label(o);
      EXPECT_TRUE(std::isfinite(el.energy(cur))) << label(o);
      EXPECT_GT(F.cwiseAbs().maxCoeff(), 0.0) << label(o);
    }
  }
}

namespace {
ShellModelSpec plate_spec(const ShellOptions& o, bool dead_pressure, bool follower_pressure, bool point_load) {
  ShellModelSpec s;
  s.mesh = mesh::rectangular_plate(1.0, 1.0, 4, 4, "plate");
  s.section = isotropic_section(1.0e6, 0.3, 0.02);
  s.options = o;
  for (int i = 0; i <= 4; ++i) s.restraints.push_back({i, kClamped});  // edge y = 0
  if (dead_pressure) s.pressures.push_back({5, 2.0, false});
  if (follower_pressure) s.pressures.push_back({10, -1.0, true}), s.pressures.push_back({11, -1.0, true});
  if (point_load) s.loads.push_back({24, Vec3(0, 0, 0.1), Vec3::Zero(), false});
  return s;
}

// n assemblies with tangent and load, as a Newton iteration does; false if anything is not finite
bool assemble(ShellModel& m, int n) {
  Eigen::VectorXd r, f;
  Eigen::SparseMatrix<double> K;
  bool finite = true;
  for (int i = 0; i < n; ++i) {
    m.evaluate(0.5, r, &K, &f);
    finite = finite && r.allFinite() && f.allFinite() && Eigen::Map<const Eigen::VectorXd>(K.valuePtr(), K.nonZeros()).allFinite();
  }
  return finite;
}
}  // namespace

TEST(EffectsOnlyAsAsked, StaticShellListsOnlyWhatRan) {
  for (int bits = 0; bits < 8; ++bits) {
    const ShellOptions o = shell_options(bits);
    for (int loads = 0; loads < 8; ++loads) {
      const bool dead = loads & 1, follower = loads & 2, point = loads & 4;
      if (!dead && !follower && !point) continue;
      ShellModel model(plate_spec(o, dead, follower, point));
      EXPECT_TRUE(model.effect_stats().empty()) << "nothing ran yet";
      EXPECT_TRUE(assemble(model, 3)) << label(o);
      const std::map<std::string, EffectStat> s = by_name(model.effect_stats());
      const std::string what = label(o) + " loads " + std::to_string(loads);
      const long long elements = 3 * 16;
      ASSERT_EQ(s.count("elastic"), 1u) << what;
      EXPECT_EQ(s.at("elastic").evaluations, elements) << what;
      EXPECT_GT(s.at("elastic").seconds, 0.0) << what;
      EXPECT_TRUE(s.at("elastic").included_in.empty());
      for (const auto& [name, on] : {std::pair<const char*, bool>{"hr", o.hr}, {"ans", o.ans}, {"drilling", o.drilling}}) {
        EXPECT_EQ(s.count(name), on ? 1u : 0u) << name << ", " << what;
        if (!on) continue;
        EXPECT_EQ(s.at(name).evaluations, elements) << name;
        EXPECT_EQ(s.at(name).included_in, "elastic") << name;
        EXPECT_TRUE(std::isnan(s.at(name).seconds)) << name << ": fused in the element, not timed apart";
      }
      EXPECT_EQ(s.count("pressure_dead"), dead ? 1u : 0u) << what;
      EXPECT_EQ(s.count("pressure_follower"), follower ? 1u : 0u) << what;
      EXPECT_EQ(s.count("point_loads"), point ? 1u : 0u) << what;
      if (dead) { EXPECT_EQ(s.at("pressure_dead").evaluations, 3); }
      if (follower) { EXPECT_EQ(s.at("pressure_follower").evaluations, 3 * 2); }
      if (point) { EXPECT_EQ(s.at("point_loads").evaluations, 3); }
      // a static model has no mass: nothing inertial, no gravity, no joints
      for (const char* never : {"inertia", "gravity", "joints", "rigid_body"}) { EXPECT_EQ(s.count(never), 0u) << never; }
      EXPECT_EQ(s.size(), 1u + o.hr + o.ans + o.drilling + dead + follower + point) << what;
    }
  }
}

namespace {
MultibodySpec pendulum_spec(const ShellOptions& o, bool gravity, bool joint, bool rigid) {
  MultibodySpec s;
  ShellBodySpec plate;
  plate.name = "plate";
  plate.mesh = mesh::rectangular_plate(1.0, 0.6, 3, 2, "plate");
  plate.section = isotropic_section(2.0e7, 0.3, 0.02);
  plate.density = 1000;
  plate.options = o;
  s.shells = {plate};
  if (rigid) {
    RigidBodySpec rb;
    rb.name = "block";
    rb.pose.p = Vec3(0.5, 1.0, 0.2);
    rb.mass = 3.0;
    s.rigid = {rb};
  }
  if (joint) s.positions.push_back({0, -1, Vec3::Zero()});
  s.gravity = gravity;
  return s;
}
}  // namespace

TEST(EffectsOnlyAsAsked, MultibodyListsOnlyWhatRanAndMatchesTheStaticNames) {
  for (int bits = 0; bits < 8; ++bits) {
    const ShellOptions o = shell_options(bits);
    for (int extra = 0; extra < 8; ++extra) {
      const bool gravity = extra & 1, joint = extra & 2, rigid = extra & 4;
      MultibodyModel m(pendulum_spec(o, gravity, joint, rigid));
      const int n = m.size(), c = m.constraint_count();
      const Eigen::VectorXd v = Eigen::VectorXd::Constant(n, 0.1), a = Eigen::VectorXd::Constant(n, -0.2);
      const Eigen::VectorXd lambda = Eigen::VectorXd::Zero(c);
      Eigen::VectorXd r, phi;
      SparseMatrixD S, B;
      IterationWeights w;
      for (int i = 0; i < 2; ++i) m.evaluate(0.0, v, a, lambda, r, phi, &w, &S, &B);
      EXPECT_TRUE(r.allFinite());
      const std::map<std::string, EffectStat> s = by_name(m.effect_stats());
      const std::string what = label(o) + " extra " + std::to_string(extra);
      const long long elements = 2 * 6;
      for (const char* always : {"elastic", "inertia"}) {
        ASSERT_EQ(s.count(always), 1u) << always << ", " << what;
        EXPECT_EQ(s.at(always).evaluations, elements);
        EXPECT_GT(s.at(always).seconds, 0.0);
      }
      for (const auto& [name, on] : {std::pair<const char*, bool>{"hr", o.hr}, {"ans", o.ans}, {"drilling", o.drilling}}) {
        EXPECT_EQ(s.count(name), on ? 1u : 0u) << name << ", " << what;
        if (!on) continue;
        EXPECT_EQ(s.at(name).evaluations, elements) << name;
        EXPECT_EQ(s.at(name).included_in, "elastic") << name;
      }
      EXPECT_EQ(s.count("gravity"), gravity ? 1u : 0u) << what;
      EXPECT_EQ(s.count("joints"), joint ? 1u : 0u) << what;
      EXPECT_EQ(s.count("rigid_body"), rigid ? 1u : 0u) << what;
      if (gravity) { EXPECT_EQ(s.at("gravity").evaluations, elements); }
      if (joint) { EXPECT_EQ(s.at("joints").evaluations, 2); }
    }
  }
}

namespace {
using namespace ff::hubbeam;
HubBeamSystem hub_beam(bool first_order, bool axial, bool torque) {
  HubBeamParams p;
  HubBeamEffects fx;
  fx.first_order_coupling = first_order;
  fx.axial = axial;
  fx.hub_torque = torque;
  return HubBeamSystem(p, fx, make_fem_basis(p.length, FemOptions{}));
}
}  // namespace

TEST(EffectsOnlyAsAsked, HubBeamListsOnlyWhatRanAndNeverEvaluatesD1WhenZeroOrder) {
  for (int bits = 0; bits < 8; ++bits) {
    const bool first_order = bits & 1, axial = bits & 2, torque = bits & 4;
    const HubBeamSystem s = hub_beam(first_order, axial, torque);
    // the zero-order model holds D1 and S(L) as NaN: any use would poison the results below
    EXPECT_EQ(s.matrices().d1.hasNaN(), !first_order);
    const int n = s.size();
    std::mt19937 gen(7);
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    Eigen::VectorXd x(n), v(n), a(n), r;
    for (int i = 0; i < n; ++i) x[i] = 0.1 * u(gen), v[i] = u(gen), a[i] = u(gen);
    v[0] = 2.0;
    Eigen::MatrixXd J;
    for (int i = 0; i < 3; ++i) s.residual(x, v, a, 0.5, r);
    for (int i = 0; i < 2; ++i) s.iteration_matrix(x, v, a, 0.5, 1.0, 0.5, 0.25, J);
    EXPECT_TRUE(r.allFinite());
    EXPECT_TRUE(J.allFinite());
    EXPECT_TRUE(std::isfinite(s.tip_axial(x)));
    EXPECT_TRUE(std::isfinite(s.kinetic_energy(x, v)));
    const std::map<std::string, EffectStat> st = by_name(s.effect_stats());
    const std::string what = std::string(first_order ? "first" : "zero") + "-order, axial " + (axial ? "on" : "off") +
                             ", torque " + (torque ? "on" : "off");
    ASSERT_EQ(st.count("inertia"), 1u);
    EXPECT_EQ(st.at("inertia").evaluations, 5);
    EXPECT_GT(st.at("inertia").seconds, 0.0);
    ASSERT_EQ(st.count("bending"), 1u);
    EXPECT_EQ(st.at("bending").included_in, "inertia");
    EXPECT_EQ(st.count("axial"), axial ? 1u : 0u) << what;
    EXPECT_EQ(st.count("first_order_coupling"), first_order ? 1u : 0u) << what;
    EXPECT_EQ(st.count("hub_torque"), torque ? 1u : 0u) << what;
    if (torque) { EXPECT_EQ(st.at("hub_torque").evaluations, 3) << "residuals only: tau(t) has no Jacobian"; }
    if (first_order) { EXPECT_EQ(st.at("first_order_coupling").evaluations, 5); }
  }
}

// switching the torque off removes exactly tau(t) from the hub equation, nothing else
TEST(EffectsOnlyAsAsked, HubTorqueOffRemovesOnlyTheTorque) {
  const HubBeamSystem on = hub_beam(true, true, true), off = hub_beam(true, true, false);
  const int n = on.size();
  Eigen::VectorXd x = Eigen::VectorXd::Constant(n, 0.01), v = Eigen::VectorXd::Constant(n, 0.2), a = v, r_on, r_off;
  on.residual(x, v, a, 0.5, r_on);
  off.residual(x, v, a, 0.5, r_off);
  EXPECT_DOUBLE_EQ(r_off[0] - r_on[0], on.torque(0.5));
  EXPECT_EQ((r_off.tail(n - 1) - r_on.tail(n - 1)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(off.torque(0.5), 0.0);
}
