// The stress fields as the models report them (core/shell/shell_stress.h): one node's value, what a
// probe reads, is the nodal field's value there bit for bit (the same elements summed in the same
// order), in the static and the dynamic model, on a structure whose sections differ (a laminated
// part beside an isotropic one: a ply field is the mean over the elements that have the ply only),
// at a deformed state; and the layout and field list follow the sections.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <memory>
#include <random>

#include "core/lie/se3.h"
#include "core/mesh/generators.h"
#include "core/shell/multibody_model.h"
#include "core/shell/shell_model.h"
#include "core/shell/shell_stress.h"

using namespace ff;
using namespace ff::shell;

namespace {

// a [0/90] section of the same thickness as the isotropic one
ShellSection laminate(double thickness) {
  ShellSection s = isotropic_section(2.0e7, 0.3, thickness);
  Ply p;
  p.e1 = 1.4e8, p.e2 = 1.0e7, p.g12 = p.g13 = 5.0e6, p.g23 = 3.0e6, p.nu12 = 0.25;
  p.thickness = thickness / 2;
  p.density = 1500.0;
  auto plies = std::make_shared<std::vector<Ply>>(2, p);
  (*plies)[1].angle = std::acos(-1.0) / 2;
  s.plies = plies;
  return s;
}

// a 4 x 3 cylindrical panel whose first column of quads is laminated, clamped along one edge
ShellModelSpec mixed_panel() {
  mesh::CylinderPatch cyl;
  cyl.radius = 0.5;
  cyl.phi0 = -0.6;
  cyl.phi1 = 0.6;
  cyl.s0 = 0;
  cyl.s1 = 0.6;
  ShellModelSpec s;
  s.mesh = mesh::cylindrical_patch(cyl, 4, 3, "panel");
  s.section = isotropic_section(2.0e7, 0.3, 0.02);
  s.sections = {s.section, laminate(0.02)};
  s.drilling_factors = {1e-3, 1e-3};
  s.quad_section.assign(s.mesh.quad_count(), 0);
  for (int q = 0; q < s.mesh.quad_count(); q += 4) s.quad_section[q] = 1;
  s.restraints = {{0, kClamped}, {1, kClamped}, {2, kClamped}, {3, kClamped}, {4, kClamped}};
  s.loads = {{19, Vec3(0.0, 0.0, -1.0), Vec3::Zero(), false}};
  return s;
}

// node poses moved off the reference: a translation and a small turn of every node's frame
std::vector<NodePose> shaken(std::vector<NodePose> poses, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  for (NodePose& X : poses) {
    X.p += Vec3(u(rng), u(rng), u(rng));
    X.R = lie::exp_so3(Vec3(u(rng), u(rng), u(rng))) * X.R;
  }
  return poses;
}

void expect_node_values_match_fields(const std::vector<std::vector<double>>& fields, std::size_t field_count,
                                     std::size_t node_count, const std::function<double(int, std::size_t)>& node_value) {
  ASSERT_EQ(fields.size(), field_count);
  for (std::size_t f = 0; f < field_count; ++f) {
    ASSERT_EQ(fields[f].size(), node_count);
    bool loaded = false;  // the shaken state stresses every field somewhere: the comparison is not 0 = 0
    for (std::size_t n = 0; n < node_count; ++n) {
      ASSERT_EQ(node_value(static_cast<int>(n), f), fields[f][n]) << "field " << f << " node " << n;
      loaded = loaded || fields[f][n] != 0.0;
    }
    EXPECT_TRUE(loaded) << "field " << f << " is zero at every node";
  }
}

TEST(StressOutputs, LayoutAndFieldsFollowTheSections) {
  const ShellModel iso([] {
    ShellModelSpec s = mixed_panel();
    s.sections.clear(), s.drilling_factors.clear(), s.quad_section.clear();
    return s;
  }());
  EXPECT_EQ(iso.stress_layout().max_plies, 0);
  EXPECT_FALSE(iso.stress_layout().failure_index);
  const std::vector<StressField> plain = stress_fields(iso.stress_layout());
  ASSERT_EQ(plain.size(), 24u);  // von Mises 3, principal 4, section stresses 9, N 3, M 3, Q 2
  EXPECT_EQ(plain.front().name, "von_mises");
  for (const StressField& f : plain) { EXPECT_FALSE(f.description.empty()) << f.name; }

  const ShellModel mixed(mixed_panel());
  EXPECT_EQ(mixed.stress_layout().max_plies, 2);
  EXPECT_FALSE(mixed.stress_layout().failure_index);  // no strengths given
  const std::vector<StressField> layered = stress_fields(mixed.stress_layout());
  ASSERT_EQ(layered.size(), 24u + 2 * 3);
  EXPECT_EQ(layered[24].name, "ply1_sigma1");
  EXPECT_EQ(layered.back().name, "ply2_tau12");
  EXPECT_EQ(mixed.nodal_stress_fields().size(), layered.size());
}

TEST(StressOutputs, StaticNodeValueIsTheNodalFieldBitForBit) {
  ShellModel model(mixed_panel());
  model.set_state({shaken(model.poses(), 7)});
  const std::size_t nf = stress_fields(model.stress_layout()).size();
  expect_node_values_match_fields(model.nodal_stress_fields(), nf, model.poses().size(),
                                  [&](int n, std::size_t f) { return model.nodal_stress(n, f); });
}

TEST(StressOutputs, PlyFieldIsTheMeanOverTheElementsWithThePly) {
  // node 1 (on the clamped edge) touches laminated quad 0 (its corner 1) and isotropic quad 1 (its
  // corner 0): its ply fields are quad 0's corner values, its section fields the mean of both
  // quads' values at that corner
  ShellModelSpec spec = mixed_panel();
  const mesh::ShellMesh mesh = spec.mesh;
  ShellModel model(spec);
  model.set_state({shaken(model.poses(), 11)});
  const std::vector<StressField> names = stress_fields(model.stress_layout());
  const auto fields = model.nodal_stress_fields();
  ElementStress s0, s1;
  auto element_stress = [&](int q, const ShellSection& section, int corner, ElementStress& out) {
    ElementPoses ref, cur;
    for (int c = 0; c < 4; ++c) {
      const int I = mesh.quads[q][c];
      ref[c] = {mesh.frames[I], mesh.points[I]};
      cur[c] = model.poses()[I];
    }
    CbShellElement(ref, section, spec.options).stresses(cur, out, corner);
  };
  ASSERT_EQ(mesh.quads[0][1], 1);
  ASSERT_EQ(mesh.quads[1][0], 1);
  element_stress(0, spec.sections[1], 1, s0);
  element_stress(1, spec.sections[0], 0, s1);
  ASSERT_EQ(s0.plies, 2);
  ASSERT_EQ(s1.plies, 0);
  ASSERT_NE(s0.ply[1][1][0], 0.0);
  ASSERT_NE(s0.N[0] + s1.N[0], 0.0);
  const int node = 1;
  for (std::size_t f = 0; f < names.size(); ++f) {
    if (names[f].name == "N11") { EXPECT_EQ(fields[f][node], 0.5 * (s0.N[0] + s1.N[0])); }
    if (names[f].name == "sigma22_top") { EXPECT_EQ(fields[f][node], 0.5 * (s0.surface[2][1] + s1.surface[2][1])); }
    if (names[f].name == "ply2_sigma1") { EXPECT_EQ(fields[f][node], s0.plies >= 2 ? s0.ply[1][1][0] : 0.0); }
  }
}

TEST(StressOutputs, DynamicNodeValueIsTheNodalFieldBitForBit) {
  MultibodySpec spec;
  ShellBodySpec panel;
  const ShellModelSpec mixed = mixed_panel();
  panel.name = "panel";
  panel.mesh = mixed.mesh;
  panel.section = mixed.section;
  panel.sections = mixed.sections;
  panel.quad_material = mixed.quad_section;
  panel.densities = {1000.0, 1500.0};
  panel.drilling_factors = mixed.drilling_factors;
  panel.density = 1000.0;
  spec.shells = {panel};
  RigidBodySpec block;  // a rigid body's node has no element: 0 in every field
  block.name = "block";
  block.pose.p = Vec3(0.0, 1.0, 0.0);
  spec.rigid = {block};
  MultibodyModel model(spec);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(-0.02, 0.02);
  Eigen::VectorXd step(model.size());
  for (int k = 0; k < model.size(); ++k) step[k] = u(rng);
  model.configure(step);
  const std::size_t nf = stress_fields(model.stress_layout()).size();
  EXPECT_EQ(model.stress_layout().max_plies, 2);
  const auto fields = model.nodal_stress_fields();
  expect_node_values_match_fields(fields, nf, model.node_count(),
                                  [&](int n, std::size_t f) { return model.nodal_stress(n, f); });
  for (std::size_t f = 0; f < nf; ++f) { EXPECT_EQ(fields[f][model.rigid_node(0)], 0.0); }
}

}  // namespace
