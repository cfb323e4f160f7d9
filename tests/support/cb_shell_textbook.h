#pragma once
/// \file cb_shell_textbook.h
/// Test oracle for CbShellElement: the CB shell energy written straight from
/// core/shell/cb_shell.md eqs. (S1)-(S13), one integration point at a time, with the force and
/// the tangent obtained by exact differentiation (hyper-dual numbers) instead of the hand-derived
/// variations (S4), (S5), (S14)-(S17). It shares no code with cb_shell.cpp, so an error in the
/// fast kernel's algebra cannot cancel against itself (cb_shell.md, "Textbook oracle").
/// Slow on purpose (576 energy evaluations per tangent); never used by the solver.

#include <array>

#include "core/shell/cb_shell.h"

namespace ff::shell {

class CbShellTextbook {
 public:
  CbShellTextbook(const ElementPoses& reference, const ShellSection& section, const ShellOptions& options);

  /// Strain energy: displacement-based, or with `hr` the condensed functional (S11).
  double energy(const ElementPoses& current) const;
  /// Force f_a = d/dδ Π(X ∘ exp(δ e_a)) and tangent K_ab = d/dε f_a(X ∘ exp(ε e_b)) at 0, with
  /// the local increments of cb_shell.h (x ← x + R δu, R ← R exp(δθ~), [u0 u1 u2 θ0 θ1 θ2] per node).
  void evaluate(const ElementPoses& current, Vec24& force, Mat24& tangent) const;

  template <class T>
  struct Node;  // a pose in scalar T; defined in cb_shell_textbook.cpp, whose helpers name it

 private:
  template <class T>
  T energy_of(const std::array<Node<T>, 4>& nodes) const;

  // reference-configuration data, plain double
  struct Point {                                // one of the 2 x 2 x 2 Gauss points
    double xi, eta, zeta;
    double weight;                              // Gauss weight (1) x det[G_xi G_eta G_zeta]
    std::array<std::array<double, 6>, 5> Q;     // (S6), all 30 entries
  };
  struct DrillPoint {                           // one of the 2 x 2 mid-surface points, (S12)
    double xi, eta;
    double area;                                // A = |G_xi x G_eta| (times Gauss weight 1)
    std::array<Vec3, 4> g1_local, g2_local;     // R0_I^T G_xi, R0_I^T G_eta
  };

  ShellSection sec_;
  ShellOptions opt_;
  std::array<Vec3, 8> ref_slaves_;              // X_I^s of (S1): I = 0..3 top (s = +1), 4..7 bottom
  std::array<Point, 8> pts_;
  Eigen::Matrix3d Cm_;                          // (S7), membrane block
  double kG_ = 0.0;                             // (S7), shear
  std::array<double, 4> j0_{};                  // (S9): a1, a2, b1, b2
  Eigen::Matrix<double, 10, 10> h_inv_;         // (S10)
  double gamma_ = 0.0;                          // (S13)
  std::array<DrillPoint, 4> drill_;
};

}  // namespace ff::shell
