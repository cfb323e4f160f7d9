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
#include <vector>

#include "core/lie/se3.h"

namespace ff::shell {

namespace cb_detail {
template <class T>
struct Tables;  // the element's fixed points on one thickness interval (cb_shell.cpp)
}

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Vec24 = Eigen::Matrix<double, 24, 1>;
using Mat24 = Eigen::Matrix<double, 24, 24>;

/// X_WN: orientation (columns e1, e2, director) and position of a master node in W: the one pose
/// type of core/lie (R = R_WN, x = p_WN).
using NodePose = lie::Pose;
using ElementPoses = std::array<NodePose, 4>;  ///< counter-clockwise about the directors

/// One ply of a laminated section (laminate.md (L1)-(L2)), in its material axes: 1 along the
/// fibre, 2 across it in the ply's plane, 3 along the director. An isotropic ply has
/// e1 = e2 = E, g12 = g13 = g23 = E / (2 (1 + nu)), nu12 = nu.
struct Ply {
  double e1 = 1.0, e2 = 1.0, g12 = 0.5, g13 = 0.5, g23 = 0.5, nu12 = 0.0;
  double thickness = 0.0;  ///< h_k
  double angle = 0.0;      ///< theta_k [rad], about the director from the reference direction to the fibre
  double density = 0.0;    ///< rho_k (dynamics, gravity)
  /// Tsai-Wu strengths (L12), positive: Xt, Xc, Yt, Yc, S12; all zero: no failure index
  std::array<double, 5> strength{};
};

struct ShellSection {
  double youngs_modulus = 1.0;     ///< E
  double poisson_ratio = 0.0;      ///< nu
  double thickness = 0.1;          ///< h0 (constant); with plies, their sum
  double shear_factor = 5.0 / 6.0; ///< kappa of eq. (7), (L9)
  /// A laminated section: its plies from the bottom (the director's negative side) up
  /// (laminate.md (L6)); null: one isotropic layer of youngs_modulus and poisson_ratio.
  std::shared_ptr<const std::vector<Ply>> plies;
  /// The direction fibre angles are measured from (world), projected on each element's tangent
  /// plane (laminate.md section 2); zero: the element's own xi direction at its centre (a
  /// generator's u direction). Also the x1 axis of the stresses the element reports.
  Eigen::Vector3d reference_direction = Eigen::Vector3d::Zero();
};
/// One isotropic layer of thickness h (the tests' and benchmarks' usual section).
inline ShellSection isotropic_section(double youngs_modulus, double poisson_ratio, double thickness,
                                      double shear_factor = 5.0 / 6.0) {
  ShellSection s;
  s.youngs_modulus = youngs_modulus;
  s.poisson_ratio = poisson_ratio;
  s.thickness = thickness;
  s.shear_factor = shear_factor;
  return s;
}

/// The largest ply count a section may have (a fixed bound keeps the element's workspace fixed).
inline constexpr int kMaxPlies = 64;

using Vec5 = Eigen::Matrix<double, 5, 1>;

/// Stresses an engineer reads, recovered at an element's centre or a corner (laminate.md section 6). Section
/// axes: x1 the reference direction projected on the tangent plane, x3 the normal, x2 = x3 x x1.
/// Components of a station: [s11, s22, s12, s13, s23] (second Piola-Kirchhoff in the lamina
/// frame; equal to the Cauchy stress to first order in the strains).
struct ElementStress {
  std::array<Vec5, 3> surface;  ///< section axes at its bottom (zeta = -1), middle (0) and top (+1)
  Eigen::Vector3d N, M;         ///< resultants per unit length: N11 N22 N12, M11 M22 M12
  Eigen::Vector2d Q;            ///< transverse shear resultants Q1 Q2 per unit length
  int plies = 0;                ///< entries of ply and tsai_wu in use (0: an isotropic section)
  /// each ply in its fibre axes (1 fibre, 2 across): [s1, s2, t12, t13, t23] at its bottom, middle, top
  std::array<std::array<Vec5, 3>, kMaxPlies> ply;
  std::array<double, kMaxPlies> tsai_wu;  ///< (L12), the largest over the ply's stations; NaN without strengths
};

/// What the recovered-resultant error indicator needs of one element (error_indicator.md (Z1)-(Z3)):
/// the resultants at its 2 x 2 in-plane points in the element frame (second Piola-Kirchhoff, per
/// unit reference length), where those points are on the reference mid-surface, and the section's
/// compliance in the same frame.
struct ResultantSamples {
  /// columns t1, t2, t3 of the element frame on the reference (t1 the centre's G_xi direction)
  Eigen::Matrix3d frame;
  /// [N11 N22 N12 M11 M22 M12 Q1 Q2] at each in-plane point, element frame
  std::array<Eigen::Matrix<double, 8, 1>, 4> resultant;
  std::array<Eigen::Vector3d, 4> position;  ///< on the reference mid-surface
  std::array<double, 4> area;               ///< area element there (Gauss weight included)
  std::array<double, 4> xi, eta;            ///< the points' parent coordinates
  /// (Z1): blockdiag([A B; B D]^-1, A_s^-1), element frame
  Eigen::Matrix<double, 8, 8> compliance;
};

/// Effects of the element (scene "effects"): each switches a term of cb_shell.md.
struct ShellOptions {
  bool hr = true;                  ///< Hellinger-Reissner membrane, eqs. (9)-(11)
  bool ans = true;                 ///< assumed natural transverse shear, eq. (8)
  bool drilling = false;           ///< Fox-Simo drilling penalty, eqs. (12)-(14)
  double drilling_factor = 1e-3;   ///< c in gamma = c G h0, eq. (13)
};

/// The element, templated on its scalar only so that one evaluation can be run in counting
/// arithmetic (CountedDouble, count_element_flops below); the solver uses CbShellElement.
template <class Scalar>
class BasicCbShellElement {
 public:
  using Vector24 = Eigen::Matrix<Scalar, 24, 1>;
  using Matrix24 = Eigen::Matrix<Scalar, 24, 24>;

  BasicCbShellElement(const ElementPoses& reference, const ShellSection& section, const ShellOptions& options);
  /// The same element in another scalar type (every reference datum converted, no recomputation).
  template <class Other>
  explicit BasicCbShellElement(const BasicCbShellElement<Other>& other);

  /// Internal force (24) and, if `tangent` is non-null, the tangent (24 x 24), eqs. (15)-(17).
  void evaluate(const ElementPoses& current, Vector24& force, Matrix24* tangent) const;
  /// Strain energy (condensed HR functional when hr is on), for consistency checks.
  Scalar energy(const ElementPoses& current) const;
  /// Stresses and resultants at `current` (laminate.md section 6): at the element's centre (the
  /// mean over its 2 x 2 in-plane points), or with `corner` 0..3 at that corner (the bilinear
  /// field through the four points, extrapolated); the in-plane stress is the assumed field with
  /// `hr`, the transverse shear the tied one with `ans`: the stresses the element's energy uses.
  void stresses(const ElementPoses& current, ElementStress& out, int corner = -1) const;

  /// The resultants at the 2 x 2 in-plane points at `current`, with the reference geometry and
  /// the section compliance (error_indicator.md (Z1)-(Z3)), for the recovered-stress indicator.
  void resultant_samples(const ElementPoses& reference, const ElementPoses& current, ResultantSamples& out) const;

  const ShellOptions& options() const { return opt_; }
  const ShellSection& section() const { return sec_; }

 private:
  template <class>
  friend class BasicCbShellElement;
  using V3 = Eigen::Matrix<Scalar, 3, 1>;
  using M3 = Eigen::Matrix<Scalar, 3, 3>;
  // Reference-only data of the kernels, precomputed here (cb_shell.md, "Implementation notes").
  // Per layer (the whole section when isotropic, else one ply: laminate.md (L6)) the element keeps
  // what the force needs (about 2.6 kB, contiguous in one block for all layers); the tangent's
  // kernels live in one heap block (TangentData) that a force-only evaluation never touches, and
  // what is the same for every element with the same layer interval (shape derivatives at the
  // fixed points) is shared.
  static constexpr int kPoints = 8;  // per layer: 2 x 2 in plane x 2 through the layer
  struct SolidPoint {                              // force data of one integration point
    Scalar weight;                                 // Gauss weight x det J (reference volume)
    Eigen::Matrix<Scalar, 5, 1> ref_metric;        // G_i.G_j for xx, ee, xe, eta-zeta, xi-zeta
    M3 Qm;                                         // eq. (6): in-plane rows, columns xx ee xe
    Eigen::Matrix<Scalar, 2, 5> Qs;                // eq. (6): shear rows, columns xx ee xe ez xz
  };
  struct Layer {                                   // laminate.md (L6)-(L9)
    const cb_detail::Tables<Scalar>* tab;          // fixed points of [zeta_lo, zeta_hi] (shared)
    double zeta_lo, zeta_hi;                       // its interval of the thickness coordinate
    std::array<SolidPoint, kPoints> pts;
    std::array<std::array<Scalar, 4>, 2> tie_ref;  // G_i.G_zeta of the tied components [station][A..D]
    Eigen::Matrix<Scalar, 10, 10> h_inv;           // eq. (10), (L8): this layer's H^{-1}
    M3 Cm;                                         // eq. (7) / (L5): in-plane stiffness, element frame
    Eigen::Matrix<Scalar, 2, 2> Cs;                // eq. (7) / (L5), (L9): kappa x transverse shear stiffness
    Scalar fibre_angle;                            // psi: from the element's t1 to the fibre (0 isotropic)
  };
  struct DrillPoint {
    Scalar weight;                                 // Gauss weight x A
    Scalar inv2A;                                  // 1 / (2A)
    std::array<V3, 4> g1_local, g2_local;          // R0_I^T G_xi, R0_I^T G_eta
  };
  struct TangentData;                              // Ku, Kt, ANS rows, H^{-1} factor per layer (cb_shell.cpp)

  // the stresses the energy uses at each layer's points (cb_shell.cpp; double only)
  template <class Visit>
  void visit_layer_stresses(const ElementPoses& cur, Visit&& visit) const;
  Scalar solid_terms(const ElementPoses& cur, Vector24& f, Matrix24* K) const;
  Scalar drilling_terms(const ElementPoses& cur, Vector24& f, Matrix24* K) const;

  ShellSection sec_;
  ShellOptions opt_;
  std::vector<Layer> layers_;                      // bottom up
  std::array<Scalar, 6> p_coef_;                   // eq. (9): a1^2, b1^2, a1 b1, a2^2, b2^2, a2 b2
  Scalar reference_angle_ = 0.0;                   // phi: from the element's t1 to the section's x1
  Scalar gamma_ = 0.0;                             // eq. (13)
  std::shared_ptr<const TangentData> tan_;         // immutable, shared by copies
  std::array<DrillPoint, 4> drill_;
};

template <>
BasicCbShellElement<double>::BasicCbShellElement(const ElementPoses& reference, const ShellSection& section,
                                                 const ShellOptions& options);
using CbShellElement = BasicCbShellElement<double>;

/// Floating-point operations of one evaluation of `element` at `current` (cb_shell.md, "Flop
/// count"), counted by running the kernel in CountedDouble arithmetic; the counted force comes
/// back too, so a caller can check that the counted run computed what the solver computes.
struct ElementFlops {
  long long force = 0;          ///< force alone
  long long force_tangent = 0;  ///< force and tangent
  Vec24 counted_force;          ///< the force of the counted run, in double
  Mat24 counted_tangent;        ///< the tangent of the counted run, in double
};
ElementFlops count_element_flops(const CbShellElement& element, const ElementPoses& current);

}  // namespace ff::shell
