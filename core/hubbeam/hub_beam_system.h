#pragma once
/// \file hub_beam_system.h
/// Rotating hub + flexible beam (the hub-beam paper, Xie & Jian 2017), equations (11)-(17) of
/// hub_beam.md.
/// State layout x = [theta | q1 free | q2 free]: hub angle [rad], axial nodal displacements of
/// nodes 2..N [m] (absent when the "axial" effect is off), then deflections v_2..v_N [m] and
/// slopes theta_2..theta_N [rad]. The root node is clamped to the hub.

#include <Eigen/Dense>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/frame/frame.h"
#include "core/hubbeam/beam_basis.h"
#include "core/model/setup_monitor.h"
#include "core/model/simulation.h"
#include "core/solve/second_order_system.h"

namespace ff::hubbeam {

struct HubBeamParams {
  double hub_radius = 0.05;        ///< a [m]
  double hub_inertia = 0.3;        ///< J_H [kg m^2]
  double length = 1.8;             ///< L [m]
  double area = 2.5e-4;            ///< A [m^2]
  double density = 2.7667e3;       ///< rho [kg/m^3]
  double youngs_modulus = 6.8952e10;  ///< E [Pa]
  double second_moment = 1.3021e-10;  ///< I [m^4]
  double torque_amplitude = 1.0;   ///< tau0 [N m]
  double torque_period = 2.0;      ///< T [s]
};

/// Which contributions the model evaluates (the scene's "effects"); nothing else is computed.
struct HubBeamEffects {
  bool axial = true;                 ///< axial stretch DoFs q1 (K1, M1, R, U11 terms)
  bool first_order_coupling = true;  ///< w_c and the D1 dynamic-stiffening terms (else zero-order)
  bool hub_torque = true;            ///< driving torque tau(t), eq. (10)
  std::vector<std::string> names() const;
};

/// Constant matrices of eqs. (7)-(9), restricted to the free DoFs. D1 and S(L) are built only with
/// first-order coupling; the zero-order model never evaluates them and holds NaN there.
struct HubBeamMatrices {
  Eigen::MatrixXd m1, k1, m2, k2, r, d1;   ///< R is (n1 x n2)
  Eigen::RowVectorXd u11, u12;
  double jb = 0.0;                         ///< J_b [kg m^2]
  Eigen::MatrixXd s_tip;                   ///< S(L) of eq. (4), free q2 DoFs
  Eigen::RowVectorXd n1_tip, n2_tip;       ///< N1(L), N2(L) on free DoFs
};

/// Assembles eqs. (7)-(9) on the full DoFs by the basis' quadrature (D1 by the swapped form (9);
/// without `with_d1`, the zero-order model, D1 is not built and stays empty).
struct FullMatrices {
  Eigen::MatrixXd m1, k1, m2, k2, r, d1;
  Eigen::RowVectorXd u11, u12;
};
/// Polls `monitor` at every quadrature point (progress; a raised stop throws SetupInterrupted).
FullMatrices assemble_full(const HubBeamParams& p, const BeamBasis& basis, bool with_d1 = true,
                           const SetupMonitor& monitor = {});
/// S(x) of eq. (4) by Gauss quadrature over [0, x] with `cells` sub-intervals (full DoFs).
Eigen::MatrixXd coupling_shape_matrix(const BeamBasis& basis, double x, int cells = 16, int gauss = 6);

struct ModalResult {
  std::vector<double> frequencies_hz;  ///< ascending; the first is the rigid hub mode (~0)
};

/// Every abscissa where HubBeamSystem evaluates `basis` (quadrature, S(L), tip, drawing), for
/// BeamBasis::check_points: what `check` validates without building the matrices.
std::vector<double> evaluation_points(const BeamBasis& basis, double length, bool first_order);

/// Estimated peak memory [bytes] of a hub-beam run with `nodes` beam nodes (FEM: elements + 1):
/// every matrix of the model and of Newmark's dense iteration is a dense square of the DoF count
/// (3 per node with the axial DoFs, else 2), so the peak grows as nodes^2. Fitted to measured
/// peaks (hub_beam.md, "Memory"); `check` and `run` refuse a scene whose estimate exceeds the
/// memory limit at its node-count key, before anything is built.
double estimated_peak_bytes(int nodes, bool axial);

/// The drawing (hub disc and beam centre line), probes and fields of a hub-beam model: known
/// before its matrices are built (HubBeamSystem::mesh(), probes(), fields() return the same).
FrameMesh hub_beam_drawing(double hub_radius, double length);
std::vector<Quantity> hub_beam_probes();
std::vector<Quantity> hub_beam_fields();

class HubBeamSystem final : public SecondOrderSystem {
 public:
  /// Assembles the matrices (polling `monitor`: progress, and SetupInterrupted on a stop).
  HubBeamSystem(const HubBeamParams& params, const HubBeamEffects& effects,
                std::unique_ptr<BeamBasis> basis, double validity_deflection_ratio = 1.0,
                const SetupMonitor& monitor = {});

  int size() const override { return 1 + n1_ + n2_; }
  void residual(const Eigen::VectorXd& x, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                double t, Eigen::VectorXd& r) const override;
  void iteration_matrix(const Eigen::VectorXd& x, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                        double t, double ca, double cv, double cx, Eigen::MatrixXd& j) const override;
  std::string check_state(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const override;

  /// Separate partial derivatives A = dr/da, C = dr/dv, K = dr/dx, eqs. (15)-(17).
  void jacobians(const Eigen::VectorXd& x, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                 Eigen::MatrixXd& A, Eigen::MatrixXd& C, Eigen::MatrixXd& K) const;

  double torque(double t) const;  ///< eq. (10) times torque_scale() [N m]
  /// Factor on the hub torque from now on (a scene's [[timeline]] torque_scale; 1 by default).
  void set_torque_scale(double scale) { torque_scale_ = scale; }
  double torque_scale() const { return torque_scale_; }
  double kinetic_energy(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const;  ///< eq. (5) [J]
  double potential_energy(const Eigen::VectorXd& x) const;                  ///< [J]
  double angular_momentum(const Eigen::VectorXd& x, const Eigen::VectorXd& v) const;  ///< eq. (14)
  double tip_transverse(const Eigen::VectorXd& x) const;  ///< w2(L) [m], floating frame
  double tip_axial(const Eigen::VectorXd& x) const;       ///< w1(L) + wc(L) [m]
  ModalResult modal_analysis() const;                     ///< eq. (28)
  /// Hub rate above which K2 + w^2 (D1 - M2) loses definiteness, eq. (29) [rad/s]; +inf when it
  /// never does (the first-order model: D1 outweighs M2).
  /// Computed when first asked (a dense generalized eigenproblem of the transverse DoFs).
  double critical_speed() const;

  // drawing: hub disc (triangles) + beam centre line (segments) in the z = 0 plane
  FrameMesh mesh() const;
  std::vector<Quantity> probes() const;
  std::vector<Quantity> fields() const;
  void fill_frame(const Eigen::VectorXd& x, const Eigen::VectorXd& v, double t, Frame& frame) const;

  /// M_theta_theta of eq. (6): hub + beam inertia about the axis in the deformed state.
  double hub_axis_inertia(const Eigen::VectorXd& x) const;

  /// Effects evaluated so far by residual() and iteration_matrix(), only those that ran. The
  /// equations (11)-(13) are one dense evaluation of every enabled term, timed per call (two clock
  /// reads) and reported on "inertia"; "bending", "axial", "first_order_coupling" (the D1 terms)
  /// and "hub_torque" (residuals only: tau(t) has no Jacobian) count the calls that evaluated them
  /// and say `included_in` "inertia".
  std::vector<EffectStat> effect_stats() const;

  const HubBeamMatrices& matrices() const { return matrices_; }
  const HubBeamParams& params() const { return params_; }
  const HubBeamEffects& effects() const { return fx_; }
  const BeamBasis& basis() const { return *basis_; }
  int axial_dofs() const { return n1_; }

 private:
  HubBeamParams params_;
  HubBeamEffects fx_;
  double torque_scale_ = 1.0;
  std::unique_ptr<BeamBasis> basis_;
  double validity_ratio_;
  mutable std::optional<double> critical_speed_;
  int n1_ = 0, n2_ = 0;
  HubBeamMatrices matrices_;
  Eigen::MatrixXd m2_minus_d1_;               ///< M2 - D1, constant
  mutable Eigen::MatrixXd work_a_, work_c_, work_k_;  ///< iteration-matrix workspace (sized once)
  mutable long long residual_calls_ = 0, matrix_calls_ = 0;  ///< effect counters (single thread)
  mutable double eval_seconds_ = 0.0;
  // drawing samples along the beam
  std::vector<double> draw_x_;
  Eigen::MatrixXd draw_n1_, draw_n2_;         ///< rows N1(x_k), N2(x_k) on free DoFs
  Eigen::MatrixXd draw_slope_rows_;           ///< dN2/dx at 3 Gauss points per sample interval (first-order only)
  Eigen::VectorXd draw_slope_weights_;        ///< their quadrature weights
  FrameMesh mesh_;                            ///< reference drawing, built once
};

}  // namespace ff::hubbeam
