#pragma once
/// \file cb_shell_inertia.h
/// Inertia and gravity of the CB shell element on SE(3) local frames (cb_shell_dynamics.md
/// §1-§4). Rates are body velocities V_I = [v_I; ω_I] and their time derivatives, 6 per node in
/// the node order of cb_shell.h; a 5-DoF node passes ω_I·e3 = 0. Forces and matrices use the
/// same local increments as CbShellElement (x ← x + R δu, R ← R exp(δθ~)).

#include <array>
#include <vector>

#include "core/shell/cb_shell.h"

namespace ff::shell {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using ElementRates = std::array<Vec6, 4>;

/// Optional outputs of CbShellInertia::evaluate: ∂F/∂V̇ (D5), ∂F/∂V (D6), ∂F/∂q (D7).
struct InertiaJacobians {
  Mat24* mass = nullptr;
  Mat24* gyroscopic = nullptr;
  Mat24* stiffness = nullptr;
};

class CbShellInertia {
 public:
  /// Consistent mass m_AB of the solid (D3) on the reference geometry.
  CbShellInertia(const ElementPoses& reference, double thickness, double density);
  /// The same for a section: a laminate's plies each with their own density, through the stack
  /// (laminate.md (L10)); an isotropic section with `density`.
  CbShellInertia(const ElementPoses& reference, const ShellSection& section, double density);

  /// Inertia force F (D4) for velocities `v` and accelerations `a` (local, per node), with the
  /// Jacobians that are asked for. With `g` given, F is the inertia force minus the gravity
  /// force (D4) − (D8), and jac.stiffness likewise ∂(F − F^g)/∂q, in one pass over the slave
  /// points: the gravity of a slave joins its inertia force before both turn into the node frame.
  void evaluate(const ElementPoses& current, const ElementRates& v, const ElementRates& a, Vec24& force,
                const InertiaJacobians& jac = {}, const Vec3* g = nullptr) const;
  /// Generalized gravity force F^g (D8) and, if asked, its derivative ∂F^g/∂q, on its own. The
  /// multibody model takes gravity in evaluate()'s pass instead; this is that pass's oracle.
  void gravity(const ElementPoses& current, const Vec3& g, Vec24& force, Mat24* dforce_dq) const;

  double kinetic_energy(const ElementPoses& current, const ElementRates& v) const;  ///< (D15)
  /// Linear momentum p and angular momentum L about the origin (D15), added to the arguments.
  void add_momenta(const ElementPoses& current, const ElementRates& v, Vec3& p, Vec3& L) const;
  /// −Σ f^g_A · x_A (D8).
  double gravity_potential(const ElementPoses& current, const Vec3& g) const;
  double mass() const { return slave_mass_.sum(); }
  /// Test oracle: true makes evaluate() form the Jacobians (D5)-(D7) term by term over the 64
  /// slave pairs instead of the per-node-pair sums (cb_shell_dynamics.md §3).
  void set_plain_jacobians(bool plain) { plain_jacobians_ = plain; }
  const Eigen::Matrix<double, 8, 8>& slave_mass() const { return mass_matrix_; }

 private:
  // Σ over the thickness combinations of node pair (I, J) (A = I + 4 s_i, B = J + 4 s_j):
  // m_AB, m_AB s_A h/2, m_AB s_B h/2, m_AB s_A s_B h²/4, and per s_j: m_AB and m_AB s_A h/2
  struct PairSums {
    double m = 0, m_a = 0, m_b = 0, m_ab = 0;
    double c0[2] = {0, 0}, c1[2] = {0, 0};
  };
  struct DensityLayer {
    double lo, hi, density;  // an interval of the thickness coordinate and its density
  };
  CbShellInertia(const ElementPoses& reference, double thickness, const std::vector<DensityLayer>& layers);
  static std::vector<DensityLayer> density_layers(const ShellSection& section, double density);
  void add_rate_and_position_blocks_plain(const ElementPoses& current, const ElementRates& v, const Vec3 w[8],
                                          const Vec3 b[8], const InertiaJacobians& jac) const;
  double half_h_;
  PairSums pair_sums_[4][4];
  bool plain_jacobians_ = false;
  Eigen::Matrix<double, 8, 8> mass_matrix_;  // m_AB (D3); slave A = master A % 4, side + for A < 4
  Eigen::Matrix<double, 8, 1> slave_mass_;  // row sums: Σ_B m_AB
};

}  // namespace ff::shell
