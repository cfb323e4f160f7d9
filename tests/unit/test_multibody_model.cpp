// Multibody model of shells, rigid bodies and joints (core/shell/cb_shell_dynamics.md): the
// assembled iteration matrix S = a M + b C + c K and the constraint Jacobian B match central
// differences of the residual and of Φ (D5)-(D13); residual and S are invariant under a
// superposed rigid motion of the whole system (joints between bodies only, no gravity).
#include <gtest/gtest.h>

#include <random>

#include "core/lie/se3.h"
#include "core/mesh/generators.h"
#include "core/shell/multibody_model.h"

using namespace ff;
using namespace ff::shell;

namespace {

MultibodySpec system_spec(bool gravity, bool ground) {
  MultibodySpec s;
  ShellBodySpec plate;
  plate.name = "plate";
  plate.mesh = mesh::rectangular_plate(1.0, 0.6, 3, 2, "plate");
  plate.section = isotropic_section(2.0e7, 0.3, 0.02);
  plate.density = 1000;
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
  panel.options.drilling = true;  // 6 DoF: can carry rotational joint rows
  panel.options.drilling_factor = 0.1;
  s.shells = {plate, panel};
  RigidBodySpec rb;
  rb.name = "block";
  rb.pose.p = Vec3(0.5, 1.0, 0.2);
  rb.mass = 3.0;
  rb.inertia << 0.4, 0.05, 0.0, 0.05, 0.3, 0.02, 0.0, 0.02, 0.2;
  s.rigid = {rb};
  s.gravity = gravity;
  s.g = Vec3(0.5, -1.0, -9.81);
  const int plate_nodes = 12, rigid = plate_nodes + 12;
  // plate corner to a ground point off its reference position: three rows (at the node itself
  // it would be a pin, see PinOnTheSpotLeavesTheUnknowns)
  s.positions.push_back({0, -1, Vec3(0.0, 0.0, 0.02)});
  s.positions.push_back({3, plate_nodes + 0, Vec3::Zero()});  // plate to panel (coincidence in a moved state)
  s.positions.push_back({plate_nodes + 5, rigid, Vec3::Zero(), Vec3::Zero(), Vec3(0.1, -0.2, 0.3)});
  s.positions.push_back({rigid, -1, Vec3(0.4, 0.9, 0.1), Vec3(-0.3, 0.1, 0.2), Vec3::Zero()});  // pivot off the CoM
  s.perpendiculars.push_back({plate_nodes + 5, rigid, Vec3::UnitX(), Vec3::UnitY()});
  s.perpendiculars.push_back({rigid, -1, Vec3::UnitZ(), Vec3::UnitX()});
  if (!ground) {
    s.positions.erase(s.positions.begin());
    s.positions.pop_back();
    s.perpendiculars.pop_back();
  }
  return s;
}

Eigen::VectorXd random_vector(int n, unsigned seed, double scale) {
  std::mt19937 g(seed);
  std::uniform_real_distribution<double> u(-1, 1);
  Eigen::VectorXd x(n);
  for (int i = 0; i < n; ++i) x[i] = scale * u(g);
  return x;
}

TEST(MultibodyModel, IterationMatrixAndConstraintJacobianMatchCentralDifferences) {
  MultibodyModel model(system_spec(true, true));
  const int n = model.size(), m = model.constraint_count();
  ASSERT_EQ(m, 4 * 3 + 2);
  model.configure(random_vector(n, 1, 0.05));  // a deformed, rotated state
  model.commit();
  const Eigen::VectorXd v = random_vector(n, 2, 1.0), vd = random_vector(n, 3, 4.0), lam = random_vector(m, 4, 50.0);
  Eigen::VectorXd r, phi, rp, rm, pp, pm;
  SparseMatrixD S, B;
  const double eps = 1e-6;
  struct Part {
    IterationWeights w;
    const char* name;
  };
  for (const Part& part : {Part{{1, 0, 0}, "mass"}, Part{{0, 1, 0}, "gyroscopic"}, Part{{0, 0, 1}, "stiffness"}}) {
    model.evaluate(0, v, vd, lam, r, phi, &part.w, &S, &B);
    const Eigen::MatrixXd Sd = Eigen::MatrixXd(S);
    Eigen::MatrixXd fd(n, n), bfd(m, n);
    for (int k = 0; k < n; ++k) {
      // the residual is linear in v̇ and quadratic in v: central differences are exact there up to
      // round-off, so a large step keeps the elastic force's round-off out of the small inertia terms
      Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
      e[k] = part.w.stiffness > 0 ? eps : 1e-2;
      if (part.w.mass > 0) {
        model.evaluate(0, v, vd + e, lam, rp, pp, nullptr, nullptr, nullptr);
        model.evaluate(0, v, vd - e, lam, rm, pm, nullptr, nullptr, nullptr);
      } else if (part.w.damping > 0) {
        model.evaluate(0, v + e, vd, lam, rp, pp, nullptr, nullptr, nullptr);
        model.evaluate(0, v - e, vd, lam, rm, pm, nullptr, nullptr, nullptr);
      } else {
        model.configure(e);
        model.evaluate(0, v, vd, lam, rp, pp, nullptr, nullptr, nullptr);
        model.configure(-e);
        model.evaluate(0, v, vd, lam, rm, pm, nullptr, nullptr, nullptr);
        model.rollback();
        bfd.col(k) = (pp - pm) / (2 * eps);
      }
      fd.col(k) = (rp - rm) / (2 * e[k]);
    }
    EXPECT_LT((Sd - fd).norm(), 1e-6 * fd.norm()) << part.name;
    EXPECT_GT(fd.norm(), 0.0) << part.name;
    if (part.w.stiffness > 0) { EXPECT_LT((Eigen::MatrixXd(B) - bfd).norm(), 1e-7 * bfd.norm()); }
  }
}

// Newton's unknown is the step x of q = q_n exp(x) (generalized_alpha.md (G3)); its exact matrix
// is the position part times T_SE3(x) per node (G8)-(G9). At a step of 0.05-0.3 rad the matrix
// without T (the shell paper's) is off by O(|x|), which this test also shows.
TEST(MultibodyModel, IterationMatrixIsTheExactDerivativeWithRespectToTheStep) {
  MultibodyModel model(system_spec(true, true));
  const int n = model.size(), m = model.constraint_count();
  model.configure(random_vector(n, 1, 0.05));
  model.commit();
  Eigen::VectorXd x0 = random_vector(n, 9, 0.1);
  for (int I = 0; I < model.node_count(); ++I)  // larger turns at some nodes: T far from I
    if (I % 3 == 0)
      for (int s = 3; s < 6; ++s)
        if (model.equation(I, s) >= 0) x0[model.equation(I, s)] *= 3.0;
  const Eigen::VectorXd v = random_vector(n, 2, 1.0), vd = random_vector(n, 3, 4.0), lam = random_vector(m, 4, 50.0);
  const IterationWeights stiffness{0, 0, 1};
  Eigen::VectorXd r, phi, rp, rm, pp, pm;
  SparseMatrixD S, B, S_paper, B_paper;
  model.configure(x0);
  model.evaluate(0, v, vd, lam, r, phi, &stiffness, &S, &B);
  model.set_exact_iteration_matrix(false);
  model.evaluate(0, v, vd, lam, r, phi, &stiffness, &S_paper, &B_paper);
  model.set_exact_iteration_matrix(true);
  model.evaluate(0, v, vd, lam, r, phi, &stiffness, &S, &B);
  // the constraint forces Gᵀλ keep the local-increment directions: ∂r/∂λ = Gᵀ = B_paperᵀ (G9)
  ASSERT_NE(model.constraint_force_directions(), nullptr);
  EXPECT_LT((Eigen::MatrixXd(*model.constraint_force_directions()) - Eigen::MatrixXd(B_paper)).norm(),
            1e-14 * Eigen::MatrixXd(B_paper).norm());
  Eigen::MatrixXd fd(n, n), bfd(m, n);
  const double eps = 1e-6;
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd e = Eigen::VectorXd::Zero(n);
    e[k] = eps;
    model.configure(x0 + e);
    model.evaluate(0, v, vd, lam, rp, pp, nullptr, nullptr, nullptr);
    model.configure(x0 - e);
    model.evaluate(0, v, vd, lam, rm, pm, nullptr, nullptr, nullptr);
    fd.col(k) = (rp - rm) / (2 * eps);
    bfd.col(k) = (pp - pm) / (2 * eps);
  }
  model.rollback();
  EXPECT_LT((Eigen::MatrixXd(S) - fd).norm(), 1e-6 * fd.norm());
  EXPECT_LT((Eigen::MatrixXd(B) - bfd).norm(), 1e-7 * bfd.norm());
  // without T the error is first order in the step, far above the differencing error
  EXPECT_GT((Eigen::MatrixXd(S_paper) - fd).norm(), 1e-3 * fd.norm());
  EXPECT_GT((Eigen::MatrixXd(B_paper) - bfd).norm(), 1e-3 * bfd.norm());
}

TEST(MultibodyModel, ResidualAndMatrixInvariantUnderRigidMotionOfTheSystem) {
  MultibodySpec spec = system_spec(false, false);
  // 6 DoF everywhere: a 5-DoF node cannot reach the frame Q R by local increments without a
  // drilling component (its spin about the director is a gauge), so exact equality needs 6
  spec.shells[0].options.drilling = true;
  spec.shells[0].options.drilling_factor = 0.1;
  MultibodyModel a(spec);
  a.configure(random_vector(a.size(), 5, 0.05));
  a.commit();
  // the same state moved by (Q, c): a second model whose committed poses are Q H, local rates equal
  MultibodyModel b(spec);
  const Mat3 Q = Eigen::AngleAxisd(2.2, Vec3(0.3, -0.8, 0.5).normalized()).toRotationMatrix();
  const Vec3 c(3, -1, 2);
  // reach Q H from the reference through local increments: H_ref exp(ξ) = Q H  ->  ξ = log(H_ref^-1 Q H)
  Eigen::VectorXd step = Eigen::VectorXd::Zero(b.size());
  for (int I = 0; I < b.node_count(); ++I) {
    const NodePose& H = a.poses()[I];
    const NodePose& R0 = b.reference_pose(I);
    const Mat3 R = R0.R.transpose() * Q * H.R;
    const Vec3 x = R0.R.transpose() * (Q * H.p + c - R0.p);
    const Eigen::Matrix<double, 6, 1> xi = ff::lie::log_se3(ff::lie::Pose{R, x});
    for (int s = 0; s < 6; ++s)
      if (b.equation(I, s) >= 0) step[b.equation(I, s)] = xi[s];
  }
  b.configure(step);
  b.commit();
  for (int I = 0; I < b.node_count(); ++I) {
    ASSERT_LT((b.poses()[I].p - (Q * a.poses()[I].p + c)).norm(), 1e-9);
    ASSERT_LT((b.poses()[I].R - Q * a.poses()[I].R).norm(), 1e-9);
  }
  const Eigen::VectorXd v = random_vector(a.size(), 6, 1.0), vd = random_vector(a.size(), 7, 4.0);
  const Eigen::VectorXd lam = random_vector(a.constraint_count(), 8, 50.0);
  Eigen::VectorXd ra, rb, pa, pb;
  SparseMatrixD Sa, Sb, Ba, Bb;
  const IterationWeights w{3.0, 2.0, 1.0};
  // position rows are in node a's frame (D11'), (D12'): values, multipliers and the constraint
  // Jacobian are all invariant, which is what lets a frozen iteration matrix stay fresh
  for (const PositionConstraint& c : spec.positions) { ASSERT_GE(c.b, 0) << "a ground point does not move with Q"; }
  a.evaluate(0, v, vd, lam, ra, pa, &w, &Sa, &Ba);
  b.evaluate(0, v, vd, lam, rb, pb, &w, &Sb, &Bb);
  EXPECT_LT((ra - rb).norm(), 1e-9 * ra.norm());
  EXPECT_LT((Eigen::MatrixXd(Sa) - Eigen::MatrixXd(Sb)).norm(), 1e-9 * Eigen::MatrixXd(Sa).norm());
  EXPECT_LT((Eigen::MatrixXd(Ba) - Eigen::MatrixXd(Bb)).norm(), 1e-9 * Eigen::MatrixXd(Ba).norm());
  for (int k = 0; k < a.constraint_count(); ++k) { EXPECT_NEAR(pa[k], pb[k], 1e-9); }
}

TEST(MultibodyModel, RotationalJointOnFiveDofNodeIsRefusedWithAReason) {
  MultibodySpec s = system_spec(false, false);
  s.perpendiculars.push_back({1, -1, Vec3::UnitX(), Vec3::UnitY()});  // node 1: plate, no drilling
  try {
    MultibodyModel m(s);
    FAIL() << "expected a refusal";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("5 DoFs"), std::string::npos) << e.what();
  }
}

// A ground point at a node's own reference position is a pin: three unknowns fewer, no rows, the
// node stays where it is whatever the step, and the model still reports the joints effect.
TEST(MultibodyModel, PinOnTheSpotLeavesTheUnknowns) {
  MultibodySpec rows = system_spec(false, false);
  MultibodySpec pins = rows;
  MultibodyModel free_model(rows);
  pins.positions.push_back({0, -1, free_model.reference_pose(0).p});
  pins.positions.push_back({1, -1, free_model.reference_pose(1).p});
  MultibodyModel pinned(pins);
  EXPECT_EQ(pinned.size(), free_model.size() - 6);
  EXPECT_EQ(pinned.constraint_count(), free_model.constraint_count());
  EXPECT_EQ(pinned.spec().positions.size(), rows.positions.size());
  pinned.configure(random_vector(pinned.size(), 9, 0.3));
  pinned.commit();
  for (int I : {0, 1}) { EXPECT_EQ((pinned.poses()[I].p - pinned.reference_pose(I).p).norm(), 0.0); }
  EXPECT_GT((pinned.poses()[0].R - pinned.reference_pose(0).R).norm(), 1e-3);  // free to turn
  Eigen::VectorXd r, phi;
  pinned.evaluate(0, Eigen::VectorXd::Zero(pinned.size()), Eigen::VectorXd::Zero(pinned.size()),
                  Eigen::VectorXd::Zero(pinned.constraint_count()), r, phi, nullptr, nullptr, nullptr);
  bool joints = false;
  for (const auto& e : pinned.effect_stats()) joints = joints || (e.effect == "joints" && e.evaluations > 0);
  EXPECT_TRUE(joints);
}

}  // namespace
