// The CB shell element with a laminated section (core/shell/laminate.md): a three-ply [30/-60/0]
// orthotropic section of distinct ply thicknesses on the curved, skewed element of
// test_cb_shell.cpp. The checks every element passes (force = dE by central differences of the
// energy, tangent = dF through H <- H exp(eps e_k), rigid-motion invariance), and the identities
// of the laminate: one isotropic ply is the isotropic element (laminate.md section 3), the
// reference direction only names the angles (section 2), an isotropic section split into plies
// keeps its stiffness (sections 3-4), and the recovered stresses (section 6) vanish in a rigid
// motion and are Qbar E in a uniform in-plane strain.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <numbers>
#include <string>
#include <vector>

#include "core/shell/cb_shell.h"
#include "core/shell/cb_shell_inertia.h"
#include "tests/support/shell_fixtures.h"

using namespace ff::shell;
using namespace ff::shell::testing;

namespace {

constexpr double kPi = std::numbers::pi;

Ply orthotropic_ply(double angle_deg, double thickness) {
  Ply p;
  p.e1 = 140e3, p.e2 = 10e3, p.g12 = 5e3, p.g13 = 5e3, p.g23 = 3.5e3, p.nu12 = 0.3;
  p.thickness = thickness;
  p.angle = angle_deg * kPi / 180.0;
  return p;
}

Ply isotropic_ply(double E, double nu, double thickness, double angle = 0.0) {
  Ply p;
  p.e1 = p.e2 = E;
  p.g12 = p.g13 = p.g23 = E / (2 * (1 + nu));
  p.nu12 = nu;
  p.thickness = thickness;
  p.angle = angle;
  return p;
}

ShellSection laminated(const std::vector<Ply>& plies, const Vec3& reference_direction) {
  ShellSection s;
  s.thickness = 0.0;
  for (const Ply& p : plies) s.thickness += p.thickness;
  s.plies = std::make_shared<const std::vector<Ply>>(plies);
  s.reference_direction = reference_direction;
  // not used with plies: far off, so that a kernel that read them instead would show
  s.youngs_modulus = 1.0, s.poisson_ratio = 0.0;
  return s;
}

// [30/-60/0] from the bottom, thicknesses 0.02, 0.01, 0.03 (h = 0.06 on the element of size ~0.5
// and radius 2 of samples::curved); the reference direction off every element axis
ShellSection three_ply() {
  return laminated({orthotropic_ply(30, 0.02), orthotropic_ply(-60, 0.01), orthotropic_ply(0, 0.03)}, Vec3(0.8, 0.6, 0.1));
}

struct Case {
  bool hr, ans, drilling;
};
ShellOptions options(const Case& c) {
  ShellOptions o;
  o.hr = c.hr, o.ans = c.ans, o.drilling = c.drilling;
  o.drilling_factor = 0.1;
  return o;
}
std::string name(const Case& c) {
  return std::string(c.hr ? "hr" : "nohr") + (c.ans ? "_ans" : "_noans") + (c.drilling ? "_6dof" : "_5dof");
}

double max_abs(const Vec24& v) { return v.cwiseAbs().maxCoeff(); }
double max_abs(const Mat24& m) { return m.cwiseAbs().maxCoeff(); }

// the largest magnitude over every number an ElementStress reports (its plies included)
double largest_stress(const ElementStress& s) {
  double m = std::max({s.N.cwiseAbs().maxCoeff(), s.M.cwiseAbs().maxCoeff(), s.Q.cwiseAbs().maxCoeff()});
  for (const Vec5& v : s.surface) m = std::max(m, v.cwiseAbs().maxCoeff());
  for (int k = 0; k < s.plies; ++k)
    for (const Vec5& v : s.ply[k]) m = std::max(m, v.cwiseAbs().maxCoeff());
  return m;
}

}  // namespace

class CbShellLaminate : public ::testing::TestWithParam<Case> {};

TEST_P(CbShellLaminate, ForceIsEnergyGradientAndTangentIsForceDerivative) {
  const Case c = GetParam();
  const ElementPoses ref = curved();
  const CbShellElement el(ref, three_ply(), options(c));
  for (unsigned seed : {1u, 2u}) {
    const ElementPoses cur = deformed(ref, seed);
    Vec24 F;
    Mat24 K;
    el.evaluate(cur, F, &K);
    const double h = 1e-6;
    Vec24 Ffd;
    Mat24 Kfd;
    central_differences(el, cur, h, Ffd, Kfd);
    // central differences, h = 1e-6: truncation ~h^2 |third derivative|, round-off ~eps |F| / h
    EXPECT_LT(max_abs(Vec24(F - Ffd)), 1e-6 * max_abs(F)) << name(c) << " seed " << seed;
    EXPECT_LT(max_abs(Mat24(K - Kfd)), 1e-6 * max_abs(K)) << name(c) << " seed " << seed;
  }
}

TEST_P(CbShellLaminate, RigidMotionInvariance) {
  const Case c = GetParam();
  const ElementPoses ref = curved();
  const CbShellElement el(ref, three_ply(), options(c));
  Vec24 F0;
  el.evaluate(moved(ref, rot(Vec3(2.1, 0.4, -1.3)), Vec3(5, -3, 1)), F0, nullptr);
  Vec24 Fd;
  el.evaluate(deformed(ref, 7), Fd, nullptr);
  EXPECT_LT(max_abs(F0), 1e-10 * max_abs(Fd)) << name(c);  // a rigid motion of the reference: no force
  // a superposed rigid motion leaves force and tangent unchanged (local frames)
  const ElementPoses cur = deformed(ref, 7);
  Vec24 F1, F2;
  Mat24 K1, K2;
  el.evaluate(cur, F1, &K1);
  el.evaluate(moved(cur, rot(Vec3(-0.7, 2.9, 0.2)), Vec3(-1, 4, 2)), F2, &K2);
  EXPECT_LT(max_abs(Vec24(F1 - F2)), 1e-10 * max_abs(F1)) << name(c);
  EXPECT_LT(max_abs(Mat24(K1 - K2)), 1e-10 * max_abs(K1)) << name(c);
}

// One ply of an isotropic material over the whole thickness is the isotropic element: its two
// Gauss points are today's two, its Pian-Sumihara field today's ((L7)-(L8) with one ply), and for
// an isotropic ply Qbar = Q, Qbar_s = G I at any angle ((L5)); so force and tangent agree to
// round-off, whatever the ply angle and reference direction.
TEST_P(CbShellLaminate, OneIsotropicPlyIsTheIsotropicElement) {
  const Case c = GetParam();
  const double E = 2.0e5, nu = 0.3, h = 0.05;
  const ElementPoses ref = curved();
  const CbShellElement iso(ref, isotropic_section(E, nu, h), options(c));
  for (const auto& [angle, direction] : {std::pair{0.0, Vec3::Zero().eval()}, std::pair{0.7, Vec3(0.3, 1.0, -0.2)}}) {
    // the section's own isotropic constants are far off (laminated()): the plies alone must give
    // the element, its drilling penalty gamma = c G h0 (cb_shell.md (13)) included
    const CbShellElement lam(ref, laminated({isotropic_ply(E, nu, h, angle)}, direction), options(c));
    for (unsigned seed : {3u, 4u}) {
      const ElementPoses cur = deformed(ref, seed);
      Vec24 Fi, Fl;
      Mat24 Ki, Kl;
      iso.evaluate(cur, Fi, &Ki);
      lam.evaluate(cur, Fl, &Kl);
      // laminate.md section 3: with angle 0 (and the element's own xi direction) the very same
      // operations, bit for bit; turned, round-off of the turned stiffness
      if (angle == 0.0) { EXPECT_TRUE(Fl == Fi && Kl == Ki) << name(c) << ": not bitwise the isotropic element"; }
      EXPECT_LE(max_abs(Vec24(Fl - Fi)), 1e-12 * max_abs(Fi)) << name(c) << " angle " << angle;
      EXPECT_LE(max_abs(Mat24(Kl - Ki)), 1e-12 * max_abs(Ki)) << name(c) << " angle " << angle;
      EXPECT_NEAR(lam.energy(cur), iso.energy(cur), 1e-12 * iso.energy(cur)) << name(c);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Effects, CbShellLaminate,
                         ::testing::Values(Case{false, false, false}, Case{true, false, false}, Case{false, true, false},
                                           Case{true, true, false}, Case{true, true, true}),
                         [](const auto& info) { return name(info.param); });

// The reference direction only names the angles (laminate.md section 2: the fibre lies at
// psi = phi + theta_k): turning it by alpha about the normal and every ply by -alpha leaves every
// fibre where it was, so force and tangent are the same to round-off, and so are the ply stresses
// in fibre axes. (On the flat element the turned direction's projection turns by exactly alpha.)
TEST(CbShellLaminate, TurningTheReferenceDirectionAndThePliesBackChangesNothing) {
  const ElementPoses ref = flat_distorted();
  const Vec3 r(1.0, 0.2, 0.0);
  const std::vector<Ply> plies{orthotropic_ply(30, 0.02), orthotropic_ply(-60, 0.01), orthotropic_ply(0, 0.03)};
  for (bool hr : {false, true}) {
    ShellOptions o;
    o.hr = hr;
    const CbShellElement base(ref, laminated(plies, r), o);
    for (double alpha : {0.4, -1.9}) {
      std::vector<Ply> turned = plies;
      for (Ply& p : turned) p.angle -= alpha;
      const CbShellElement other(ref, laminated(turned, rot(Vec3(0, 0, alpha)) * r), o);
      const ElementPoses cur = deformed(ref, 5);
      Vec24 F1, F2;
      Mat24 K1, K2;
      base.evaluate(cur, F1, &K1);
      other.evaluate(cur, F2, &K2);
      EXPECT_LT(max_abs(Vec24(F1 - F2)), 1e-10 * max_abs(F1)) << "alpha " << alpha << (hr ? " hr" : "");
      EXPECT_LT(max_abs(Mat24(K1 - K2)), 1e-10 * max_abs(K1)) << "alpha " << alpha << (hr ? " hr" : "");
      ElementStress s1, s2;
      base.stresses(cur, s1);
      other.stresses(cur, s2);
      ASSERT_EQ(s1.plies, 3);
      ASSERT_EQ(s2.plies, 3);
      const double scale = largest_stress(s1);
      EXPECT_GT(scale, 0.0);
      for (int k = 0; k < 3; ++k)
        for (int w = 0; w < 3; ++w)
          EXPECT_LT((s1.ply[k][w] - s2.ply[k][w]).cwiseAbs().maxCoeff(), 1e-10 * scale) << "ply " << k << " station " << w;
    }
  }
}

namespace {
// Quadratic form u^T K0 u of the tangent at the (stress-free) reference: the element's linear
// stiffness in the state u, given as world translations and rotation vectors per node.
double stiffness_in(const CbShellElement& el, const ElementPoses& ref, const std::array<Vec3, 4>& u,
                    const std::array<Vec3, 4>& theta) {
  Vec24 F;
  Mat24 K;
  el.evaluate(ref, F, &K);
  Vec24 v;
  for (int I = 0; I < 4; ++I) v.segment<3>(6 * I) = ref[I].R.transpose() * u[I], v.segment<3>(6 * I + 3) = ref[I].R.transpose() * theta[I];
  return v.dot(K * v);
}
// a membrane state: for the flat element an affine in-plane stretch and shear; for the curved one
// (axis y through the origin) the axial stretch with the radial expansion, uniform membrane strains
std::array<Vec3, 4> membrane_displacements(const ElementPoses& ref, bool curved_patch) {
  std::array<Vec3, 4> u;
  for (int I = 0; I < 4; ++I) {
    const Vec3& X = ref[I].p;
    u[I] = curved_patch ? Vec3(1e-3 * X.x(), -0.6e-3 * X.y(), 1e-3 * X.z()) : Vec3(1e-3 * X.x() + 0.4e-3 * X.y(), -0.6e-3 * X.y(), 0.0);
  }
  return u;
}
// a bending state: w = (kx x^2 + ky y^2)/2 + kxy x y along z with the rotations of the Kirchhoff
// normal, theta = (w_y, -w_x, 0): pure bending on the flat element, bending-dominated on the
// shallow curved one
void bending_state(const ElementPoses& ref, std::array<Vec3, 4>& u, std::array<Vec3, 4>& theta) {
  const double kx = 1e-3, ky = -0.4e-3, kxy = 0.3e-3;
  for (int I = 0; I < 4; ++I) {
    const double x = ref[I].p.x(), y = ref[I].p.y();
    u[I] = Vec3(0, 0, 0.5 * (kx * x * x + ky * y * y) + kxy * x * y);
    theta[I] = Vec3(ky * y + kxy * x, -(kx * x + kxy * y), 0);
  }
}
}  // namespace

// An isotropic material split into three equal plies against one layer (hr on and off). The
// continuum stiffness is the same; what differs is the discretization through the thickness:
// - flat element: the lamina-frame strains are linear in zeta and the volume measure constant,
//   so both rules (2 Gauss points per ply, 2 over the section) integrate the quadratic energy
//   exactly, and with hr the single-layer field [P, zeta P] lies in the per-ply fields
//   [P, zeta_k P] (L7) while the strain is a tensor product of the in-plane shapes with
//   {1, zeta}, whose projection the richer field does not change: equal to round-off.
// - curved element (radius R = 2, h = 0.05, a = h/2R): the lamina frame and the volume measure
//   vary with zeta through 1 + a zeta, so the energy density is no longer a cubic in zeta. In
//   bending (density ~ zeta^2 (1 + a zeta)^-k, k ~ 3) the zeta^4 term has a relative weight
//   ~ k(k+1)/2 a^2, which the single layer's 2 points miss by 8/45 of its integral against the
//   2/3 of zeta^2, about 0.4 (h/R)^2; the three plies' rule misses far less. With hr the per-ply
//   field also follows the strain's departure from linear in zeta (relative <= 2a = h/R), which
//   changes the condensed energy by at most its square, (h/R)^2. Bending: tolerance (h/R)^2 =
//   6.3e-4. In membrane the departure enters only at a^2 (density ~ (1 + a zeta)^-k without the
//   zeta^2), so both effects are of order a^4: tolerance (h/R)^4 = 3.9e-7.
TEST(CbShellLaminate, IsotropicSectionSplitIntoThreePliesKeepsItsStiffness) {
  const double E = 2.0e5, nu = 0.3, h = 0.05, R = 2.0;
  for (bool curved_patch : {false, true}) {
    const ElementPoses ref = curved_patch ? curved() : flat_distorted();
    const double tol_bending = curved_patch ? std::pow(h / R, 2) : 1e-11, tol_membrane = curved_patch ? std::pow(h / R, 4) : 1e-11;
    for (bool hr : {false, true}) {
      ShellOptions o;
      o.hr = hr;
      const CbShellElement one(ref, isotropic_section(E, nu, h), o);
      const CbShellElement three(ref, laminated({isotropic_ply(E, nu, h / 3), isotropic_ply(E, nu, h / 3), isotropic_ply(E, nu, h / 3)}, Vec3::Zero()), o);
      const std::array<Vec3, 4> zero{Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
      const std::array<Vec3, 4> um = membrane_displacements(ref, curved_patch);
      const double m1 = stiffness_in(one, ref, um, zero), m3 = stiffness_in(three, ref, um, zero);
      std::array<Vec3, 4> ub, tb;
      bending_state(ref, ub, tb);
      const double b1 = stiffness_in(one, ref, ub, tb), b3 = stiffness_in(three, ref, ub, tb);
      const std::string what = std::string(curved_patch ? "curved" : "flat") + (hr ? " hr" : " no hr");
      std::printf("%s: membrane %.6e vs %.6e (%.2e), bending %.6e vs %.6e (%.2e)\n", what.c_str(), m1, m3, m3 / m1 - 1, b1,
                  b3, b3 / b1 - 1);
      EXPECT_GT(m1, 0.0);
      EXPECT_GT(b1, 0.0);
      EXPECT_NEAR(m3 / m1, 1.0, tol_membrane) << what;
      EXPECT_NEAR(b3 / b1, 1.0, tol_bending) << what;
    }
  }
}

// A rigid motion strains nothing: every stress, resultant and ply stress is zero (to round-off of
// the strains, ~1e-15, times the stiffness); a deformed state is not (the check can fail).
TEST(CbShellLaminate, StressesOfARigidMotionAreZero) {
  const ElementPoses ref = curved();
  for (bool hr : {false, true}) {
    ShellOptions o;
    o.hr = hr;
    const CbShellElement el(ref, three_ply(), o);
    ElementStress s;
    el.stresses(moved(ref, rot(Vec3(2.1, 0.4, -1.3)), Vec3(5, -3, 1)), s);
    EXPECT_EQ(s.plies, 3);
    EXPECT_LT(largest_stress(s), 1e-10 * 140e3) << (hr ? "hr" : "no hr");
    el.stresses(deformed(ref, 2, 0.01), s);
    EXPECT_GT(largest_stress(s), 1e-4 * 140e3) << (hr ? "hr" : "no hr");
  }
}

// A uniform in-plane Green-Lagrange strain E (an affine stretch of the flat element, directors
// unchanged) is exact for the element with and without hr (test_cb_shell.cpp's affine state), so
// St. Venant-Kirchhoff gives, at every station of ply k, S = Qbar_k E in section axes and
// Q T E in fibre axes (laminate.md (L1), (L3), (L5), section 6, written here from Jones's explicit
// formulas, ch. 2), N = sum Qbar_k h_k E, M = sum Qbar_k zbar_k h_k E, Q = 0; and each ply's
// Tsai-Wu index (L12) of that stress (Tsai & Wu 1971, F12 = -sqrt(F11 F22)/2 of Tsai & Hahn), NaN
// for a ply without strengths.
TEST(CbShellLaminate, UniformMembraneStrainGivesEachPlyItsQbarE) {
  const ElementPoses ref = flat_distorted();
  const Vec3 r(1.0, 0.2, 0.0);
  std::vector<Ply> plies{orthotropic_ply(30, 0.02), orthotropic_ply(-60, 0.01), orthotropic_ply(0, 0.03)};
  const std::array<double, 5> strength{1500, 1200, 50, 250, 70};  // Xt Xc Yt Yc S12, carbon/epoxy-like (MPa)
  plies[0].strength = strength, plies[2].strength = strength;     // ply 1 has none
  Eigen::Matrix3d Fd = Eigen::Matrix3d::Identity();
  Fd.topLeftCorner<2, 2>() << 1.003, 0.002, -0.001, 0.998;
  ElementPoses cur = ref;
  for (auto& n : cur) n.p = Fd * n.p;
  const Eigen::Matrix3d Eg = 0.5 * (Fd.transpose() * Fd - Eigen::Matrix3d::Identity());
  // section axes: x1 = r projected (the plane is z = 0), x2 = z x x1
  const Vec3 x1 = r.normalized(), x2 = Vec3::UnitZ().cross(x1);
  const Eigen::Vector3d e(x1.dot(Eg * x1), x2.dot(Eg * x2), 2 * x1.dot(Eg * x2));  // engineering shear
  for (bool hr : {false, true}) {
    ShellOptions o;
    o.hr = hr;
    const CbShellElement el(ref, laminated(plies, r), o);
    ElementStress s;
    el.stresses(cur, s);
    ASSERT_EQ(s.plies, 3);
    double z = -0.03;
    Eigen::Vector3d N = Eigen::Vector3d::Zero(), M = N;
    double scale = 0.0;
    for (int k = 0; k < 3; ++k) {
      const Ply& p = plies[k];
      const double c = std::cos(p.angle), sn = std::sin(p.angle), c2 = c * c, s2 = sn * sn;
      const double d = 1 - p.nu12 * p.nu12 * p.e2 / p.e1;
      const double Q11 = p.e1 / d, Q22 = p.e2 / d, Q12 = p.nu12 * p.e2 / d, Q66 = p.g12;
      Eigen::Matrix3d Qb;  // Jones (2.85)
      Qb(0, 0) = Q11 * c2 * c2 + 2 * (Q12 + 2 * Q66) * s2 * c2 + Q22 * s2 * s2;
      Qb(0, 1) = Qb(1, 0) = (Q11 + Q22 - 4 * Q66) * s2 * c2 + Q12 * (s2 * s2 + c2 * c2);
      Qb(1, 1) = Q11 * s2 * s2 + 2 * (Q12 + 2 * Q66) * s2 * c2 + Q22 * c2 * c2;
      Qb(0, 2) = Qb(2, 0) = (Q11 - Q12 - 2 * Q66) * sn * c2 * c + (Q12 - Q22 + 2 * Q66) * s2 * sn * c;
      Qb(1, 2) = Qb(2, 1) = (Q11 - Q12 - 2 * Q66) * s2 * sn * c + (Q12 - Q22 + 2 * Q66) * sn * c2 * c;
      Qb(2, 2) = (Q11 + Q22 - 2 * Q12 - 2 * Q66) * s2 * c2 + Q66 * (s2 * s2 + c2 * c2);
      const Eigen::Vector3d S = Qb * e;
      // fibre axes from the stress transformation (Jones (2.79)), independent of the strain route
      const Eigen::Vector3d S1(c2 * S[0] + s2 * S[1] + 2 * c * sn * S[2], s2 * S[0] + c2 * S[1] - 2 * c * sn * S[2],
                               -c * sn * S[0] + c * sn * S[1] + (c2 - s2) * S[2]);
      scale = std::max(scale, S.cwiseAbs().maxCoeff());
      for (int w = 0; w < 3; ++w) {
        EXPECT_LT((s.ply[k][w].head<3>() - S1).cwiseAbs().maxCoeff(), 1e-9 * S.norm()) << "ply " << k << " station " << w << (hr ? " hr" : "");
        EXPECT_LT(s.ply[k][w].tail<2>().cwiseAbs().maxCoeff(), 1e-9 * S.norm()) << "ply " << k;
      }
      const double Xt = strength[0], Xc = strength[1], Yt = strength[2], Yc = strength[3], S12 = strength[4];
      const double F11 = 1 / (Xt * Xc), F22 = 1 / (Yt * Yc);
      const double index = (1 / Xt - 1 / Xc) * S1[0] + (1 / Yt - 1 / Yc) * S1[1] + F11 * S1[0] * S1[0] + F22 * S1[1] * S1[1] +
                           S1[2] * S1[2] / (S12 * S12) - std::sqrt(F11 * F22) * S1[0] * S1[1];
      if (k == 1) { EXPECT_TRUE(std::isnan(s.tsai_wu[k])) << "a ply without strengths has no index"; }
      else EXPECT_NEAR(s.tsai_wu[k], index, 1e-9 * std::abs(index)) << "ply " << k << (hr ? " hr" : "");
      if (k == 0) { EXPECT_LT((s.surface[0].head<3>() - S).cwiseAbs().maxCoeff(), 1e-9 * S.norm()) << "bottom"; }
      if (k == 2) { EXPECT_LT((s.surface[2].head<3>() - S).cwiseAbs().maxCoeff(), 1e-9 * S.norm()) << "top"; }
      N += S * p.thickness;
      M += S * (z + 0.5 * p.thickness) * p.thickness;
      z += p.thickness;
    }
    EXPECT_LT((s.N - N).cwiseAbs().maxCoeff(), 1e-9 * scale * 0.06) << (hr ? "hr" : "no hr");
    EXPECT_LT((s.M - M).cwiseAbs().maxCoeff(), 1e-9 * scale * 0.06 * 0.03) << (hr ? "hr" : "no hr");
    EXPECT_LT(s.Q.cwiseAbs().maxCoeff(), 1e-9 * scale * 0.06) << (hr ? "hr" : "no hr");
  }
}

// Inertia through the stack (laminate.md (L10)): a rigid rotation omega about an axis along x at
// height z0 above the flat element's mid-plane moves every point of the solid exactly as the
// element interpolates it, so the kinetic energy is exact:
//   T = omega^2 / 2 [ m (I_x + z0^2 A) - 2 z0 S A + J A ],
// m = sum rho_k h_k, S = sum rho_k h_k zbar_k (first moment), J = sum rho_k (z_{k+1}^3 - z_k^3)/3
// (rotary), A and I_x = integral of y^2 dA of the quadrilateral (shoelace formulas). The densities
// differ so that S != 0: a ply order or a sign of z gone wrong shows in the -2 z0 S A term.
TEST(CbShellLaminate, InertiaOfTheStackGivesTheKineticEnergyOfARigidRotation) {
  const ElementPoses ref = flat_distorted();
  std::vector<Ply> plies{orthotropic_ply(30, 0.02), orthotropic_ply(-60, 0.01), orthotropic_ply(0, 0.03)};
  plies[0].density = 3.0e-9, plies[1].density = 1.0e-9, plies[2].density = 0.8e-9;
  const ShellSection sec = laminated(plies, Vec3(1, 0.2, 0));
  const CbShellInertia inertia(ref, sec, 7.8e-9);  // the argument is the isotropic density: unused with plies
  double m = 0, S = 0, J = 0, z = -0.5 * sec.thickness;
  for (const Ply& p : plies) {
    m += p.density * p.thickness;
    S += p.density * p.thickness * (z + 0.5 * p.thickness);
    J += p.density * (std::pow(z + p.thickness, 3) - std::pow(z, 3)) / 3;
    z += p.thickness;
  }
  double A = 0, Ix = 0;
  for (int i = 0; i < 4; ++i) {
    const Vec3 &a = ref[i].p, &b = ref[(i + 1) % 4].p;
    const double cross = a.x() * b.y() - b.x() * a.y();
    A += 0.5 * cross;
    Ix += cross * (a.y() * a.y() + a.y() * b.y() + b.y() * b.y()) / 12;
  }
  EXPECT_NEAR(inertia.mass(), m * A, 1e-12 * m * A);
  const double omega = 3.0, z0 = 0.3;
  const Vec3 w(omega, 0, 0), c(0, 0, z0);
  ElementRates v;
  for (int I = 0; I < 4; ++I) {
    v[I].head<3>() = ref[I].R.transpose() * w.cross(ref[I].p - c);
    v[I].tail<3>() = ref[I].R.transpose() * w;
  }
  const double T = 0.5 * omega * omega * (m * (Ix + z0 * z0 * A) - 2 * z0 * S * A + J * A);
  EXPECT_NEAR(inertia.kinetic_energy(ref, v), T, 1e-12 * T);
  // the first-moment and rotary terms are far above the tolerance: the check sees them
  EXPECT_GT(std::abs(2 * z0 * S * A), 1e-3 * T);
  EXPECT_GT(J * A, 1e-4 * T);
}

// A reference direction with no projection on the element's tangent plane names no fibre
// direction (laminate.md section 2: refused when |r - (r.t3) t3| < 1e-3 |r|); one just outside
// that cone is accepted.
TEST(CbShellLaminate, ReferenceDirectionAlongTheNormalIsRefused) {
  const ElementPoses ref = flat_distorted();  // normal +z
  const std::vector<Ply> plies{orthotropic_ply(0, 0.02), orthotropic_ply(90, 0.02)};
  EXPECT_THROW(CbShellElement(ref, laminated(plies, Vec3(0, 0, -2)), ShellOptions{}), std::invalid_argument);
  EXPECT_THROW(CbShellElement(ref, laminated(plies, Vec3(0.5e-3, 0, 1)), ShellOptions{}), std::invalid_argument);
  EXPECT_NO_THROW(CbShellElement(ref, laminated(plies, Vec3(2e-3, 0, 1)), ShellOptions{}));
}
