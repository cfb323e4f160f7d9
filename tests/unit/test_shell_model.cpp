// Shell model assembly (core/shell/shell_model.h): the assembled tangent is the derivative of the
// assembled residual along the solver's own update() (global translations, global 6-DoF rotations,
// local 5-DoF rotations), with restraints, a symmetry plane, fixed and follower loads.
#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <tuple>

#include "core/assembly/element_threads.h"
#include "core/shell/shell_model.h"
#include "tests/support/static_fd.h"

using namespace ff::shell;

namespace {
// nx x ny quads on a cylindrical patch (radius R, axis y) or a flat plate (R = 0)
ff::mesh::ShellMesh patch(int nx, int ny, double R) {
  ff::mesh::ShellMesh m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double s = 1.0 * i / nx - 0.5, y = 0.8 * j / ny;
      if (R > 0) {
        const Vec3 n(std::sin(s / R), 0, std::cos(s / R));
        m.points.push_back(R * n + Vec3(0, y, -R));
        m.normals.push_back(n);
      } else {
        m.points.emplace_back(s, y, 0);
        m.normals.push_back(Vec3::UnitZ());
      }
    }
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = j * (nx + 1) + i;
      m.quads.push_back({a, a + 1, a + nx + 2, a + nx + 1});
    }
  for (const Vec3& n : m.normals) m.frames.push_back(ff::mesh::frame_from_normal(n, Vec3::UnitX()));
  m.fold.assign(m.points.size(), 0);
  return m;
}

ShellModelSpec spec(bool drilling, double R) {
  ShellModelSpec s;
  s.mesh = patch(3, 2, R);
  s.section = isotropic_section(1.0e4, 0.3, 0.02);
  s.options.drilling = drilling;
  s.options.drilling_factor = 0.1;
  // clamp the edge y = 0 except a node on the symmetry plane x = 0... here: clamp nodes 0 and 3
  s.restraints = {{0, kClamped}, {3, kClamped}, {1, kUz}};
  s.symmetry = {{2, 0}};  // node 2 sits at x = 0 (nx = 3: x = -0.5, -1/6, 1/6, 0.5 -> no; use plane normal y)
  s.symmetry = {{1, 1}};  // node 1 on y = 0: plane normal y contains the director
  s.loads = {{11, Vec3(0.1, 0.2, -0.3), Vec3::Zero(), false},
             {10, Vec3(0.05, 0.0, 0.2), Vec3(0.01, -0.02, 0.0), true},
             {9, Vec3::Zero(), Vec3(0.0, 0.03, 0.01), false}};
  // quads 0-5: one dead and two follower pressures (quad 1 has restrained corners)
  s.pressures = {{0, 0.4, false}, {1, -0.7, true}, {4, 0.9, true}};
  return s;
}

// size of the model of spec s without the restraints of node `node`
int spec_size_without(ShellModelSpec s, int node) {
  std::erase_if(s.restraints, [&](const auto& r) { return r.first == node; });
  return ShellModel(s).size();
}

Eigen::VectorXd unit(int n, int k, double h) {
  Eigen::VectorXd d = Eigen::VectorXd::Zero(n);
  d[k] = h;
  return d;
}
}  // namespace

class ShellModelTangent : public ::testing::TestWithParam<std::tuple<bool, double>> {};

TEST_P(ShellModelTangent, MatchesCentralDifferencesOfTheResidual) {
  const auto [drilling, R] = GetParam();
  ShellModel model(spec(drilling, R));
  const int n = model.size();
  // a large deformed state reached through the solver's own update
  std::mt19937 g(11);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  Eigen::VectorXd d(n);
  for (int k = 0; k < n; ++k) d[k] = u(g);
  model.update(d);
  const double lambda = 0.7;
  Eigen::VectorXd r, rp, rm;
  Eigen::SparseMatrix<double> K;
  model.evaluate(lambda, r, &K, nullptr);
  const Eigen::MatrixXd Kd = Eigen::MatrixXd(K);
  const double h = 1e-6;
  const Eigen::MatrixXd Kfd = ff::test::central_difference_tangent(model, lambda, h);
  const double scale = Kd.cwiseAbs().maxCoeff();
  EXPECT_LT((Kd - Kfd).cwiseAbs().maxCoeff(), 2e-6 * scale) << "drilling " << drilling << " R " << R;
  // the load vector is dr/dlambda with the sign of the convention r = f_int - lambda f_ref
  Eigen::VectorXd load, r2;
  model.evaluate(lambda, r, nullptr, &load);
  model.evaluate(lambda + 1e-3, r2, nullptr, nullptr);
  EXPECT_LT(((r2 - r) / 1e-3 + load).cwiseAbs().maxCoeff(), 1e-9 * (1 + load.cwiseAbs().maxCoeff()));
}

INSTANTIATE_TEST_SUITE_P(FiveAndSixDofs, ShellModelTangent,
                         ::testing::Combine(::testing::Bool(), ::testing::Values(0.0, 1.5)));

// The follower-pressure load stiffness alone: tangent(with pressure) - tangent(without) against
// central differences of residual(with) - residual(without), bounded relative to the pressure
// part itself (the full-tangent test above bounds it only against the much stiffer elements).
TEST_P(ShellModelTangent, FollowerPressureStiffnessMatchesCentralDifferences) {
  const auto [drilling, R] = GetParam();
  ShellModelSpec with = spec(drilling, R), without = with;
  without.pressures.clear();
  with.pressures = {{1, -7.0, true}, {4, 9.0, true}, {5, 3.0, true}};
  ShellModel a(with), b(without);
  const int n = a.size();
  std::mt19937 g(5);
  std::uniform_real_distribution<double> u(-0.15, 0.15);
  Eigen::VectorXd d(n);
  for (int k = 0; k < n; ++k) d[k] = u(g);
  a.update(d);
  b.update(d);
  const double lambda = 0.7;
  auto residual_difference = [&](const Eigen::VectorXd& step) {
    Eigen::VectorXd ra, rb;
    a.save_state(), b.save_state();
    a.update(step), b.update(step);
    a.evaluate(lambda, ra, nullptr, nullptr);
    b.evaluate(lambda, rb, nullptr, nullptr);
    a.restore_state(), b.restore_state();
    return Eigen::VectorXd(ra - rb);
  };
  Eigen::VectorXd r;
  Eigen::SparseMatrix<double> Ka, Kb;
  a.evaluate(lambda, r, &Ka, nullptr);
  b.evaluate(lambda, r, &Kb, nullptr);
  const Eigen::MatrixXd Kp = Eigen::MatrixXd(Ka) - Eigen::MatrixXd(Kb);
  Eigen::MatrixXd Kfd(n, n);
  const double h = 1e-5;
  for (int k = 0; k < n; ++k) Kfd.col(k) = (residual_difference(unit(n, k, h)) - residual_difference(unit(n, k, -h))) / (2 * h);
  const double scale = Kp.cwiseAbs().maxCoeff();
  ASSERT_GT(scale, 0.1);  // the pressure part is really there
  // the pressure forces are quadratic in the translations: central differences are exact up to
  // round-off of the element residuals (~1e-16 x E h / h_fd ~ 1e-9)
  EXPECT_LT((Kp - Kfd).cwiseAbs().maxCoeff(), 1e-6 * scale);
  // non-symmetric in general
  EXPECT_GT((Kp - Kp.transpose()).cwiseAbs().maxCoeff(), 1e-3 * scale);
}

// Resultants of a uniform pressure p on the flat patch (area 1 x 0.8, normal +z): p A e_z in the
// reference configuration; after a rigid rotation Q the follower resultant turns to p A Q e_z and
// the dead one stays.
TEST(ShellModel, PressureResultantIsPressureTimesArea) {
  ShellModelSpec s = spec(false, 0.0);
  s.restraints.clear(), s.symmetry.clear(), s.loads.clear();
  const double p = 2.5;
  for (bool follower : {false, true}) {
    s.pressures.clear();
    for (int q = 0; q < s.mesh.quad_count(); ++q) s.pressures.push_back({q, p, follower});
    ShellModel m(s);
    Eigen::VectorXd r, load;
    const Mat3 Q = Eigen::AngleAxisd(0.8, Vec3(1, 2, -0.5).normalized()).toRotationMatrix();
    Eigen::VectorXd d = Eigen::VectorXd::Zero(m.size());
    for (int I = 0; I < s.mesh.node_count(); ++I)
      d.segment<3>(m.equation(I, 0)) = Q * s.mesh.points[I] - s.mesh.points[I];
    for (int pass = 0; pass < 2; ++pass) {
      m.evaluate(1.0, r, nullptr, &load);
      Vec3 total = Vec3::Zero();
      for (int I = 0; I < s.mesh.node_count(); ++I) total += load.segment<3>(m.equation(I, 0));
      const Vec3 expected = p * 0.8 * (pass == 1 && follower ? Vec3(Q * Vec3::UnitZ()) : Vec3::UnitZ());
      EXPECT_LT((total - expected).norm(), 1e-13) << "follower " << follower << " rotated " << pass;
      m.update(d);  // translations only: the follower load reads positions, not rotations
    }
  }
}

TEST(ShellModel, RestraintsAreExactAndCounted) {
  ShellModel five(spec(false, 1.5)), six(spec(true, 1.5));
  // 12 nodes; 5-DoF: 60 - clamped 2x5 - uz 1 - symmetry (u_y, theta_2) 2 = 47
  EXPECT_EQ(five.size(), 12 * 5 - 10 - 1 - 2);
  // 6-DoF: 72 - 12 - 1 - symmetry (u_y, r_x, r_z) 3 = 56
  EXPECT_EQ(six.size(), 12 * 6 - 12 - 1 - 3);
  // whatever the update, restrained global components stay at zero
  for (ShellModel* m : {&five, &six}) {
    Eigen::VectorXd d = Eigen::VectorXd::Constant(m->size(), 0.2);
    m->update(d);
    EXPECT_EQ(m->node_displacement(0).norm(), 0.0);
    EXPECT_EQ(m->node_displacement(1).z(), 0.0);
    EXPECT_EQ(m->node_displacement(1).y(), 0.0);
    // symmetry: the director of node 1 stays in the plane y = 0 (rotation only about y's normal)
    EXPECT_NEAR(m->poses()[1].R.col(2).y(), 0.0, 1e-14);
  }
}

// A 5-DoF node has no drilling rotation, so holding its rotation about one global axis x (not the
// director z) leaves it exactly one free axis, d x x = y (shell_model.md eq. R5): after any
// update its rotation has no component about x, and its director stays in the plane x = 0.
TEST(ShellModel, SingleAxisRotationRestraintOnFiveDofNodeLeavesOneFreeAxis) {
  ShellModelSpec s = spec(false, 0.0);
  s.restraints.push_back({5, kRx});
  ShellModel five(s);
  EXPECT_EQ(five.size(), spec_size_without(s, 5) - 1);
  std::mt19937 g(3);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (int pass = 0; pass < 3; ++pass) {
    Eigen::VectorXd d(five.size());
    for (int k = 0; k < five.size(); ++k) d[k] = u(g);
    five.update(d);
    const Mat3 Q = five.poses()[5].R * five.spec().mesh.frames[5].transpose();  // rotation since the start
    const Eigen::AngleAxisd aa(Q);
    EXPECT_GT(aa.angle(), 1e-3);
    EXPECT_LT(std::abs(aa.axis().x()), 1e-12) << "rotation axis " << aa.axis().transpose();
  }
  s.options.drilling = true;
  EXPECT_NO_THROW(ShellModel{s});
}

// The element loop's threads do not change the assembly: residual, tangent and load vector of a
// deformed curved patch are bitwise those of one thread, on the loop back-end of this build
// (oneTBB, or the std::thread pool with FLEXFRAME_ELEMENT_THREADS=std: scripts/sanitize --tsan
// runs this test on that one).
TEST(ShellModelThreads, AssemblyIsBitwiseTheSameOnAnyThreadCount) {
  ShellModelSpec s = spec(true, 1.5);
  s.mesh = patch(12, 9, 1.5);
  s.loads = {{40, Vec3(0.1, 0.2, -0.3), Vec3::Zero(), false}};
  s.pressures = {{7, 0.4, false}, {20, -0.7, true}, {33, 0.9, true}};
  auto assemble = [&](int threads) {
    ShellModel model(s);
    model.set_threads({threads, nullptr});
    std::mt19937 g(3);
    std::uniform_real_distribution<double> u(-0.1, 0.1);
    Eigen::VectorXd d(model.size());
    for (int k = 0; k < model.size(); ++k) d[k] = u(g);
    model.update(d);
    Eigen::VectorXd r, load;
    Eigen::SparseMatrix<double> K;
    model.evaluate(0.7, r, &K, &load);
    return std::tuple(r, Eigen::MatrixXd(K), load);
  };
  const auto [r1, K1, l1] = assemble(1);
  ASSERT_GT(r1.cwiseAbs().maxCoeff(), 0.0);
  for (int threads : {2, 3, 7}) {
    const auto [r, K, l] = assemble(threads);
    const std::string on = std::to_string(threads) + " threads (" + ff::assembly::element_loop_backend() + ")";
    EXPECT_TRUE(r.size() == r1.size() && std::memcmp(r.data(), r1.data(), r.size() * sizeof(double)) == 0) << on;
    EXPECT_TRUE(K.size() == K1.size() && std::memcmp(K.data(), K1.data(), K.size() * sizeof(double)) == 0) << on;
    EXPECT_TRUE(l.size() == l1.size() && std::memcmp(l.data(), l1.data(), l.size() * sizeof(double)) == 0) << on;
  }
}
