#include "core/hubbeam/hub_beam_system.h"

#include <chrono>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>

#include "core/solve/gauss.h"

namespace ff::hubbeam {

using Eigen::MatrixXd;
using Eigen::RowVectorXd;
using Eigen::VectorXd;

namespace {
constexpr int kDrawSamples = 61;  // points of the drawn beam centre line
constexpr int kHubDrawSegments = 48;
}  // namespace

std::vector<std::string> HubBeamEffects::names() const {
  std::vector<std::string> n{"inertia", "bending"};
  if (axial) n.push_back("axial");
  if (first_order_coupling) n.push_back("first_order_coupling");
  if (hub_torque) n.push_back("hub_torque");
  return n;
}

namespace {
// indices of the non-zero entries of a shape row (an FEM row has 2 or 4 of 2N)
void nonzeros(const RowVectorXd& row, std::vector<int>& idx) {
  idx.clear();
  for (int i = 0; i < row.size(); ++i)
    if (row[i] != 0.0) idx.push_back(i);
}
// m += c a^T b, touching only the non-zero entries of a and b when they are few (the FEM rows:
// the dense outer product made a 2000-element beam's set-up take minutes). The sum of each entry
// is the same as the dense product's, (c a_i) b_j, in the same order: results do not change.
void add_outer(MatrixXd& m, double c, const RowVectorXd& a, const RowVectorXd& b, std::vector<int>& ia,
               std::vector<int>& ib) {
  nonzeros(a, ia);
  nonzeros(b, ib);
  if (4 * ia.size() > static_cast<std::size_t>(a.size()) && 4 * ib.size() > static_cast<std::size_t>(b.size())) {
    m.noalias() += c * a.transpose() * b;
    return;
  }
  for (int j : ib)
    for (int i : ia) m(i, j) += (c * a[i]) * b[j];
}
}  // namespace

FullMatrices assemble_full(const HubBeamParams& p, const BeamBasis& basis, bool with_d1, const SetupMonitor& monitor) {
  const int n = basis.node_count();
  const double rho_a = p.density * p.area, ea = p.youngs_modulus * p.area,
               ei = p.youngs_modulus * p.second_moment, a = p.hub_radius, len = p.length;
  FullMatrices f;
  f.m1 = f.k1 = MatrixXd::Zero(n, n);
  f.m2 = f.k2 = MatrixXd::Zero(2 * n, 2 * n);
  if (with_d1) f.d1 = MatrixXd::Zero(2 * n, 2 * n);
  f.r = MatrixXd::Zero(n, 2 * n);
  f.u11 = RowVectorXd::Zero(n);
  f.u12 = RowVectorXd::Zero(2 * n);
  ShapeRows s = basis.make_rows();
  std::vector<int> ia, ib;
  const std::vector<QuadraturePoint> points = basis.quadrature();
  const std::string phase = "assembling the beam matrices";
  for (std::size_t k = 0; k < points.size(); ++k) {
    const QuadraturePoint& q = points[k];
    monitor.poll(phase, static_cast<double>(k) / points.size());
    basis.evaluate(q.x, s);
    const double w = q.weight;
    add_outer(f.m1, rho_a * w, s.n1, s.n1, ia, ib);  // eq. (7)
    add_outer(f.k1, ea * w, s.dn1, s.dn1, ia, ib);   // eq. (8)
    add_outer(f.m2, rho_a * w, s.n2, s.n2, ia, ib);
    add_outer(f.k2, ei * w, s.ddn2, s.ddn2, ia, ib);
    add_outer(f.r, rho_a * w, s.n1, s.n2, ia, ib);
    f.u11 += (rho_a * (a + q.x) * w) * s.n1;
    f.u12 += (rho_a * (a + q.x) * w) * s.n2;
    if (!with_d1) continue;
    // eq. (9): inner integral of (a + x) from s to L done in closed form
    const double lever = a * (len - q.x) + 0.5 * (len * len - q.x * q.x);
    add_outer(f.d1, rho_a * lever * w, s.dn2, s.dn2, ia, ib);
  }
  return f;
}

MatrixXd coupling_shape_matrix(const BeamBasis& basis, double x, int cells, int gauss) {
  const int n = basis.node_count();
  MatrixXd s_mat = MatrixXd::Zero(2 * n, 2 * n);
  if (x <= 0.0) return s_mat;
  const GaussRule rule = gauss_legendre(gauss);
  ShapeRows s = basis.make_rows();
  std::vector<int> ia, ib;
  const double h = x / cells;
  for (int c = 0; c < cells; ++c)
    for (std::size_t g = 0; g < rule.points.size(); ++g) {
      basis.evaluate(h * (c + 0.5 * (rule.points[g] + 1.0)), s);
      add_outer(s_mat, 0.5 * h * rule.weights[g], s.dn2, s.dn2, ia, ib);  // eq. (4)
    }
  return s_mat;
}

std::vector<double> evaluation_points(const BeamBasis& basis, double length, bool first_order) {
  std::vector<double> xs;
  for (const QuadraturePoint& q : basis.quadrature()) xs.push_back(q.x);
  const auto add_gauss = [&](double a, double b, int gauss) {
    const GaussRule rule = gauss_legendre(gauss);
    for (double p : rule.points) xs.push_back(a + 0.5 * (b - a) * (p + 1.0));
  };
  if (first_order) {
    const int cells = 16, gauss = 6;  // coupling_shape_matrix's defaults, for S(L)
    for (int c = 0; c < cells; ++c) add_gauss(length * c / cells, length * (c + 1) / cells, gauss);
  }
  for (int k = 0; k < kDrawSamples; ++k) {
    xs.push_back(length * k / (kDrawSamples - 1));
    if (first_order && k > 0) add_gauss(length * (k - 1) / (kDrawSamples - 1), length * k / (kDrawSamples - 1), 3);
  }
  return xs;
}

// Measured peaks (run of a few steps with its metrics, i.e. the modal analysis at the end; FEM,
// 1 + 3 (n - 1) DoFs with axial, 1 + 2 (n - 1) without):
//   elements  DoFs   peak [MB]   (peak - 55 MB) / DoFs^2 [bytes]
//   400       801      133        122   (no axial)
//   400      1201      216        112
//   800      2401      652        104
// Every matrix of the model, Newmark's iteration matrix, its factor and the modal analysis' are
// dense squares of the DoF count: 125 bytes (about 16 doubles) per DoF^2 bounds them all.
double estimated_peak_bytes(int nodes, bool axial) {
  if (nodes <= 1) return 0.0;
  const double dofs = 1.0 + (axial ? 3.0 : 2.0) * (nodes - 1);
  return 55e6 + 125.0 * dofs * dofs;
}

FrameMesh build_mesh(double hub_radius, const std::vector<double>& draw_x, int hub_segments);

namespace {
// free DoFs: the root node (index 0) is clamped; q2 = [v_1..v_N, theta_1..theta_N]
std::vector<int> free_axial(int n) {
  std::vector<int> idx;
  for (int i = 1; i < n; ++i) idx.push_back(i);
  return idx;
}
std::vector<int> free_transverse(int n) {
  std::vector<int> idx;
  for (int i = 1; i < n; ++i) idx.push_back(i);
  for (int i = 1; i < n; ++i) idx.push_back(n + i);
  return idx;
}
MatrixXd pick(const MatrixXd& m, const std::vector<int>& rows, const std::vector<int>& cols) {
  MatrixXd out(rows.size(), cols.size());
  for (std::size_t i = 0; i < rows.size(); ++i)
    for (std::size_t j = 0; j < cols.size(); ++j) out(i, j) = m(rows[i], cols[j]);
  return out;
}
RowVectorXd pick(const RowVectorXd& v, const std::vector<int>& cols) {
  RowVectorXd out(cols.size());
  for (std::size_t j = 0; j < cols.size(); ++j) out[j] = v[cols[j]];
  return out;
}
}  // namespace

HubBeamSystem::HubBeamSystem(const HubBeamParams& params, const HubBeamEffects& effects,
                             std::unique_ptr<BeamBasis> basis, double validity_deflection_ratio,
                             const SetupMonitor& monitor)
    : params_(params), fx_(effects), basis_(std::move(basis)), validity_ratio_(validity_deflection_ratio) {
  const int n = basis_->node_count();
  const std::vector<int> ia = free_axial(n), it = free_transverse(n);
  const bool first_order = fx_.first_order_coupling;
  const FullMatrices f = assemble_full(params_, *basis_, first_order, monitor);
  n1_ = fx_.axial ? static_cast<int>(ia.size()) : 0;
  n2_ = static_cast<int>(it.size());
  const std::vector<int> ia_used = fx_.axial ? ia : std::vector<int>{};
  matrices_.m1 = pick(f.m1, ia_used, ia_used);
  matrices_.k1 = pick(f.k1, ia_used, ia_used);
  matrices_.r = pick(f.r, ia_used, it);
  matrices_.u11 = pick(f.u11, ia_used);
  matrices_.m2 = pick(f.m2, it, it);
  matrices_.k2 = pick(f.k2, it, it);
  matrices_.u12 = pick(f.u12, it);
  // the zero-order model never evaluates D1 or S(L): NaN, so a term multiplied by zero would show
  const double unused = std::numeric_limits<double>::quiet_NaN();
  matrices_.d1 = first_order ? pick(f.d1, it, it) : MatrixXd::Constant(n2_, n2_, unused);
  const double rho_a = params_.density * params_.area, a = params_.hub_radius;
  m2_minus_d1_ = first_order ? MatrixXd(matrices_.m2 - matrices_.d1) : matrices_.m2;
  matrices_.jb = rho_a * (std::pow(a + params_.length, 3) - std::pow(a, 3)) / 3.0;  // eq. (8)
  monitor.poll("the coupling matrix S(L)", 0.0);
  matrices_.s_tip =
      first_order ? pick(coupling_shape_matrix(*basis_, params_.length), it, it) : MatrixXd::Constant(n2_, n2_, unused);
  ShapeRows s = basis_->make_rows();
  basis_->evaluate(params_.length, s);
  matrices_.n1_tip = pick(s.n1, ia_used);
  matrices_.n2_tip = pick(s.n2, it);

  // drawing samples (precomputed so fill_frame is a few small products): the shape rows at the
  // samples, and for w_c(x_k) = -1/2 q2^T S(x_k) q2 the slope rows dN2/dx at the 3 Gauss points of
  // every interval between samples, so that q2^T S(x_k) q2 is a running sum of squared slopes
  // (one dense S(x_k) per sample took 61 n2^2 doubles: 7.8 GB for 2000 elements)
  const int samples = kDrawSamples;
  const GaussRule rule = gauss_legendre(3);
  draw_x_.resize(samples);
  draw_n1_.resize(samples, n1_);
  draw_n2_.resize(samples, n2_);
  if (fx_.first_order_coupling) {
    draw_slope_rows_.resize((samples - 1) * static_cast<int>(rule.points.size()), n2_);
    draw_slope_weights_.resize(draw_slope_rows_.rows());
  }
  for (int k = 0; k < samples; ++k) {
    monitor.poll("the drawing samples", static_cast<double>(k) / samples);
    draw_x_[k] = params_.length * k / (samples - 1);
    if (fx_.first_order_coupling && k > 0) {
      const double h = draw_x_[k] - draw_x_[k - 1];
      for (std::size_t g = 0; g < rule.points.size(); ++g) {
        basis_->evaluate(draw_x_[k - 1] + 0.5 * h * (rule.points[g] + 1.0), s);
        const int row = (k - 1) * static_cast<int>(rule.points.size()) + static_cast<int>(g);
        draw_slope_rows_.row(row) = pick(s.dn2, it);
        draw_slope_weights_[row] = 0.5 * h * rule.weights[g];
      }
    }
    basis_->evaluate(draw_x_[k], s);
    draw_n1_.row(k) = pick(s.n1, ia_used);
    draw_n2_.row(k) = pick(s.n2, it);
  }
  mesh_ = build_mesh(params_.hub_radius, draw_x_, kHubDrawSegments);
}

// eq. (29): K2 phi = w^2 (M2 - D1) phi; the smallest positive w is the critical speed. A dense
// generalized eigenproblem of n2 x n2 (minutes for a 2000-element beam): solved when first asked,
// by a run's first step, never by set-up or `check`
double HubBeamSystem::critical_speed() const {
  if (!critical_speed_) {
    Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> es(m2_minus_d1_, matrices_.k2, Eigen::EigenvaluesOnly);
    const double mu = es.eigenvalues().maxCoeff();
    critical_speed_ = mu > 0 ? 1.0 / std::sqrt(mu) : std::numeric_limits<double>::infinity();
  }
  return *critical_speed_;
}

double HubBeamSystem::hub_axis_inertia(const VectorXd& x) const {
  const auto q1 = x.segment(1, n1_), q2 = x.segment(1 + n1_, n2_);
  // eq. (6), summed in this order; the D1 term only in the first-order model
  double m = params_.hub_inertia + matrices_.jb + 2.0 * matrices_.u11.dot(q1);
  if (fx_.first_order_coupling) m -= q2.dot(matrices_.d1 * q2);
  m += q1.dot(matrices_.m1 * q1);
  m += q2.dot(matrices_.m2 * q2);
  return m;
}

double HubBeamSystem::torque(double t) const {
  if (!fx_.hub_torque || t < 0.0 || t > params_.torque_period) return 0.0;
  return torque_scale_ * params_.torque_amplitude * std::sin(2.0 * M_PI * t / params_.torque_period);  // eq. (10)
}

void HubBeamSystem::residual(const VectorXd& x, const VectorXd& v, const VectorXd& a, double t,
                             VectorXd& r) const {
  const auto t0 = std::chrono::steady_clock::now();
  r.resize(size());
  const auto q1 = x.segment(1, n1_), q2 = x.segment(1 + n1_, n2_);
  const auto dq1 = v.segment(1, n1_), dq2 = v.segment(1 + n1_, n2_);
  const auto aq1 = a.segment(1, n1_), aq2 = a.segment(1 + n1_, n2_);
  const double w = v[0], dw = a[0];
  const bool first_order = fx_.first_order_coupling;
  const VectorXd m1q1 = matrices_.m1 * q1, m2q2 = matrices_.m2 * q2, rq2 = matrices_.r * q2;
  const VectorXd d1q2 = first_order ? VectorXd(matrices_.d1 * q2) : VectorXd();
  const VectorXd rtq1 = matrices_.r.transpose() * q1;
  const double mtt = hub_axis_inertia(x);
  // eq. (11); the zero-order model leaves the D1 terms out (not multiplied by zero)
  double gyro = m1q1.dot(dq1) + m2q2.dot(dq2) + matrices_.u11.dot(dq1);
  if (first_order) gyro -= d1q2.dot(dq2);
  r[0] = mtt * dw - rq2.dot(aq1) + (matrices_.u12.transpose() + rtq1).dot(aq2) + 2.0 * w * gyro;
  if (fx_.hub_torque) r[0] -= torque(t);
  // eq. (12)
  r.segment(1, n1_) = matrices_.m1 * aq1 - rq2 * dw - 2.0 * w * (matrices_.r * dq2) + matrices_.k1 * q1 -
                      (w * w) * m1q1 - (w * w) * matrices_.u11.transpose();
  // eq. (13)
  if (first_order)
    r.segment(1 + n1_, n2_) = matrices_.m2 * aq2 + (matrices_.u12.transpose() + rtq1) * dw +
                              2.0 * w * (matrices_.r.transpose() * dq1) + matrices_.k2 * q2 + (w * w) * (d1q2 - m2q2);
  else
    r.segment(1 + n1_, n2_) = matrices_.m2 * aq2 + (matrices_.u12.transpose() + rtq1) * dw +
                              2.0 * w * (matrices_.r.transpose() * dq1) + matrices_.k2 * q2 - (w * w) * m2q2;
  ++residual_calls_;
  eval_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

void HubBeamSystem::jacobians(const VectorXd& x, const VectorXd& v, const VectorXd& a, MatrixXd& A,
                              MatrixXd& C, MatrixXd& K) const {
  const int n = size(), o1 = 1, o2 = 1 + n1_;
  A.setZero(n, n);
  C.setZero(n, n);
  K.setZero(n, n);
  const auto q1 = x.segment(1, n1_), q2 = x.segment(1 + n1_, n2_);
  const auto dq1 = v.segment(1, n1_), dq2 = v.segment(1 + n1_, n2_);
  const auto aq1 = a.segment(1, n1_), aq2 = a.segment(1 + n1_, n2_);
  const double w = v[0], dw = a[0];
  const VectorXd m1q1 = matrices_.m1 * q1, m2q2 = matrices_.m2 * q2, rq2 = matrices_.r * q2;
  const VectorXd rtq1 = matrices_.r.transpose() * q1;
  const MatrixXd& m2d1 = m2_minus_d1_;  // M2 alone in the zero-order model
  // eq. (15)
  A(0, 0) = hub_axis_inertia(x);
  A.block(0, o1, 1, n1_) = -rq2.transpose();
  A.block(0, o2, 1, n2_) = matrices_.u12 + rtq1.transpose();
  A.block(o1, 0, n1_, 1) = -rq2;
  A.block(o1, o1, n1_, n1_) = matrices_.m1;
  A.block(o2, 0, n2_, 1) = matrices_.u12.transpose() + rtq1;
  A.block(o2, o2, n2_, n2_) = matrices_.m2;
  // eq. (16)
  double gyro = m1q1.dot(dq1) + m2q2.dot(dq2) + matrices_.u11.dot(dq1);
  if (fx_.first_order_coupling) {
    const VectorXd d1q2 = matrices_.d1 * q2;
    gyro -= d1q2.dot(dq2);
  }
  C(0, 0) = 2.0 * gyro;
  C.block(0, o1, 1, n1_) = 2.0 * w * (m1q1.transpose() + matrices_.u11);
  C.block(0, o2, 1, n2_) = 2.0 * w * (m2d1 * q2).transpose();
  C.block(o1, 0, n1_, 1) = -2.0 * (matrices_.r * dq2) - 2.0 * w * (m1q1 + matrices_.u11.transpose());
  C.block(o1, o2, n1_, n2_) = -2.0 * w * matrices_.r;
  C.block(o2, 0, n2_, 1) = 2.0 * (matrices_.r.transpose() * dq1) - 2.0 * w * (m2d1 * q2);
  C.block(o2, o1, n2_, n1_) = 2.0 * w * matrices_.r.transpose();
  // eq. (17)
  K.block(0, o1, 1, n1_) = dw * (2.0 * matrices_.u11 + 2.0 * m1q1.transpose()) + (matrices_.r * aq2).transpose() +
                           2.0 * w * (matrices_.m1 * dq1).transpose();
  K.block(0, o2, 1, n2_) = dw * 2.0 * (m2d1 * q2).transpose() - (matrices_.r.transpose() * aq1).transpose() +
                           2.0 * w * (m2d1 * dq2).transpose();
  K.block(o1, o1, n1_, n1_) = matrices_.k1 - (w * w) * matrices_.m1;
  K.block(o1, o2, n1_, n2_) = -dw * matrices_.r;
  K.block(o2, o1, n2_, n1_) = dw * matrices_.r.transpose();
  K.block(o2, o2, n2_, n2_) = matrices_.k2 - (w * w) * m2d1;
}

void HubBeamSystem::iteration_matrix(const VectorXd& x, const VectorXd& v, const VectorXd& a,
                                     double /*t*/, double ca, double cv, double cx, MatrixXd& j) const {
  const auto t0 = std::chrono::steady_clock::now();
  jacobians(x, v, a, work_a_, work_c_, work_k_);
  j.noalias() = ca * work_a_;  // eq. (26)
  j.noalias() += cv * work_c_;
  j.noalias() += cx * work_k_;
  ++matrix_calls_;
  eval_seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

std::vector<EffectStat> HubBeamSystem::effect_stats() const {
  std::vector<EffectStat> out;
  const long long calls = residual_calls_ + matrix_calls_;
  if (calls == 0) return out;
  const double fused = std::numeric_limits<double>::quiet_NaN();
  out.push_back({"inertia", calls, eval_seconds_, {}});
  out.push_back({"bending", calls, fused, "inertia"});
  if (n1_ > 0) out.push_back({"axial", calls, fused, "inertia"});
  if (fx_.first_order_coupling) out.push_back({"first_order_coupling", calls, fused, "inertia"});
  if (fx_.hub_torque && residual_calls_) out.push_back({"hub_torque", residual_calls_, fused, "inertia"});
  return out;
}

std::string HubBeamSystem::check_state(const VectorXd& x, const VectorXd& v) const {
  if (!x.allFinite() || !v.allFinite()) return "the state became non-finite";
  const double tip = tip_transverse(x);
  if (std::abs(tip) > validity_ratio_ * params_.length) {
    std::ostringstream msg;
    msg << "tip deflection " << tip << " m exceeds " << validity_ratio_
        << " x beam length: the response grew without bound (small-deformation model no longer valid)";
    return msg.str();
  }
  return {};
}

double HubBeamSystem::kinetic_energy(const VectorXd& x, const VectorXd& v) const {
  const auto q1 = x.segment(1, n1_), q2 = x.segment(1 + n1_, n2_);
  const auto dq1 = v.segment(1, n1_), dq2 = v.segment(1 + n1_, n2_);
  const double w = v[0];
  // eq. (5)
  return 0.5 * hub_axis_inertia(x) * w * w +
         w * (matrices_.u12.dot(dq2) + q1.dot(matrices_.r * dq2) - q2.dot(matrices_.r.transpose() * dq1)) +
         0.5 * dq1.dot(matrices_.m1 * dq1) + 0.5 * dq2.dot(matrices_.m2 * dq2);
}

double HubBeamSystem::potential_energy(const VectorXd& x) const {
  const auto q1 = x.segment(1, n1_), q2 = x.segment(1 + n1_, n2_);
  return 0.5 * q1.dot(matrices_.k1 * q1) + 0.5 * q2.dot(matrices_.k2 * q2);
}

double HubBeamSystem::angular_momentum(const VectorXd& x, const VectorXd& v) const {
  const auto q1 = x.segment(1, n1_), q2 = x.segment(1 + n1_, n2_);
  const auto dq1 = v.segment(1, n1_), dq2 = v.segment(1 + n1_, n2_);
  // eq. (14)
  return hub_axis_inertia(x) * v[0] + matrices_.u12.dot(dq2) + q1.dot(matrices_.r * dq2) -
         q2.dot(matrices_.r.transpose() * dq1);
}

double HubBeamSystem::tip_transverse(const VectorXd& x) const {
  return matrices_.n2_tip.dot(x.segment(1 + n1_, n2_));
}

double HubBeamSystem::tip_axial(const VectorXd& x) const {
  const auto q2 = x.segment(1 + n1_, n2_);
  double u = n1_ > 0 ? matrices_.n1_tip.dot(x.segment(1, n1_)) : 0.0;
  if (fx_.first_order_coupling) u -= 0.5 * q2.dot(matrices_.s_tip * q2);  // eq. (4), wc(L)
  return u;
}

ModalResult HubBeamSystem::modal_analysis() const {
  // eq. (28)
  const int n = size();
  VectorXd zero = VectorXd::Zero(n);
  MatrixXd A, C, K;
  jacobians(zero, zero, zero, A, C, K);
  // frequencies only: without the eigenvectors (n^2 more doubles) the same eigenvalues, in a third of the time
  Eigen::GeneralizedSelfAdjointEigenSolver<MatrixXd> es(K, A, Eigen::EigenvaluesOnly);
  ModalResult out;
  for (int i = 0; i < n; ++i) {
    const double lam = std::max(0.0, es.eigenvalues()[i]);
    out.frequencies_hz.push_back(std::sqrt(lam) / (2.0 * M_PI));
  }
  return out;
}

FrameMesh HubBeamSystem::mesh() const { return mesh_; }

FrameMesh build_mesh(double hub_radius, const std::vector<double>& draw_x, int hub_segments) {
  FrameMesh m;
  auto add = [&](double px, double py) {
    m.reference_points.insert(m.reference_points.end(), {px, py, 0.0});
  };
  // hub disc: centre + rim, triangle fan
  add(0.0, 0.0);
  for (int k = 0; k < hub_segments; ++k) {
    const double phi = 2.0 * M_PI * k / hub_segments;
    add(hub_radius * std::cos(phi), hub_radius * std::sin(phi));
  }
  for (int k = 0; k < hub_segments; ++k)
    m.triangles.insert(m.triangles.end(), {0, 1 + k, 1 + (k + 1) % hub_segments});
  // beam centre line
  const int first = 1 + hub_segments;
  for (double xb : draw_x) add(hub_radius + xb, 0.0);
  for (int k = 0; k + 1 < static_cast<int>(draw_x.size()); ++k)
    m.lines.insert(m.lines.end(), {first + k, first + k + 1});
  return m;
}

std::vector<Quantity> HubBeamSystem::probes() const { return hub_beam_probes(); }
std::vector<Quantity> HubBeamSystem::fields() const { return hub_beam_fields(); }

FrameMesh hub_beam_drawing(double hub_radius, double length) {
  std::vector<double> draw_x(kDrawSamples);
  for (int k = 0; k < kDrawSamples; ++k) draw_x[k] = length * k / (kDrawSamples - 1);
  return build_mesh(hub_radius, draw_x, kHubDrawSegments);
}

std::vector<Quantity> hub_beam_probes() {
  return {{"hub_angle", "deg", "hub angle"},
          {"hub_rate", "rad/s", "hub angular rate"},
          {"tip_transverse", "m", "tip transverse displacement"},
          {"tip_axial", "m", "tip axial displacement"},
          {"torque", "N m", "hub torque"},
          {"energy", "J", "total energy"},
          {"angular_momentum", "kg m^2/s", "angular momentum about the hub axis"}};
}

std::vector<Quantity> hub_beam_fields() {
  return {{"deflection", "m", "elastic displacement"}, {"transverse", "m", "transverse displacement"}};
}

void HubBeamSystem::fill_frame(const VectorXd& x, const VectorXd& v, double t, Frame& frame) const {
  const double th = x[0], c = std::cos(th), s = std::sin(th);
  const auto q1 = x.segment(1, n1_), q2 = x.segment(1 + n1_, n2_);
  const int hub_points = 1 + kHubDrawSegments, beam_points = static_cast<int>(draw_x_.size());
  const int total = hub_points + beam_points;
  frame.points.resize(3 * total);
  frame.base_points.resize(3 * total);
  frame.fields.assign(2, std::vector<double>(total, 0.0));
  const FrameMesh& ref = mesh_;
  for (int k = 0; k < hub_points; ++k) {
    const double px = ref.reference_points[3 * k], py = ref.reference_points[3 * k + 1];
    const double wx = c * px - s * py, wy = s * px + c * py;
    frame.points[3 * k] = frame.base_points[3 * k] = wx;
    frame.points[3 * k + 1] = frame.base_points[3 * k + 1] = wy;
    frame.points[3 * k + 2] = frame.base_points[3 * k + 2] = 0.0;
  }
  double slope_squares = 0.0;
  for (int k = 0; k < beam_points; ++k) {
    const double w1 = n1_ > 0 ? draw_n1_.row(k).dot(q1) : 0.0;
    const double w2 = draw_n2_.row(k).dot(q2);
    if (fx_.first_order_coupling && k > 0)
      for (int g = 0; g < 3; ++g) {
        const int row = 3 * (k - 1) + g;
        const double slope = draw_slope_rows_.row(row).dot(q2);
        slope_squares += draw_slope_weights_[row] * slope * slope;  // q2^T S(x_k) q2, eq. (4)
      }
    const double wc = -0.5 * slope_squares;
    const double rx = params_.hub_radius + draw_x_[k] + w1 + wc, ry = w2;  // eq. (1)
    const double bx = params_.hub_radius + draw_x_[k];
    const int i = hub_points + k;
    frame.points[3 * i] = c * rx - s * ry;
    frame.points[3 * i + 1] = s * rx + c * ry;
    frame.points[3 * i + 2] = 0.0;
    frame.base_points[3 * i] = c * bx;
    frame.base_points[3 * i + 1] = s * bx;
    frame.base_points[3 * i + 2] = 0.0;
    frame.fields[0][i] = std::hypot(w1 + wc, w2);
    frame.fields[1][i] = w2;
  }
  frame.time = t;
  frame.probes = {th * 180.0 / M_PI,     v[0],   tip_transverse(x), tip_axial(x),
                  torque(t),             kinetic_energy(x, v) + potential_energy(x),
                  angular_momentum(x, v)};
}

}  // namespace ff::hubbeam
