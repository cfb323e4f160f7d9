// Supports in any axes (core/shell/shell_model.md §R): node bases for restraints in oblique,
// cylindrical or nodal directions, symmetry planes of any normal, prescribed displacements and
// reactions. The tangent and the load vector are checked against central differences of the
// residual along the model's own update() and load factor; restrained directions stay exact.
#include <gtest/gtest.h>

#include <random>

#include "core/shell/shell_model.h"
#include "tests/support/static_fd.h"

using namespace ff::shell;

namespace {
// nx x ny quads of a cylindrical patch (radius R, axis y): x = R sin(s/R), z = R cos(s/R) - R
ff::mesh::ShellMesh cylinder_patch(int nx, int ny, double R) {
  ff::mesh::ShellMesh m;
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) {
      const double s = 1.0 * i / nx - 0.5, y = 0.8 * j / ny;
      const Vec3 n(std::sin(s / R), 0, std::cos(s / R));
      m.points.push_back(R * n + Vec3(0, y, -R));
      m.normals.push_back(n);
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

// restraints along oblique directions, a symmetry plane that is no coordinate plane, a prescribed
// displacement along an oblique direction, follower and dead loads
ShellModelSpec oblique_spec(bool drilling) {
  ShellModelSpec s;
  s.mesh = cylinder_patch(3, 2, 1.5);  // nodes 0..3 at y = 0, 4..7 at y = 0.4, 8..11 at y = 0.8
  s.section = isotropic_section(1.0e4, 0.3, 0.02);
  s.options.drilling = drilling;
  s.options.drilling_factor = 0.1;
  const Vec3 d1 = Vec3(1, 1, 0).normalized(), d2 = Vec3(0.2, -0.3, 1).normalized();
  s.directions = {{0, d1, false, 0.0, 0}, {0, d2, false, 0.0, 0}, {0, Vec3(0, 1, 1), true, 0.0, 0},
                  {3, Vec3::UnitY(), false, 0.0, 1}, {3, Vec3(1, 0, 1), false, 0.0, 1},
                  {3, Vec3(0.3, 0.4, 0.5), false, 0.05, 2},  // prescribed: 3 directions span R^3
                  {2, Vec3(0.6, -0.8, 0.0), false, -0.03, 3}};
  // node 1 on the plane through the y axis' parallel that contains its director and y
  const Vec3 d = s.mesh.normals[1];
  s.symmetry_planes = {{1, d.cross(Vec3::UnitY()), 4}};
  s.loads = {{11, Vec3(0.1, 0.2, -0.3), Vec3::Zero(), false}, {10, Vec3(0.05, 0.0, 0.2), Vec3(0.01, -0.02, 0.0), true}};
  s.pressures = {{4, 0.9, true}};
  return s;
}

}  // namespace

class ShellSupports : public ::testing::TestWithParam<bool> {};

TEST_P(ShellSupports, TangentAndLoadMatchCentralDifferencesWithObliqueBases) {
  ShellModel model(oblique_spec(GetParam()));
  const int n = model.size();
  std::mt19937 g(7);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  Eigen::VectorXd d(n);
  for (int k = 0; k < n; ++k) d[k] = u(g);
  const double lambda = 0.6;
  Eigen::VectorXd r, rp, rm, load;
  model.evaluate(lambda, r, nullptr, nullptr);  // prescribed nodes at lambda
  model.update(d);
  Eigen::SparseMatrix<double> K;
  model.evaluate(lambda, r, &K, &load);
  const Eigen::MatrixXd Kd(K);
  const double h = 1e-6;
  const Eigen::MatrixXd Kfd = ff::test::central_difference_tangent(model, lambda, h);
  const double scale = Kd.cwiseAbs().maxCoeff();
  EXPECT_LT((Kd - Kfd).cwiseAbs().maxCoeff(), 2e-6 * scale);
  // f_ref = -dr/dlambda: the loads plus -K_ap value_p through the prescribed columns (eq. R4);
  // evaluate() moves the prescribed nodes to each lambda itself
  model.save_state();
  model.evaluate(lambda + h, rp, nullptr, nullptr);
  model.restore_state();
  model.evaluate(lambda - h, rm, nullptr, nullptr);
  model.restore_state();
  const Eigen::VectorXd dr = (rp - rm) / (2 * h);
  EXPECT_LT((dr + load).cwiseAbs().maxCoeff(), 1e-6 * (1 + load.cwiseAbs().maxCoeff()));
  // the same load vector without the tangent (the elements at prescribed nodes still give K_ap)
  Eigen::VectorXd load_only;
  model.evaluate(lambda, r, nullptr, &load_only);
  EXPECT_LT((load_only - load).cwiseAbs().maxCoeff(), 1e-12 * (1 + load.cwiseAbs().maxCoeff()));
  // the prescribed part is really there: without it the load would differ
  ShellModelSpec plain = oblique_spec(GetParam());
  for (DirectionRestraint& r : plain.directions) r.value = 0.0;
  ShellModel unloaded(plain);
  Eigen::VectorXd load_plain;
  unloaded.evaluate(lambda, r, nullptr, &load_plain);
  EXPECT_GT((load_plain - load).cwiseAbs().maxCoeff(), 1e-3 * load.cwiseAbs().maxCoeff());
}

TEST_P(ShellSupports, RestrainedAndPrescribedDirectionsAreExact) {
  ShellModelSpec s = oblique_spec(GetParam());
  ShellModel model(s);
  std::mt19937 g(9);
  std::uniform_real_distribution<double> u(-0.3, 0.3);
  for (const double lambda : {0.3, -1.2, 2.0}) {
    Eigen::VectorXd d(model.size()), r;
    for (int k = 0; k < model.size(); ++k) d[k] = u(g);
    const Mat3 R_before = model.poses()[0].R;
    model.update(d);
    // node 0: its rotation increment about (0, 1, 1) is held (6 DoFs: the increment R_after
    // R_before^T has no component along it; 5 DoFs: the restraint projected on the tangent plane)
    if (GetParam()) {
      const Eigen::AngleAxisd inc(Mat3(model.poses()[0].R * R_before.transpose()));
      EXPECT_GT(inc.angle(), 1e-3);
      EXPECT_LT(std::abs(inc.angle() * inc.axis().dot(Vec3(0, 1, 1).normalized())), 1e-12);
    }
    model.evaluate(lambda, r, nullptr, nullptr);
    for (const DirectionRestraint& c : s.directions) {
      if (c.rotation) continue;
      const double moved = c.direction.normalized().dot(model.node_displacement(c.node));
      EXPECT_NEAR(moved, lambda * c.value, 1e-14) << "node " << c.node;
    }
    // node 3 is held in all three directions: it sits exactly at its prescribed point
    const Vec3 dirs[3] = {Vec3::UnitY(), Vec3(1, 0, 1).normalized(), Vec3(0.3, 0.4, 0.5).normalized()};
    Eigen::Matrix3d D;
    for (int k = 0; k < 3; ++k) D.row(k) = dirs[k].transpose();
    const Vec3 target = D.inverse() * Vec3(0, 0, lambda * 0.05);
    EXPECT_LT((model.node_displacement(3) - target).norm(), 1e-14);
    // the symmetry node keeps its director in its plane
    const Vec3 nrm = s.symmetry_planes[0].normal.normalized();
    EXPECT_NEAR(model.poses()[1].R.col(2).dot(nrm), 0.0, 1e-13);
    EXPECT_NEAR(model.node_displacement(1).dot(nrm), 0.0, 1e-14);
  }
}

INSTANTIATE_TEST_SUITE_P(FiveAndSixDofs, ShellSupports, ::testing::Bool());

// The reactions balance the applied loads: summed over every node (free nodes carry only the
// residual), f_int sums to zero for a translation-invariant element, so sum(reactions) = -lambda
// sum(f_ext) at any state; and a free node in equilibrium has none.
TEST(ShellSupports, ReactionsBalanceTheLoads) {
  ShellModelSpec s;
  s.mesh = cylinder_patch(4, 3, 2.0);
  s.section = isotropic_section(1.0e4, 0.3, 0.02);
  for (int i = 0; i <= 4; ++i) s.restraints.push_back({i, kClamped});
  const Vec3 P(0.02, -0.01, -0.05);
  s.loads = {{18, P, Vec3::Zero(), false}};
  s.pressures = {{5, 0.3, false}};
  ShellModel m(s);
  std::mt19937 g(1);
  std::uniform_real_distribution<double> u(-0.05, 0.05);
  Eigen::VectorXd d(m.size()), r, load;
  for (int k = 0; k < m.size(); ++k) d[k] = u(g);
  m.update(d);
  const double lambda = 0.8;
  m.evaluate(lambda, r, nullptr, &load);
  Vec3 total = Vec3::Zero(), applied = P;
  for (int I = 0; I < s.mesh.node_count(); ++I) total += m.node_reaction(I);
  // the pressure resultant on quad 5 (dead: reference geometry)
  Eigen::VectorXd r0, load0;
  ShellModelSpec only_pressure = s;
  only_pressure.loads.clear();
  only_pressure.restraints.clear();
  ShellModel p(only_pressure);
  p.evaluate(1.0, r0, nullptr, &load0);
  for (int I = 0; I < s.mesh.node_count(); ++I) applied += load0.segment<3>(p.equation(I, 0));
  EXPECT_LT((total + lambda * applied).norm(), 1e-12 * (1 + r.norm()) + 1e-13);
  EXPECT_GT(applied.norm(), 0.01);
}

// Turning a whole symmetric problem about an axis that is no coordinate axis gives the same
// answer: a quarter of a square plate under a central point load, once with its symmetry planes
// x = 0 and y = 0, once turned by 30 degrees about z (planes of normals (cos, sin, 0) and
// (-sin, cos, 0)). Every displacement, turned back, agrees to round-off.
TEST(ShellSupports, TurnedSymmetryPlanesGiveTheSameSolution) {
  for (bool drilling : {false, true}) {
    const double angle = 30.0 * std::acos(-1.0) / 180.0;
    const Mat3 Q = Eigen::AngleAxisd(angle, Vec3::UnitZ()).toRotationMatrix();
    Vec3 out[2];
    for (int turned = 0; turned < 2; ++turned) {
      const Mat3 T = turned ? Q : Mat3::Identity();
      ShellModelSpec s;
      const int n = 4;
      for (int j = 0; j <= n; ++j)
        for (int i = 0; i <= n; ++i) {
          s.mesh.points.push_back(T * Vec3(0.5 * i / n, 0.5 * j / n, 0.0));
          s.mesh.normals.push_back(Vec3::UnitZ());
        }
      for (int j = 0; j < n; ++j)
        for (int i = 0; i < n; ++i) {
          const int a = j * (n + 1) + i;
          s.mesh.quads.push_back({a, a + 1, a + n + 2, a + n + 1});
        }
      for (const Vec3& nn : s.mesh.normals) s.mesh.frames.push_back(ff::mesh::frame_from_normal(nn, T * Vec3::UnitX()));
      s.mesh.fold.assign(s.mesh.points.size(), 0);
      s.section = isotropic_section(1.0e4, 0.3, 0.01);
      s.options.drilling = drilling;
      for (int k = 0; k <= n; ++k) {
        s.symmetry_planes.push_back({k * (n + 1), T * Vec3::UnitX(), 0});  // x = 0
        s.symmetry_planes.push_back({k, T * Vec3::UnitY(), 1});            // y = 0
        s.directions.push_back({k * (n + 1) + n, Vec3::UnitZ(), false, 0.0, 2});     // x = 0.5: hinged in z
        s.directions.push_back({n * (n + 1) + k, Vec3::UnitZ(), false, 0.0, 2});     // y = 0.5
      }
      s.loads = {{0, Vec3(0, 0, -0.25 * 1e-4), Vec3::Zero(), false}};
      ShellModel m(s);
      // a few Newton iterations at lambda = 1 (nearly linear)
      Eigen::VectorXd r, dx;
      Eigen::SparseMatrix<double> K;
      for (int it = 0; it < 6; ++it) {
        m.evaluate(1.0, r, &K, nullptr);
        Eigen::SparseLU<Eigen::SparseMatrix<double>> lu(K);
        dx = lu.solve(-r);
        m.update(dx);
      }
      m.evaluate(1.0, r, nullptr, nullptr);
      EXPECT_LT(r.norm(), 1e-12);
      out[turned] = T.transpose() * m.node_displacement(2 * (n + 1) + 3);  // an interior node, turned back
    }
    EXPECT_GT(out[0].norm(), 1e-4);
    EXPECT_LT((out[0] - out[1]).norm(), 1e-10 * out[0].norm()) << "drilling " << drilling;
  }
}

// Contradicting or impossible input is refused with the entry it came from.
TEST(ShellSupports, ContradictionsAreRefusedWithTheirSource) {
  ShellModelSpec s = oblique_spec(false);
  s.directions.push_back({2, Vec3(0.6, -0.8, 0.0), false, 0.07, 9});  // same direction, another value
  try {
    ShellModel m(s);
    ADD_FAILURE() << "accepted two values along one direction";
  } catch (const ShellSpecError& e) {
    EXPECT_EQ(e.source(), 9);
    EXPECT_EQ(e.part(), ShellSpecError::Part::restraint);
  }
  s = oblique_spec(false);
  s.symmetry_planes.push_back({5, Vec3(0.0, 0.3, 1.0), 6});  // crosses the director of node 5
  try {
    ShellModel m(s);
    ADD_FAILURE() << "accepted a symmetry plane the director crosses";
  } catch (const ShellSpecError& e) {
    EXPECT_EQ(e.source(), 6);
    EXPECT_NE(std::string(e.what()).find("crosses"), std::string::npos) << e.what();
  }
  s.options.drilling = true;  // 6 DoFs: any plane is exact
  EXPECT_NO_THROW(ShellModel{s});
}

// A director that misses a symmetry plane by less than kSymmetryDirectorSnap (e.g. normals read
// from a file with 6 digits) is moved into it, and the move is reported.
TEST(ShellSupports, NearlyContainedDirectorIsSnappedIntoThePlane) {
  ShellModelSpec s = oblique_spec(false);
  s.symmetry_planes.clear();
  const Vec3 d = s.mesh.normals[1];
  const Vec3 nrm = (d.cross(Vec3::UnitY()) + 3e-5 * d).normalized();
  s.symmetry_planes = {{1, nrm, 0}};
  ShellModel m(s);
  EXPECT_EQ(m.snapped_directors(), 1);
  EXPECT_NEAR(m.largest_director_snap(), 3e-5, 1e-7);
  EXPECT_NEAR(m.spec().mesh.frames[1].col(2).dot(nrm), 0.0, 1e-15);
}

// Issue 30: an element that cannot be formed says whether the thickness is at fault (it forms
// with a thinner section) or the mid-surface itself (degenerate at any thickness), so a scene can
// blame material.thickness or the mesh instead of the thickness every time.
TEST(ShellSupports, ElementFailuresTellThicknessFromMidSurface) {
  ShellModelSpec s;
  s.mesh = cylinder_patch(3, 2, 0.3);  // radius 0.3
  s.section = isotropic_section(1.0e4, 0.3, 2.0);  // 2.0 thick: the inner face passes the axis
  try {
    ShellModel m(s);
    ADD_FAILURE() << "accepted a shell far thicker than its radius";
  } catch (const ShellSpecError& e) {
    EXPECT_EQ(e.part(), ShellSpecError::Part::element) << e.what();
  }
  s.section.thickness = 0.02;
  for (std::size_t i = 0; i < s.mesh.normals.size(); ++i) {  // directors lying in the surface
    s.mesh.normals[i] = Vec3::UnitY();
    s.mesh.frames[i] = ff::mesh::frame_from_normal(Vec3::UnitY(), Vec3::UnitX());
  }
  try {
    ShellModel m(s);
    ADD_FAILURE() << "accepted directors lying in the surface";
  } catch (const ShellSpecError& e) {
    EXPECT_EQ(e.part(), ShellSpecError::Part::mid_surface) << e.what();
  }
}
