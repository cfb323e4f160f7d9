#pragma once
/// \file cb_shell.h
/// Continuum-based 4-node shell on SE(3) local frames (cb_shell.md). Each node carries the pose
/// X_WN = (R, x): R's third column is the director. Forces and tangents are with respect to local
/// increments [δu; δθ] per node (x ← x + R δu, R ← R exp(δθ~)), 6 per node in the order
/// node 0 [u0 u1 u2 θ0 θ1 θ2], node 1 ...; θ2 (drilling) has stiffness only with the drilling
/// effect — without it a caller keeps 5 DoFs per node.

#include <Eigen/Dense>
#include <array>
#include <memory>

#include "core/lie/se3.h"

namespace ff::shell {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec24 = Eigen::Matrix<double, 24, 1>;
using Mat24 = Eigen::Matrix<double, 24, 24>;

/// X_WN: orientation (columns e1, e2, director) and position of a master node in W: the one pose
/// type of core/lie (R = R_WN, x = p_WN).
using NodePose = lie::Pose;
using ElementPoses = std::array<NodePose, 4>;  ///< counter-clockwise about the directors

struct ShellSection {
  double youngs_modulus = 1.0;     ///< E
  double poisson_ratio = 0.0;      ///< nu
  double thickness = 0.1;          ///< h0 (constant)
  double shear_factor = 5.0 / 6.0; ///< kappa of eq. (7)
};

/// Effects of the element (scene "effects"): each switches a term of cb_shell.md.
struct ShellOptions {
  bool hr = true;                  ///< Hellinger-Reissner membrane, eqs. (9)-(11)
  bool ans = true;                 ///< assumed natural transverse shear, eq. (8)
  bool drilling = false;           ///< Fox-Simo drilling penalty, eqs. (12)-(14)
  double drilling_factor = 1e-3;   ///< c in gamma = c G h0, eq. (13)
};

class CbShellElement {
 public:
  CbShellElement(const ElementPoses& reference, const ShellSection& section, const ShellOptions& options);

  /// Internal force (24) and, if `tangent` is non-null, the tangent (24 x 24), eqs. (15)-(17).
  void evaluate(const ElementPoses& current, Vec24& force, Mat24* tangent) const;
  /// Strain energy (condensed HR functional when hr is on), for consistency checks.
  double energy(const ElementPoses& current) const;

  const ShellOptions& options() const { return opt_; }
  const ShellSection& section() const { return sec_; }

 private:
  // Reference-only data of the kernels, precomputed here (cb_shell.md, "Implementation notes").
  // The element keeps inline only what the force needs (about 2.6 kB, contiguous); the tangent's
  // kernels live in one heap block (TangentData) that a force-only evaluation never touches, and
  // what is the same for every element (shape derivatives at the fixed points) is shared.
  static constexpr int kPoints = 8;  // 2 x 2 in plane x 2 through the thickness
  struct SolidPoint {                              // force data of one integration point
    double weight;                                 // Gauss weight x det J (reference volume)
    Eigen::Matrix<double, 5, 1> ref_metric;        // G_i.G_j for xx, ee, xe, eta-zeta, xi-zeta
    Eigen::Matrix3d Qm;                            // eq. (6): in-plane rows, columns xx ee xe
    Eigen::Matrix<double, 2, 5> Qs;                // eq. (6): shear rows, columns xx ee xe ez xz
  };
  struct DrillPoint {
    double weight;                                 // Gauss weight x A
    double inv2A;                                  // 1 / (2A)
    std::array<Vec3, 4> g1_local, g2_local;        // R0_I^T G_xi, R0_I^T G_eta
  };
  struct TangentData;                              // Ku, Kt, ANS rows, H^{-1} factor (cb_shell.cpp)

  double solid_terms(const ElementPoses& cur, Vec24& f, Mat24* K) const;
  double drilling_terms(const ElementPoses& cur, Vec24& f, Mat24* K) const;

  ShellSection sec_;
  ShellOptions opt_;
  std::array<SolidPoint, kPoints> pts_;
  std::array<std::array<double, 4>, 2> tie_ref_;   // G_i.G_zeta of the tied components [layer][A..D]
  std::array<double, 6> p_coef_;                   // eq. (9): a1^2, b1^2, a1 b1, a2^2, b2^2, a2 b2
  Eigen::Matrix<double, 10, 10> h_inv_;            // eq. (10)
  Eigen::Matrix3d Cm_;                             // eq. (7), membrane block
  double kG_ = 0.0;                                // eq. (7), shear
  double gamma_ = 0.0;                             // eq. (13)
  std::shared_ptr<const TangentData> tan_;         // immutable, shared by copies
  std::array<DrillPoint, 4> drill_;
};

}  // namespace ff::shell
