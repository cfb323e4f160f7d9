#pragma once
/// \file se3.h
/// Rigid motions SE(3): poses, exponential and logarithm of body-frame twists, the 6×6 right
/// tangent operator and its inverse, adjoint and ad. Equation numbers refer to core/lie/lie.md.
///
/// Conventions (lie.md §6-§9):
///  - Pose X_AB = (R, p) in Drake's monogram notation: X_AB.R = R_AB (columns: B's axes in A),
///    X_AB.p = p_AB, short for p_AoBo_A (origin of B in A). A vector v_A is expressed in A.
///    As a 4×4 matrix [[R, p], [0, 1]]; X_AC = X_AB * X_BC; p_AQ = X_AB.act(p_BQ).
///  - a twist h = [u; θ] ∈ R⁶ is TRANSLATION FIRST, expressed in the body frame:
///    ĥ = [[θ̃, u], [0, 0]] and exp(h) = (exp(θ), T(θ)ᵀ u) (eq. 25), so u is not the
///    translation of exp(h) unless θ ∥ u or θ = 0.
///  - increments are right (body) increments, X ← X exp(Δh):  δp = R δu, δR = R δθ̃ (eq. 23),
///    and exp(h + δh) = exp(h) exp(T_SE3(h) δh) + O(δh²) (eq. 32).

#include "core/lie/so3.h"

namespace ff::lie {

using Vec6 = Eigen::Matrix<double, 6, 1>;
using Mat6 = Eigen::Matrix<double, 6, 6>;
using Mat4 = Eigen::Matrix4d;

/// Pose X_AB of frame B in frame A (eq. 20). Plain value type, 96 bytes, no heap.
struct Pose {
  Mat3 R = Mat3::Identity();  ///< X_AB.R = R_AB, orthonormal, det +1
  Vec3 p = Vec3::Zero();      ///< X_AB.p = p_AB = p_AoBo_A: origin of B expressed in A [m]

  static Pose Identity() { return Pose{}; }

  /// X_BA = X_AB⁻¹ = (R_ABᵀ, −R_ABᵀ p_AB) (eq. 22).
  Pose inverse() const { return Pose{R.transpose(), -(R.transpose() * p)}; }

  /// p_AQ = R_AB p_BQ + p_AB (eq. 22).
  Vec3 act(const Vec3& p_BQ) const { return R * p_BQ + p; }

  /// [[R, p], [0, 1]] (eq. 20).
  Mat4 matrix() const {
    Mat4 m = Mat4::Identity();
    m.topLeftCorner<3, 3>() = R;
    m.topRightCorner<3, 1>() = p;
    return m;
  }
};

/// X_AC = X_AB * X_BC = (R_AB R_BC, p_AB + R_AB p_BC) (eq. 21).
inline Pose operator*(const Pose& X_AB, const Pose& X_BC) {
  return Pose{X_AB.R * X_BC.R, X_AB.p + X_AB.R * X_BC.p};
}

/// Twist blocks: h = [u; θ] (translation first).
inline Vec3 twist_u(const Vec6& h) { return h.head<3>(); }
inline Vec3 twist_theta(const Vec6& h) { return h.tail<3>(); }
inline Vec6 make_twist(const Vec3& u, const Vec3& theta) {
  Vec6 h;
  h << u, theta;
  return h;
}

/// 4×4 ĥ = [[θ̃, u], [0, 0]] (eq. 24).
inline Mat4 hat_se3(const Vec6& h) {
  Mat4 m = Mat4::Zero();
  m.topLeftCorner<3, 3>() = hat(twist_theta(h));
  m.topRightCorner<3, 1>() = twist_u(h);
  return m;
}

/// Inverse of hat_se3 (eq. 24); reads the skew part of the rotation block.
inline Vec6 vee_se3(const Mat4& m) {
  return make_twist(m.topRightCorner<3, 1>(), vee(m.topLeftCorner<3, 3>()));
}

/// ad_h = [[θ̃, ũ], [0, θ̃]] (eq. 31): (ad_a b)^ = â b̂ − b̂ â.
inline Mat6 ad_se3(const Vec6& h) {
  const Mat3 th = hat(twist_theta(h));
  Mat6 A;
  A.topLeftCorner<3, 3>() = th;
  A.topRightCorner<3, 3>() = hat(twist_u(h));
  A.bottomLeftCorner<3, 3>().setZero();
  A.bottomRightCorner<3, 3>() = th;
  return A;
}

/// Ad_X = [[R_AB, p̃_AB R_AB], [0, R_AB]] (eq. 29) for X = X_AB: X exp(h) X⁻¹ = exp(Ad_X h).
/// Maps a twist in B coordinates to A coordinates.
inline Mat6 adjoint(const Pose& X_AB) {
  Mat6 A;
  A.topLeftCorner<3, 3>() = X_AB.R;
  A.topRightCorner<3, 3>() = hat(X_AB.p) * X_AB.R;
  A.bottomLeftCorner<3, 3>().setZero();
  A.bottomRightCorner<3, 3>() = X_AB.R;
  return A;
}

/// exp(h) = (exp(θ), T(θ)ᵀ u) (eqs. 25-26). One sin/cos pair.
inline Pose exp_se3(const Vec6& h) {
  const Vec3 u = twist_u(h), theta = twist_theta(h);
  const double phi = theta.norm();
  detail::Angle a;
  if (phi < detail::kTiny) {
    a.phi = phi;
    a.phi2 = phi * phi;
  } else {
    a = detail::Angle::of(phi);
  }
  const double k1 = detail::c1(a), k2 = detail::c2(a);
  Pose X;
  X.R = detail::rotation(theta, detail::c0(a), k1, a.phi2);
  // T(θ)ᵀ u = u + c1 θ×u + c2 θ×(θ×u), with θ×(θ×u) = θ(θ·u) − φ² u (eq. 26)
  X.p = (1.0 - k2 * a.phi2) * u + k1 * theta.cross(u) + (k2 * theta.dot(u)) * theta;
  return X;
}

/// log(X) = [T(θ)⁻ᵀ p; θ], θ = log(R), |θ| ≤ π (eq. 28). No transcendental call beyond atan2.
inline Vec6 log_se3(const Pose& X) {
  const auto lr = detail::log_so3_with_angle(X.R);
  const Vec3& theta = lr.theta;
  const double k5 = detail::c5(lr.angle);
  // T⁻ᵀ p = p − ½ θ×p + c5 θ×(θ×p)
  const Vec3 u = (1.0 - k5 * lr.angle.phi2) * X.p - 0.5 * theta.cross(X.p) +
                 (k5 * theta.dot(X.p)) * theta;
  return make_twist(u, theta);
}

/// T_SE3(h) = [[T(θ), T_uθ], [0, T(θ)]] (eqs. 32-35):
/// exp(h + δh) = exp(h) exp(T_SE3(h) δh) + O(δh²).
inline Mat6 tangent_se3(const Vec6& h) {
  const Vec3 u = twist_u(h), theta = twist_theta(h);
  const auto a = detail::Angle::of(theta.norm());
  const double k1 = detail::c1(a), k2 = detail::c2(a), k3 = detail::c3(a), k4 = detail::c4(a);
  const Mat3 th = hat(theta);
  const Mat3 tth = theta * theta.transpose();

  Mat3 T = k2 * tth - k1 * th;
  T.diagonal().array() += 1.0 - k2 * a.phi2;

  // T_uθ = −c1 ũ + c2 (uθᵀ + θuᵀ) + (θ·u)[c3 θ̃ + c4 θθᵀ − (2 c2 + c4 φ²) I] (eq. 35 with eq. 2)
  const double tu = theta.dot(u);
  Mat3 Tut = -k1 * hat(u) + k2 * (u * theta.transpose() + theta * u.transpose()) +
             tu * (k3 * th + k4 * tth);
  Tut.diagonal().array() -= tu * (2.0 * k2 + k4 * a.phi2);

  Mat6 Ts;
  Ts.topLeftCorner<3, 3>() = T;
  Ts.topRightCorner<3, 3>() = Tut;
  Ts.bottomLeftCorner<3, 3>().setZero();
  Ts.bottomRightCorner<3, 3>() = T;
  return Ts;
}

/// T_SE3(h)⁻¹ = [[T⁻¹, T⁻_uθ], [0, T⁻¹]] (eqs. 37-38); defined for |θ| < 2π.
inline Mat6 tangent_se3_inverse(const Vec6& h) {
  const Vec3 u = twist_u(h), theta = twist_theta(h);
  const auto a = detail::Angle::of(theta.norm());
  const double k5 = detail::c5(a), k6 = detail::c6(a);
  const Mat3 tth = theta * theta.transpose();

  Mat3 Ti = k5 * tth + 0.5 * hat(theta);
  Ti.diagonal().array() += 1.0 - k5 * a.phi2;

  // T⁻_uθ = ½ ũ + c5 (uθᵀ + θuᵀ) + (θ·u)[c6 θθᵀ − (2 c5 + c6 φ²) I] (eq. 38 with eq. 2)
  const double tu = theta.dot(u);
  Mat3 Tut = 0.5 * hat(u) + k5 * (u * theta.transpose() + theta * u.transpose()) + (tu * k6) * tth;
  Tut.diagonal().array() -= tu * (2.0 * k5 + k6 * a.phi2);

  Mat6 Ts;
  Ts.topLeftCorner<3, 3>() = Ti;
  Ts.topRightCorner<3, 3>() = Tut;
  Ts.bottomLeftCorner<3, 3>().setZero();
  Ts.bottomRightCorner<3, 3>() = Ti;
  return Ts;
}

}  // namespace ff::lie
