// The static solvers on states that are not vectors: a pendulum whose angle is a unit complex
// number (SO(2)) and a rigid body whose attitude is a rotation matrix (SO(3)). The problems store
// only the group element, so the only way to move them is update(δ) = right multiplication by
// exp(δ); a solver that added vectors to the state could not even be written against them.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <Eigen/Geometry>
#include <complex>
#include <vector>

#include "core/solve/static_arclength.h"
#include "core/solve/static_newton.h"

namespace ff {
namespace {

// Pendulum of weight W and arm ℓ under a constant torque λ M0, angle θ from hanging down:
// r = Wℓ sin θ − λ M0, K = Wℓ cos θ. Equilibria λ(θ) = (Wℓ/M0) sin θ: a limit point at θ = π/2,
// λ back to zero at θ = π (inverted) and negative beyond — the angle wraps through ±π there.
class Pendulum : public StaticProblem {
 public:
  double w_l = 2.0, m0 = 1.0, arm = 1.0;  // arm: dof_scale, so the arc length is a tip distance
  std::complex<double> z{1.0, 0.0}, saved{1.0, 0.0};
  int size() const override { return 1; }
  void evaluate(double lambda, Eigen::VectorXd& r, Eigen::SparseMatrix<double>* k, Eigen::VectorXd* f) override {
    r.resize(1);
    r[0] = w_l * z.imag() - lambda * m0;
    if (k) {
      k->resize(1, 1);
      k->setZero();
      k->insert(0, 0) = w_l * z.real();
      k->makeCompressed();
    }
    if (f) *f = Eigen::VectorXd::Constant(1, m0);
  }
  void update(const Eigen::VectorXd& d) override { z *= std::polar(1.0, d[0]); }
  void save_state() override { saved = z; }
  void restore_state() override { z = saved; }
  double dof_scale(int) const override { return arm; }
  double lambda_of_state() const { return w_l * z.imag() / m0; }
};

TEST(ManifoldSO2, ArcLengthTurnsThePendulumOverThroughTheInvertedPosition) {
  Pendulum p;
  p.arm = 0.5;
  ArcLengthSettings s;
  s.convergence.residual_tolerance = 1e-12;
  s.initial_load_increment = 0.1;
  s.max_arc_length_ratio = 2.0;
  s.lambda_max = 10.0;
  s.monitor_dof = 0;
  s.displacement_limit = 4.5;  // rad, past π: the solver's Σδ, the problem has no angle
  std::vector<std::pair<StaticStepInfo, std::complex<double>>> path;
  s.on_step = [&](const StaticStepInfo& i) { path.emplace_back(i, p.z); };
  const StaticResult r = solve_arc_length(p, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::displacement_limit);
  EXPECT_EQ(r.limit_points, 1);  // θ = π/2; λ then falls through zero at θ = π
  double theta_prev = 0.0;
  bool wrapped = false;
  for (const auto& [info, z] : path) {
    const double theta = info.monitored;  // unwrapped angle = Σ of the increments
    EXPECT_NEAR(std::abs(z), 1.0, 1e-13);
    EXPECT_NEAR(std::cos(theta), z.real(), 1e-12);
    EXPECT_NEAR(std::sin(theta), z.imag(), 1e-12);
    EXPECT_NEAR(info.lambda, 2.0 * std::sin(theta), 1e-11);
    // dof_scale 0.5: the step norm is the arc travelled by a point at 0.5 from the pivot
    EXPECT_NEAR(info.step_norm, 0.5 * (theta - theta_prev), 1e-12);
    wrapped |= std::arg(z) < 0.0 && theta > M_PI;
    theta_prev = theta;
  }
  EXPECT_TRUE(wrapped);
  EXPECT_GE(theta_prev, 4.5);
  EXPECT_LT(r.lambda, 0.0);
}

TEST(ManifoldSO2, LoadControlStopsAtTheLimitTorque) {
  Pendulum p;
  LoadControlSettings s;
  s.lambda_end = 2.5;  // beyond the largest torque the weight can hold (λ = 2)
  const StaticResult r = solve_load_control(p, s);
  EXPECT_EQ(r.status, StaticStatus::diverged);
  EXPECT_NEAR(r.lambda, 2.0, 1e-4);
  EXPECT_GT(p.z.real(), 0.0);  // still below horizontal
  EXPECT_NEAR(p.lambda_of_state(), r.lambda, 1e-8);
}

// ---------------------------------------------------------------------------------------------
// Rigid body, attitude R, body points b_i (the unit axes) loaded by dead forces
// F_i(λ) = c b_i + λ P_i. Potential Π = −Σ F_i·(R b_i); with R ← R exp(θ̂):
//   r = −Σ b_i × (Rᵀ F_i),   K = −Σ b̂_i (Rᵀ F_i)^   (non-symmetric off equilibrium),
// f_ref = Σ b_i × (Rᵀ P_i) depends on the state. The minimum of Π is R = U diag(1,1,det) Vᵀ
// from the SVD of M = Σ F_i b_iᵀ (Kabsch), which the loaded path tracks continuously.
Eigen::Matrix3d hat(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d exp_so3(const Eigen::Vector3d& v) {
  const double a = v.norm();
  return a < 1e-300 ? Eigen::Matrix3d::Identity() : Eigen::AngleAxisd(a, v / a).toRotationMatrix();
}

class RigidBody : public StaticProblem {
 public:
  double c = 1.0;
  std::array<Eigen::Vector3d, 3> b{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
  std::array<Eigen::Vector3d, 3> p{Eigen::Vector3d(-3.0, 3.0, 0.5), Eigen::Vector3d(-3.0, -3.0, 1.0),
                                   Eigen::Vector3d(1.0, 0.0, -0.5)};
  Eigen::Matrix3d rot = Eigen::Matrix3d::Identity(), saved = Eigen::Matrix3d::Identity();

  int size() const override { return 3; }
  void evaluate(double lambda, Eigen::VectorXd& r, Eigen::SparseMatrix<double>* k, Eigen::VectorXd* f) override {
    Eigen::Vector3d res = Eigen::Vector3d::Zero(), load = Eigen::Vector3d::Zero();
    Eigen::Matrix3d kk = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d v = rot.transpose() * (c * b[i] + lambda * p[i]);
      res -= b[i].cross(v);
      load += b[i].cross(rot.transpose() * p[i]);
      kk -= hat(b[i]) * hat(v);
    }
    r = res;
    if (f) *f = load;
    if (k) {
      *k = kk.sparseView(0.0, 0.0);
      k->makeCompressed();
    }
  }
  void update(const Eigen::VectorXd& d) override { rot = rot * exp_so3(d); }
  void save_state() override { saved = rot; }
  void restore_state() override { rot = saved; }

  Eigen::Matrix3d kabsch(double lambda) const {
    Eigen::Matrix3d m = Eigen::Matrix3d::Zero();
    for (int i = 0; i < 3; ++i) m += (c * b[i] + lambda * p[i]) * b[i].transpose();
    Eigen::JacobiSVD<Eigen::Matrix3d> svd(m, Eigen::ComputeFullU | Eigen::ComputeFullV);
    Eigen::Matrix3d d = Eigen::Matrix3d::Identity();
    d(2, 2) = (svd.matrixU() * svd.matrixV().transpose()).determinant();
    return svd.matrixU() * d * svd.matrixV().transpose();
  }
};

double rotation_angle(const Eigen::Matrix3d& r) { return Eigen::AngleAxisd(r).angle(); }

TEST(ManifoldSO3, TangentIsTheDerivativeAlongUpdate) {
  // the test problem itself: K δ = d/dε r(R exp(εδ̂)) by central differences, h ≈ cbrt(eps)
  RigidBody body;
  body.rot = exp_so3(Eigen::Vector3d(0.3, -0.7, 1.1));
  Eigen::VectorXd r0, rp, rm, f;
  Eigen::SparseMatrix<double> k;
  body.evaluate(0.7, r0, &k, &f);
  const Eigen::Matrix3d kd = Eigen::Matrix3d(k);
  const double h = 6e-6;
  for (int j = 0; j < 3; ++j) {
    Eigen::VectorXd e = Eigen::VectorXd::Unit(3, j);
    body.save_state();
    body.update(h * e);
    body.evaluate(0.7, rp, nullptr, nullptr);
    body.restore_state();
    body.update(-h * e);
    body.evaluate(0.7, rm, nullptr, nullptr);
    body.restore_state();
    // truncation h²|r'''| + round-off eps|r|/h ≈ 1e-10 for |r| ~ 10
    EXPECT_LT((kd.col(j) - (rp - rm) / (2 * h)).norm(), 1e-8) << j;
  }
  EXPECT_GT((kd - kd.transpose()).norm(), 0.1);  // non-symmetric away from equilibrium
}

TEST(ManifoldSO3, LoadControlFollowsTheKabschSolutionThroughALargeRotation) {
  RigidBody body;
  LoadControlSettings s;
  s.convergence.residual_tolerance = 1e-12;
  s.convergence.increment_tolerance = 1e-12;
  double last_angle = 0.0;
  int steps = 0;
  s.on_step = [&](const StaticStepInfo& i) {
    ++steps;
    EXPECT_LT((body.rot - body.kabsch(i.lambda)).norm(), 1e-10) << "λ = " << i.lambda;
    EXPECT_LT((body.rot.transpose() * body.rot - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    last_angle = rotation_angle(body.rot);
  };
  const StaticResult r = solve_load_control(body, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_GT(steps, 3);
  EXPECT_GT(last_angle, 2.0);  // well beyond small rotations (> 115°)
  EXPECT_LT((body.rot - body.kabsch(1.0)).norm(), 1e-10);
}

TEST(ManifoldSO3, ArcLengthLandsOnLambdaMaxOnTheSamePath) {
  RigidBody body;
  ArcLengthSettings s;
  s.convergence.residual_tolerance = 1e-12;
  s.convergence.increment_tolerance = 1e-12;
  s.initial_load_increment = 0.05;
  s.lambda_max = 1.0;
  s.on_step = [&](const StaticStepInfo& i) {
    EXPECT_LT((body.rot - body.kabsch(i.lambda)).norm(), 1e-10) << "λ = " << i.lambda;
  };
  const StaticResult r = solve_arc_length(body, s);
  ASSERT_EQ(r.status, StaticStatus::completed) << r.reason;
  EXPECT_EQ(r.stop, StaticStop::lambda_reached);
  EXPECT_DOUBLE_EQ(r.lambda, 1.0);
  EXPECT_LT((body.rot - body.kabsch(1.0)).norm(), 1e-10);
}

}  // namespace
}  // namespace ff
