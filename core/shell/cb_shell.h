#pragma once
/// \file cb_shell.h
/// Continuum-based 4-node shell on SE(3) local frames (cb_shell.md). Each node carries the pose
/// X_WN = (R, x): R's third column is the director. Forces and tangents are with respect to local
/// increments [δu; δθ] per node (x ← x + R δu, R ← R exp(δθ~)), 6 per node in the order
/// node 0 [u0 u1 u2 θ0 θ1 θ2], node 1 ...; θ2 (drilling) has stiffness only with the drilling
/// effect — without it a caller keeps 5 DoFs per node.

#include <Eigen/Dense>
#include <array>

namespace ff::shell {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec24 = Eigen::Matrix<double, 24, 1>;
using Mat24 = Eigen::Matrix<double, 24, 24>;

/// X_WN: orientation (columns e1, e2, director) and position of a master node in W.
struct NodePose {
  Mat3 R = Mat3::Identity();
  Vec3 x = Vec3::Zero();
};
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
  // reference-only data of the kernels, precomputed here (cb_shell.md, "Implementation notes")
  static constexpr int kPoints = 8;  // 2 x 2 in plane x 2 through the thickness
  using Mat37 = Eigen::Matrix<double, 3, 7>;
  struct SolidPoint {
    double weight;                                 // Gauss weight x det J (reference volume)
    double xi, eta, zeta;
    int layer;                                     // thickness layer (tying values)
    // rows I: sum over the two slaves of master I of dN/d(xi, eta, zeta); rows 4 + I: the same
    // sum weighted by s, so g = [x_I, h0/2 d_I] * phi (eqs. 1, 3)
    Eigen::Matrix<double, 8, 3> phi;
    Eigen::Matrix<double, 5, 1> ref_metric;        // G_i.G_j for xx, ee, xe, eta-zeta, xi-zeta
    Eigen::Matrix3d Qm;                            // eq. (6): in-plane rows, columns xx ee xe
    Eigen::Matrix<double, 2, 5> Qs;                // eq. (6): shear rows, columns xx ee xe ez xz
    Eigen::Matrix<double, 3, 10> P;                // eq. (9), P-hat at this point
    // master rows of node I from R_I^T g: u part Ku, theta part Kt; columns: with hr the five
    // columns of w B_m^T P (eq. 11, per layer) then the two scaled shear rows; without hr the
    // three membrane rows times sqrt(w) L_c (C_m = L_c L_c^T), the two shear rows, two unused
    std::array<Mat37, 4> Ku, Kt;
    Eigen::Matrix<double, 4, 2> ans;               // tying rows into the shear rows, eq. (8)
  };
  struct TyingPoint {                              // eq. (8) at one thickness layer
    Eigen::Matrix<double, 8, 3> phi;               // as SolidPoint::phi
    Eigen::Matrix<double, 8, 8> M;                 // eq. (5) of the tied component in phi's basis
    double ref_value;                              // G_i.G_zeta of the tied component
    int i;                                         // 1 (eta-zeta) or 0 (xi-zeta)
  };
  struct DrillPoint {
    double weight;                                 // Gauss weight x A
    double inv2A;                                  // 1 / (2A)
    Eigen::Vector4d N, dNxi, dNeta;
    std::array<Vec3, 4> g1_local, g2_local;        // R0_I^T G_xi, R0_I^T G_eta
  };

  double solid_terms(const ElementPoses& cur, Vec24& f, Mat24* K) const;
  double drilling_terms(const ElementPoses& cur, Vec24& f, Mat24* K) const;

  ShellSection sec_;
  ShellOptions opt_;
  std::array<SolidPoint, kPoints> pts_;
  std::array<std::array<TyingPoint, 4>, 2> tying_;  // [layer][A, B, C, D]
  std::array<DrillPoint, 4> drill_;
  Eigen::Matrix<double, 10, 10> h_inv_;            // eq. (10)
  Eigen::Matrix<double, 10, 10> h_inv_factor_;     // L with L L^T = h_inv_
  Eigen::Matrix<double, 5, 5> C_;                  // eq. (7)
  double gamma_ = 0.0;                             // eq. (13)
};

}  // namespace ff::shell
