// The recovered-resultant error indicator (core/shell/error_indicator.md): the patch test (a
// constant resultant field on a distorted mesh is recovered exactly, (Z5), so eta = 0), the
// rigid-motion invariance of a local-frame quantity, the rate at which it falls for a field
// bilinear elements cannot follow (h^1 in the energy norm, Zienkiewicz-Taylor-Zhu 7th ed.
// section 13.4), and the section compliance (Z1)-(Z2) against the classical laminate stiffness.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "core/lie/se3.h"
#include "core/mesh/generators.h"
#include "core/shell/shell_model.h"

using namespace ff;
using namespace ff::shell;

namespace {

constexpr double kE = 2.0e11, kNu = 0.3, kH = 0.01;

// an a x b plate of n x n quads whose interior nodes are moved by up to 20 % of an element
ShellModelSpec plate(int n, bool distort, double a = 1.0, double b = 1.0) {
  ShellModelSpec s;
  s.mesh = mesh::rectangular_plate(a, b, n, n, "plate");
  if (distort) {
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> u(-0.2, 0.2);
    const double hx = a / n, hy = b / n;
    for (int j = 1; j < n; ++j)
      for (int i = 1; i < n; ++i) {
        Eigen::Vector3d& p = s.mesh.points[j * (n + 1) + i];
        p.x() += u(rng) * hx, p.y() += u(rng) * hy;
      }
  }
  s.section = isotropic_section(kE, kNu, kH);
  return s;
}

// the model's reference poses moved by x -> x + disp(x) with the frames turned by turn(x)
template <class Disp, class Turn>
ShellState deformed(const ShellModel& m, Disp disp, Turn turn) {
  ShellState st = m.state();
  for (std::size_t n = 0; n < st.poses.size(); ++n) {
    const Eigen::Vector3d x = m.spec().mesh.points[n];
    st.poses[n].p = x + disp(x);
    st.poses[n].R = turn(x) * st.poses[n].R;
  }
  return st;
}
Eigen::Matrix3d no_turn(const Eigen::Vector3d&) { return Eigen::Matrix3d::Identity(); }

}  // namespace

TEST(ErrorIndicator, UniformStretchOnADistortedMeshIsRecoveredExactly) {
  ShellModel m(plate(6, true));
  m.set_state(deformed(m, [](const Eigen::Vector3d& x) { return Eigen::Vector3d(1e-3 * x.x(), -4e-4 * x.y(), 0.0); }, no_turn));
  const RecoveredErrorIndicator ind = m.error_indicator();
  ASSERT_GT(ind.energy2, 0.0);
  EXPECT_LT(ind.relative, 1e-7);  // round-off of the fit only
  for (double v : ind.nodal) { EXPECT_LT(v, 1e-6); }
}

TEST(ErrorIndicator, UniformBendingIsRecoveredExactly) {
  // a plate rolled to curvature kappa: M11 constant, which the element's curvature measure takes
  // exactly at its points (measured: eta = 2e-11, round-off against the bending energy)
  ShellModel m(plate(8, false));
  const double kappa = 0.05;
  m.set_state(deformed(
      m,
      [&](const Eigen::Vector3d& x) {
        return Eigen::Vector3d(std::sin(kappa * x.x()) / kappa - x.x(), 0.0, (1 - std::cos(kappa * x.x())) / kappa);
      },
      [&](const Eigen::Vector3d& x) { return Eigen::Matrix3d(Eigen::AngleAxisd(-kappa * x.x(), Eigen::Vector3d::UnitY())); }));
  const RecoveredErrorIndicator ind = m.error_indicator();
  ASSERT_GT(ind.energy2, 0.0);
  EXPECT_LT(ind.relative, 1e-8);
}

// u_x = e x^2 / 2: a membrane strain growing along x, which bilinear elements take as constant per
// element (along x). The recovered field follows it; the error falls with h^1 (Z9's premise).
double linear_strain_error(int n) {
  ShellModel m(plate(n, false));
  m.set_state(deformed(m, [](const Eigen::Vector3d& x) { return Eigen::Vector3d(0.5e-3 * x.x() * x.x(), 0.0, 0.0); }, no_turn));
  return m.error_indicator().relative;
}

TEST(ErrorIndicator, FallsWithTheElementSizeAtTheEnergyNormsRate) {
  const double e4 = linear_strain_error(4), e8 = linear_strain_error(8), e16 = linear_strain_error(16);
  EXPECT_GT(e4, 0.01);  // visibly wrong: constant strain per element against a linear one
  // observed orders log2(e_h / e_h/2): 1 for the energy norm of bilinear elements
  EXPECT_NEAR(std::log2(e4 / e8), 1.0, 0.15);
  EXPECT_NEAR(std::log2(e8 / e16), 1.0, 0.1);
}

TEST(ErrorIndicator, TheElementWhereTheFieldBendsMostCarriesTheLargestShare) {
  // u_x = e x^3 / 3: the strain's gradient grows with x, so the worst element is on the far edge
  ShellModel m(plate(8, false));
  m.set_state(deformed(m, [](const Eigen::Vector3d& x) { return Eigen::Vector3d(1e-3 * x.x() * x.x() * x.x() / 3, 0.0, 0.0); }, no_turn));
  const RecoveredErrorIndicator ind = m.error_indicator();
  ASSERT_GE(ind.worst, 0);
  double xc = 0;
  for (int n : m.elements()[ind.worst].nodes) xc += 0.25 * m.spec().mesh.points[n].x();
  EXPECT_GT(xc, 0.8);
  // the indicator's RMS over the elements is the global relative error, (Z9)
  double ms = 0;
  for (double v : ind.element) ms += v * v;
  EXPECT_NEAR(std::sqrt(ms / ind.element.size()), ind.relative, 1e-12);
}

TEST(ErrorIndicator, ARigidMotionOfTheDeformedShellChangesNothing) {
  ShellModel m(plate(5, true));
  auto disp = [](const Eigen::Vector3d& x) {
    return Eigen::Vector3d(2e-4 * x.x() * x.y(), 1e-4 * x.x() * x.x(), 1e-2 * x.x() * x.y());
  };
  auto turn = [](const Eigen::Vector3d& x) { return Eigen::Matrix3d(Eigen::AngleAxisd(0.02 * x.y(), Eigen::Vector3d::UnitX())); };
  m.set_state(deformed(m, disp, turn));
  const RecoveredErrorIndicator before = m.error_indicator();
  ShellState moved = m.state();
  const Eigen::Matrix3d Q = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  for (NodePose& X : moved.poses) X.p = Q * X.p + Eigen::Vector3d(3, -2, 7), X.R = Q * X.R;
  m.set_state(moved);
  const RecoveredErrorIndicator after = m.error_indicator();
  ASSERT_GT(before.relative, 1e-4);
  EXPECT_NEAR(after.relative, before.relative, 1e-9 * before.relative);
  for (std::size_t k = 0; k < before.element.size(); ++k)
    EXPECT_NEAR(after.element[k], before.element[k], 1e-8 * before.relative);
}

TEST(ErrorIndicator, TheSectionComplianceIsTheLaminateStiffnessInverted) {
  // (Z2) against the closed forms of an isotropic section: A = E h / (1 - nu^2) [1 nu 0; nu 1 0;
  // 0 0 (1 - nu)/2], B = 0, D = A h^2 / 12, A_s = kappa G h (Reddy eqs. 3.3.17, 3.3.25)
  ShellModel m(plate(1, false));
  ResultantSamples rs;
  ElementPoses ref;
  ShellElements::corner_poses(m.elements()[0], m.poses(), ref);
  m.elements()[0].elastic->resultant_samples(ref, ref, rs);
  Eigen::Matrix3d A;
  const double c = kE * kH / (1 - kNu * kNu);
  A << c, c * kNu, 0, c * kNu, c, 0, 0, 0, c * (1 - kNu) / 2;
  const Eigen::Matrix3d D = A * kH * kH / 12;
  const double As = 5.0 / 6.0 * kE / (2 * (1 + kNu)) * kH;
  const Eigen::Matrix<double, 8, 8> S = rs.compliance;
  EXPECT_LT((S.topLeftCorner<3, 3>() - A.inverse()).norm(), 1e-9 * A.inverse().norm());
  EXPECT_LT((S.block<3, 3>(3, 3) - D.inverse()).norm(), 1e-9 * D.inverse().norm());
  EXPECT_LT((S.block<3, 3>(0, 3)).norm(), 1e-12 * D.inverse().norm());
  EXPECT_NEAR(S(6, 6), 1 / As, 1e-9 / As);
  EXPECT_NEAR(S(7, 7), 1 / As, 1e-9 / As);
  // the reference state has no resultants, and the four points cover the element's area
  for (int g = 0; g < 4; ++g) { EXPECT_LT(rs.resultant[g].norm(), 1e-6); }
  EXPECT_NEAR(rs.area[0] + rs.area[1] + rs.area[2] + rs.area[3], 1.0, 1e-12);
}
