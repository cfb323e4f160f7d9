// The pieces of the eigen-analyses (core/shell/shell_eigen.md): the mass in solver rows, the
// invariance of the frequencies under a rigid motion of the whole structure (the local-frame
// matrices K and M turned by the node frames), and the imperfection's move of the mesh.
#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cmath>

#include "core/mesh/generators.h"
#include "core/shell/multibody_modes.h"
#include "core/shell/shell_eigen_simulation.h"

namespace {
using namespace ff::shell;

ShellModelSpec free_plate(int n) {
  ShellModelSpec s;
  s.mesh = ff::mesh::rectangular_plate(1.0, 0.6, n, n);
  s.section.youngs_modulus = 2.1e11;
  s.section.poisson_ratio = 0.3;
  s.section.thickness = 0.01;
  s.options.hr = s.options.ans = true;
  return s;
}

std::vector<double> frequencies(ShellModelSpec spec, int modes) {
  ShellEigenSettings st;
  st.modes = modes;
  st.densities.assign(spec.mesh.quad_count(), 7800.0);
  ShellEigenSimulation sim(std::move(spec), st, ff::RunInfo{});
  EXPECT_EQ(sim.compute(), "");
  std::vector<double> f;
  for (const ff::Mode& m : sim.modes()->modes) f.push_back(m.value);
  return f;
}
}  // namespace

// u^T M u for a unit rigid translation is the plate's mass rho h A, along every axis.
TEST(ShellEigenUnit, MassOfARigidTranslationIsTheTotalMass) {
  ShellModel model(free_plate(6));
  std::vector<CbShellInertia> inertia;
  for (int k = 0; k < model.elements().size(); ++k) {
    ElementPoses ref;
    ShellElements::corner_poses(model.elements()[k], model.poses(), ref);
    inertia.emplace_back(ref, model.elements()[k].elastic->section(), 7800.0);
  }
  Eigen::SparseMatrix<double> M;
  model.assemble_element_matrices(
      [&](int k, const ElementPoses& cur, Mat24& m) {
        ElementRates still;
        for (Vec6& v : still) v.setZero();
        Vec24 f;
        InertiaJacobians jac;
        jac.mass = &m;
        m.setZero();
        inertia[k].evaluate(cur, still, still, f, jac);
      },
      M);
  for (int axis = 0; axis < 3; ++axis) {
    Eigen::VectorXd u = Eigen::VectorXd::Zero(model.size());
    for (int I = 0; I < model.spec().mesh.node_count(); ++I) u[model.equation(I, axis)] = 1.0;
    EXPECT_NEAR(u.dot(M * u), 7800.0 * 0.01 * 0.6, 1e-9 * 46.8) << "axis " << axis;
  }
  EXPECT_LT((Eigen::MatrixXd(M) - Eigen::MatrixXd(M).transpose()).cwiseAbs().maxCoeff(), 1e-12 * M.coeffs().maxCoeff());
}

// The free plate turned and moved as a whole has the same frequencies (to round-off): K and M are
// formed in the node frames and turned by them, so a rigid motion of the reference cannot change
// them. Six zero modes in both.
TEST(ShellEigenUnit, FrequenciesAreInvariantUnderARigidMotion) {
  const std::vector<double> flat = frequencies(free_plate(6), 10);
  ShellModelSpec turned = free_plate(6);
  const Mat3 Q = Eigen::AngleAxisd(0.7, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  for (int I = 0; I < turned.mesh.node_count(); ++I) {
    turned.mesh.points[I] = Q * turned.mesh.points[I] + Vec3(3, -1, 2);
    turned.mesh.frames[I] = Q * turned.mesh.frames[I];
    turned.mesh.normals[I] = Q * turned.mesh.normals[I];
  }
  for (auto& corners : turned.mesh.corner_normals)
    for (Vec3& n : corners) n = Q * n;
  turned.mesh.frame_reference = Q * turned.mesh.frame_reference;
  const std::vector<double> moved = frequencies(std::move(turned), 10);
  ASSERT_EQ(flat.size(), moved.size());
  for (int k = 0; k < 6; ++k) {
    EXPECT_EQ(flat[k], 0.0);
    EXPECT_EQ(moved[k], 0.0);
  }
  for (std::size_t k = 6; k < flat.size(); ++k) { EXPECT_NEAR(moved[k], flat[k], 1e-8 * flat[k]) << k; }
}

// A mode that is a rigid translation along z moves every node by the amplitude along z and turns no
// frame; a rotation slot turns the node's frame about its own e1 (5-DoF node) by the scaled angle.
TEST(ShellEigenUnit, ImperfectionMovesNodesAsTheStateUpdateDoes) {
  ShellModel model(free_plate(3));
  Eigen::VectorXd mode = Eigen::VectorXd::Zero(model.size());
  for (int I = 0; I < model.spec().mesh.node_count(); ++I) mode[model.equation(I, 2)] = -4.0;
  const int node = 5;
  mode[model.equation(node, 3)] = 2.0;  // half the largest translation: the angle becomes 0.5 x amplitude
  const ff::mesh::ShellMesh moved = perturbed_mesh(model, mode, 0.01);
  for (int I = 0; I < model.spec().mesh.node_count(); ++I) {
    EXPECT_NEAR((moved.points[I] - model.spec().mesh.points[I] - Vec3(0, 0, -0.01)).norm(), 0.0, 1e-15);
    if (I != node) {
      EXPECT_LT((moved.frames[I] - model.spec().mesh.frames[I]).norm(), 1e-15);
    }
  }
  const Mat3 R0 = model.spec().mesh.frames[node];
  const Mat3 expected = R0 * Eigen::AngleAxisd(0.005, Vec3::UnitX()).toRotationMatrix();
  EXPECT_LT((moved.frames[node] - expected).norm(), 1e-14);
  EXPECT_LT((moved.normals[node] - expected.col(2)).norm(), 1e-14);
}

// Joints are honoured (shell_eigen.md (E2')): two free plates side by side have 12 zero
// frequencies; joined node by node along their common edge (a hinge line: translations tied,
// rotations free) they keep 6 rigid-body modes plus the hinge's mechanism, 7, and the first
// elastic frequency is finite. The bordered shift-invert solves with the constraint rows.
TEST(ShellEigenUnit, HingedPlatesHaveSevenZeroFrequencies) {
  auto two_plates = [](bool hinge) {
    MultibodySpec spec;
    for (int p = 0; p < 2; ++p) {
      ShellBodySpec b;
      b.name = p == 0 ? "left" : "right";
      b.mesh = ff::mesh::rectangular_plate(1.0, 1.0, 4, 4);
      for (Vec3& x : b.mesh.points) x.x() += p;  // right plate on x in [1, 2]
      b.section.youngs_modulus = 2.1e11;
      b.section.poisson_ratio = 0.3;
      b.section.thickness = 0.01;
      b.options.hr = b.options.ans = true;
      b.options.drilling = false;
      b.density = 7800.0;
      spec.shells.push_back(std::move(b));
    }
    if (hinge) {
      const int offset = spec.shells[0].mesh.node_count();
      for (int i = 0; i < spec.shells[0].mesh.node_count(); ++i) {
        if (std::abs(spec.shells[0].mesh.points[i].x() - 1.0) > 1e-12) continue;
        for (int j = 0; j < spec.shells[1].mesh.node_count(); ++j)
          if ((spec.shells[1].mesh.points[j] - spec.shells[0].mesh.points[i]).norm() < 1e-12)
            spec.positions.push_back({i, offset + j});
      }
      EXPECT_EQ(spec.positions.size(), 5u);
    }
    MultibodyModel model(std::move(spec));
    ff::EigenSolveSettings st;
    st.count = 14;
    return multibody_modes(model, st);
  };
  for (const bool hinge : {false, true}) {
    const MultibodyModes modes = two_plates(hinge);
    ASSERT_TRUE(modes.result.ok()) << modes.result.error;
    const int zeros = static_cast<int>(std::count(modes.rigid_body.begin(), modes.rigid_body.end(), true));
    EXPECT_EQ(zeros, hinge ? 7 : 12) << (hinge ? "hinged" : "apart");
    const int first_elastic = zeros;
    ASSERT_LT(first_elastic, static_cast<int>(modes.result.values.size()));
    EXPECT_GT(modes.result.values[first_elastic], 1e-6 * modes.reference_omega2 * 1e-6);
  }
}
