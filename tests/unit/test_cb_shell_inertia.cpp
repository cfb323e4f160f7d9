// Inertia and gravity of the CB shell (core/shell/cb_shell_dynamics.md): the consistent mass
// integrates to rho h A, kinetic energy is ½ VᵀMV, the Jacobians (D5)-(D8) match central
// differences of the force, forces and Jacobians are invariant under superposed rigid motions.
#include <gtest/gtest.h>

#include "core/shell/cb_shell_inertia.h"
#include "tests/support/shell_fixtures.h"

using namespace ff::shell;
using namespace ff::shell::testing;

namespace {

constexpr double kH = 0.05, kRho = 7.8e3;

ElementRates random_rates(unsigned seed, double scale) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  ElementRates r;
  for (auto& v : r)
    for (int k = 0; k < 6; ++k) v[k] = scale * u(g);
  return r;
}

double area(const ElementPoses& p) {  // 2x2 Gauss area of the bilinear mid-surface
  const double xi[4] = {-1, 1, 1, -1}, eta[4] = {-1, -1, 1, 1}, gp = 1.0 / std::sqrt(3.0);
  double a = 0;
  for (double x : {-gp, gp})
    for (double y : {-gp, gp}) {
      Vec3 gx = Vec3::Zero(), gy = Vec3::Zero();
      for (int I = 0; I < 4; ++I) {
        gx += 0.25 * xi[I] * (1 + eta[I] * y) * p[I].p;
        gy += 0.25 * eta[I] * (1 + xi[I] * x) * p[I].p;
      }
      a += gx.cross(gy).norm();
    }
  return a;
}

class InertiaOn : public ::testing::TestWithParam<bool> {  // param: curved reference
 protected:
  ElementPoses ref() const { return GetParam() ? curved() : flat_distorted(); }
};

// Volume of the element's trilinear solid (slaves of (S1)) by 5x5x5 Gauss points, independent of
// the 3x3x3 rule of (D3): on a curved element the interpolated director is shorter than 1, so the
// solid's volume is below h A (here by about cos(0.24) for directors 0.47 rad apart).
double solid_volume(const ElementPoses& p) {
  const double xi[4] = {-1, 1, 1, -1}, eta[4] = {-1, -1, 1, 1};
  const double gp[5] = {-0.9061798459386640, -0.5384693101056831, 0.0, 0.5384693101056831, 0.9061798459386640};
  const double gw[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889, 0.4786286704993665,
                        0.2369268850561891};
  double v = 0;
  for (int i = 0; i < 5; ++i)
    for (int j = 0; j < 5; ++j)
      for (int k = 0; k < 5; ++k) {
        Vec3 G[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
        for (int I = 0; I < 4; ++I)
          for (double s : {1.0, -1.0}) {
            const Vec3 X = p[I].p + s * 0.5 * kH * p[I].R.col(2);
            const double nz = 0.5 * (1 + s * gp[k]);
            G[0] += 0.25 * xi[I] * (1 + eta[I] * gp[j]) * nz * X;
            G[1] += 0.25 * eta[I] * (1 + xi[I] * gp[i]) * nz * X;
            G[2] += 0.25 * (1 + xi[I] * gp[i]) * (1 + eta[I] * gp[j]) * 0.5 * s * X;
          }
        v += gw[i] * gw[j] * gw[k] * G[0].dot(G[1].cross(G[2]));
      }
  return v;
}

TEST_P(InertiaOn, MassIntegratesToDensityTimesVolume) {
  const ElementPoses r = ref();
  CbShellInertia in(r, kH, kRho);
  EXPECT_NEAR(in.mass(), kRho * solid_volume(r), 1e-12 * in.mass());
  if (!GetParam()) { EXPECT_NEAR(in.mass(), kRho * kH * area(r), 1e-12 * in.mass()); }  // flat: V = h A
  EXPECT_LT((in.slave_mass() - in.slave_mass().transpose()).norm(), 1e-12 * in.slave_mass().norm());
}

TEST_P(InertiaOn, KineticEnergyIsHalfVTMV) {
  const ElementPoses r = ref(), cur = deformed(r, 3);
  CbShellInertia in(r, kH, kRho);
  const ElementRates v = random_rates(5, 1.0), zero{};
  Vec24 f;
  Mat24 M;
  in.evaluate(cur, v, zero, f, {&M, nullptr, nullptr});
  Vec24 V;
  for (int I = 0; I < 4; ++I) V.segment<6>(6 * I) = v[I];
  EXPECT_NEAR(in.kinetic_energy(cur, v), 0.5 * V.dot(M * V), 1e-12 * in.kinetic_energy(cur, v));
  EXPECT_LT((M - M.transpose()).norm(), 1e-12 * M.norm());
  // positive definite on the 5 DoFs per node that move the slaves
  Eigen::SelfAdjointEigenSolver<Mat24> es(M);
  int positive = 0;
  for (int k = 0; k < 24; ++k) positive += es.eigenvalues()[k] > 1e-10 * es.eigenvalues().maxCoeff();
  EXPECT_EQ(positive, 20);
}

// M = dF/dV̇ (D5), C = dF/dV (D6), K = dF/dq (D7) by central differences at a large-rotation state
TEST_P(InertiaOn, JacobiansMatchCentralDifferences) {
  const ElementPoses r = ref(), cur = deformed(r, 11, 0.1);
  CbShellInertia in(r, kH, kRho);
  const ElementRates v = random_rates(7, 2.0), a = random_rates(9, 5.0);
  Vec24 f;
  Mat24 M, C, K;
  in.evaluate(cur, v, a, f, {&M, &C, &K});
  const double eps = 1e-6;
  Mat24 Mfd, Cfd, Kfd;
  for (int k = 0; k < 24; ++k) {
    Vec24 fp, fm;
    ElementRates ap = a, am = a, vp = v, vm = v;
    ap[k / 6][k % 6] += eps, am[k / 6][k % 6] -= eps;
    in.evaluate(cur, v, ap, fp), in.evaluate(cur, v, am, fm);
    Mfd.col(k) = (fp - fm) / (2 * eps);
    vp[k / 6][k % 6] += eps, vm[k / 6][k % 6] -= eps;
    in.evaluate(cur, vp, a, fp), in.evaluate(cur, vm, a, fm);
    Cfd.col(k) = (fp - fm) / (2 * eps);
    in.evaluate(perturb(cur, k, eps), v, a, fp), in.evaluate(perturb(cur, k, -eps), v, a, fm);
    Kfd.col(k) = (fp - fm) / (2 * eps);
  }
  EXPECT_LT((M - Mfd).norm(), 1e-7 * M.norm());
  EXPECT_LT((C - Cfd).norm(), 1e-7 * C.norm());
  EXPECT_LT((K - Kfd).norm(), 1e-6 * K.norm());
  EXPECT_GT(C.norm(), 1e-3 * M.norm());  // the check is not vacuous
  EXPECT_GT(K.norm(), 1e-3 * M.norm());
}

TEST_P(InertiaOn, GravityDerivativeMatchesCentralDifferences) {
  const ElementPoses r = ref(), cur = deformed(r, 13, 0.1);
  CbShellInertia in(r, kH, kRho);
  const Vec3 g(0.3, -1.0, -9.81);
  Vec24 f;
  Mat24 K, Kfd;
  in.gravity(cur, g, f, &K);
  for (int k = 0; k < 24; ++k) {
    Vec24 fp, fm;
    in.gravity(perturb(cur, k, 1e-6), g, fp, nullptr), in.gravity(perturb(cur, k, -1e-6), g, fm, nullptr);
    Kfd.col(k) = (fp - fm) / 2e-6;
  }
  EXPECT_LT((K - Kfd).norm(), 1e-7 * K.norm());
  // total generalized force on translations is the weight, in local components per node
  Vec3 total = Vec3::Zero();
  for (int I = 0; I < 4; ++I) total += cur[I].R * f.segment<3>(6 * I);
  EXPECT_LT((total - in.mass() * g).norm(), 1e-12 * in.mass() * g.norm());
  // gravity force is minus the derivative of the potential along local increments
  for (int k = 0; k < 24; ++k) {
    const double dU = (in.gravity_potential(perturb(cur, k, 1e-6), g) - in.gravity_potential(perturb(cur, k, -1e-6), g)) / 2e-6;
    EXPECT_NEAR(-dU, f[k], 1e-6 * in.mass() * g.norm()) << "dof " << k;
  }
}

// The per-node-pair Jacobians (what evaluate() uses) against the plain sum over the 64 slave
// pairs (set_plain_jacobians, the oracle): the same matrices to round-off.
TEST_P(InertiaOn, PairSumJacobiansEqualThePlainSlaveSum) {
  const ElementPoses r = ref(), cur = deformed(r, 29, 0.1);
  CbShellInertia fast(r, kH, kRho), plain(r, kH, kRho);
  plain.set_plain_jacobians(true);
  const ElementRates v = random_rates(31, 2.0), a = random_rates(33, 5.0);
  const Vec3 g(0.3, -1.0, -9.81);
  Vec24 f1, f2;
  Mat24 M1, C1, K1, M2, C2, K2;
  fast.evaluate(cur, v, a, f1, {&M1, &C1, &K1}, &g);
  plain.evaluate(cur, v, a, f2, {&M2, &C2, &K2}, &g);
  EXPECT_EQ(f1, f2);  // the force path is shared
  EXPECT_LT((M1 - M2).norm(), 1e-14 * M2.norm());
  EXPECT_LT((C1 - C2).norm(), 1e-14 * C2.norm());
  EXPECT_LT((K1 - K2).norm(), 1e-14 * K2.norm());
  EXPECT_GT(C2.norm(), 1e-3 * M2.norm());  // not vacuous
}

// The one-pass inertia-with-gravity (what the multibody model calls) against the two separate
// kernels: F = F_inertia − F^g and ∂F/∂q = K_inertia − ∂F^g/∂q, the rate Jacobians unchanged,
// to round-off; and its stiffness against central differences of its own force.
TEST_P(InertiaOn, OnePassGravityEqualsInertiaMinusGravity) {
  const ElementPoses r = ref(), cur = deformed(r, 17, 0.1);
  CbShellInertia in(r, kH, kRho);
  const ElementRates v = random_rates(21, 2.0), a = random_rates(23, 5.0);
  const Vec3 g(0.3, -1.0, -9.81);
  Vec24 f_in, f_g, f_one;
  Mat24 M, C, K, Kg, M1, C1, K1;
  in.evaluate(cur, v, a, f_in, {&M, &C, &K});
  in.gravity(cur, g, f_g, &Kg);
  in.evaluate(cur, v, a, f_one, {&M1, &C1, &K1}, &g);
  EXPECT_LT((f_one - (f_in - f_g)).norm(), 1e-13 * (f_in.norm() + f_g.norm()));
  EXPECT_LT((K1 - (K - Kg)).norm(), 1e-13 * (K.norm() + Kg.norm()));
  EXPECT_EQ(M1, M);
  EXPECT_EQ(C1, C);
  EXPECT_GT(f_g.norm(), 1e-2 * f_in.norm());  // gravity is not negligible here: the check bites
  Mat24 Kfd;
  for (int k = 0; k < 24; ++k) {
    Vec24 fp, fm;
    in.evaluate(perturb(cur, k, 1e-6), v, a, fp, {}, &g), in.evaluate(perturb(cur, k, -1e-6), v, a, fm, {}, &g);
    Kfd.col(k) = (fp - fm) / 2e-6;
  }
  EXPECT_LT((K1 - Kfd).norm(), 1e-6 * K1.norm());
}

// Rigid-motion invariance (cb_shell_dynamics.md §2): same local rates, superposed (Q, c)
TEST_P(InertiaOn, ForceAndJacobiansInvariantUnderRigidMotion) {
  const ElementPoses r = ref(), cur = deformed(r, 17, 0.1);
  CbShellInertia in(r, kH, kRho);
  const ElementRates v = random_rates(19, 2.0), a = random_rates(23, 5.0);
  const Mat3 Q = rot(Vec3(-2.1, 0.4, 1.7));
  const Vec3 c(4, -3, 2);
  Vec24 f1, f2;
  Mat24 M1, C1, K1, M2, C2, K2;
  in.evaluate(cur, v, a, f1, {&M1, &C1, &K1});
  in.evaluate(moved(cur, Q, c), v, a, f2, {&M2, &C2, &K2});
  EXPECT_LT((f1 - f2).norm(), 1e-12 * f1.norm());
  EXPECT_LT((M1 - M2).norm(), 1e-12 * M1.norm());
  EXPECT_LT((C1 - C2).norm(), 1e-12 * C1.norm());
  EXPECT_LT((K1 - K2).norm(), 1e-12 * K1.norm());
}

// A rigid rotation about a fixed axis: momentum and energy agree with the rigid-body formulas
TEST_P(InertiaOn, RigidSpinHasRigidBodyMomenta) {
  const ElementPoses r = ref();
  CbShellInertia in(r, kH, kRho);
  const Vec3 Omega(0.3, -0.7, 1.1);  // spatial angular velocity about the origin
  ElementRates v;
  for (int I = 0; I < 4; ++I) {
    const Vec3 xdot = Omega.cross(r[I].p);
    v[I] << r[I].R.transpose() * xdot, r[I].R.transpose() * Omega;
  }
  Vec3 p = Vec3::Zero(), L = Vec3::Zero();
  in.add_momenta(r, v, p, L);
  // p = m Omega x x_c with x_c the centre of mass; T = ½ Omega . L for a rigid motion about the origin
  EXPECT_NEAR(in.kinetic_energy(r, v), 0.5 * Omega.dot(L), 1e-10 * in.kinetic_energy(r, v));
  Vec3 xc = Vec3::Zero();
  {
    Vec3 x[8];
    for (int A = 0; A < 8; ++A) x[A] = r[A % 4].p + (A < 4 ? 1 : -1) * 0.5 * kH * r[A % 4].R.col(2);
    for (int A = 0; A < 8; ++A) xc += in.slave_mass().row(A).sum() * x[A];
    xc /= in.mass();
  }
  EXPECT_LT((p - in.mass() * Omega.cross(xc)).norm(), 1e-10 * p.norm());
}

INSTANTIATE_TEST_SUITE_P(Geometry, InertiaOn, ::testing::Values(false, true),
                         [](const auto& info) { return info.param ? "curved" : "flat_distorted"; });

}  // namespace
