#pragma once
/// \file so3.h
/// Rotation group SO(3): hat/vee, exponential, logarithm, right tangent operator, its inverse
/// and its directional derivative. Equation numbers refer to core/lie/lie.md.
///
/// Conventions (lie.md §1, §4):
///  - a rotation vector θ ∈ R³ (radians) maps to R = exp(θ̃); φ = |θ|.
///  - increments are body-frame (right) increments: exp(θ + δθ) = exp(θ) exp(T(θ) δθ) + O(δθ²),
///    so T is the *right* tangent (right Jacobian), T(0) = I, T(θ)ᵀ = T(−θ).
///  - every function here is header-inline, allocation-free and calls at most one sin/cos pair.

#include <Eigen/Core>
#include <Eigen/Geometry>  // cross

#include <array>
#include <cmath>
#include <cstddef>

namespace ff::lie {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

/// Skew matrix ã with ã b = a × b (eq. 1). Generic in the scalar so that the shell kernel can
/// also run in counting arithmetic (core/shell/counted_scalar.h).
template <class Derived>
Eigen::Matrix<typename Derived::Scalar, 3, 3> hat(const Eigen::MatrixBase<Derived>& a) {
  static_assert(Derived::SizeAtCompileTime == 3, "hat takes a 3-vector");
  Eigen::Matrix<typename Derived::Scalar, 3, 3> m;
  m << 0.0, -a.z(), a.y(),  //
      a.z(), 0.0, -a.x(),   //
      -a.y(), a.x(), 0.0;
  return m;
}

/// Inverse of hat on the skew part of m: vee(ã) = a (eq. 1). The symmetric part is ignored.
inline Vec3 vee(const Mat3& m) {
  return 0.5 * Vec3(m(2, 1) - m(1, 2), m(0, 2) - m(2, 0), m(1, 0) - m(0, 1));
}

namespace detail {

/// Rotation angle φ with its square and the half-angle sine/cosine s = sin(φ/2), c = cos(φ/2).
/// Half angles give 1 − cos φ = 2s², 1 + cos φ = 2c², sin φ = 2sc without cancellation (eq. 5).
struct Angle {
  double phi = 0.0;
  double phi2 = 0.0;
  double s = 0.0;
  double c = 1.0;

  /// The one sin/cos pair of every exp/tangent call.
  static Angle of(double phi) {
    Angle a;
    a.phi = phi;
    a.phi2 = phi * phi;
    a.s = std::sin(0.5 * phi);
    a.c = std::cos(0.5 * phi);
    return a;
  }
};

template <std::size_t N>
constexpr double horner(const std::array<double, N>& k, double x) {
  double r = k[N - 1];
  for (std::size_t i = N - 1; i-- > 0;) r = r * x + k[i];
  return r;
}

constexpr double inv_factorial(int n) {
  double r = 1.0;
  for (int i = 2; i <= n; ++i) r /= i;
  return r;
}

// taylor coefficients in x = φ² of c2, c3, c4 (lie.md eqs. 40-42); N chosen so the first
// dropped term is < 1e-18 relative at the switch angle of table (44)
template <std::size_t N>
constexpr std::array<double, N> series_c2() {
  std::array<double, N> k{};
  for (std::size_t i = 0; i < N; ++i) k[i] = (i % 2 ? -1.0 : 1.0) * inv_factorial(2 * int(i) + 3);
  return k;
}
template <std::size_t N>
constexpr std::array<double, N> series_c3() {
  std::array<double, N> k{};
  for (std::size_t i = 0; i < N; ++i)
    k[i] = (i % 2 ? -1.0 : 1.0) * 2.0 * double(i + 1) * inv_factorial(2 * int(i) + 4);
  return k;
}
template <std::size_t N>
constexpr std::array<double, N> series_c4() {
  std::array<double, N> k{};
  for (std::size_t i = 0; i < N; ++i)
    k[i] = (i % 2 ? 1.0 : -1.0) * 2.0 * double(i + 1) * inv_factorial(2 * int(i) + 5);
  return k;
}

/// |B_2m| / (2m)! for m = 1..36 (B = Bernoulli numbers), computed in binary128 from the
/// recurrence Σ_{k=0}^{n} B_k / (k! (n−k+1)!) = 0; the coefficients of c5 and c6 (eq. 43).
inline constexpr std::array<double, 36> bernoulli_over_factorial = {
    8.33333333333333333e-02, 1.38888888888888889e-03, 3.30687830687830688e-05,
    8.26719576719576720e-07, 2.08767569878680990e-08, 5.28419013868749318e-10,
    1.33825365306846788e-11, 3.38968029632258287e-13, 8.58606205627784456e-15,
    2.17486869855806187e-16, 5.50900282836022952e-18, 1.39544646858125233e-19,
    3.53470703962946747e-21, 8.95351742703754685e-23, 2.26795245233768306e-24,
    5.74479066887220245e-26, 1.45517247561486490e-27, 3.68599494066531018e-29,
    9.33673425709504467e-31, 2.36502241570062993e-32, 5.99067176248213430e-34,
    1.51745488446829026e-35, 3.84375812545418823e-37, 9.73635307264669104e-39,
    2.46624704420068096e-40, 6.24707674182074369e-42, 1.58240302446449143e-43,
    4.00827368594893597e-45, 1.01530758555695563e-46, 2.57180415824187175e-48,
    6.51445603523381493e-50, 1.65013099068965246e-51, 4.17983062853947589e-53,
    1.05876346677029088e-54, 2.68187919126077067e-56, 6.79327935110742121e-58};

template <std::size_t N>
constexpr std::array<double, N> series_c5() {
  std::array<double, N> k{};
  for (std::size_t i = 0; i < N; ++i) k[i] = bernoulli_over_factorial[i];
  return k;
}
template <std::size_t N>
constexpr std::array<double, N> series_c6() {
  std::array<double, N> k{};
  for (std::size_t i = 0; i < N; ++i) k[i] = 2.0 * double(i + 1) * bernoulli_over_factorial[i + 1];
  return k;
}

// switch angles and term counts, table (44) of lie.md
inline constexpr double kTiny = 1e-4;  // c0, c1: 2 terms, dropped term < 1e-18 relative
inline constexpr double kSwitchC2 = 2.0;
inline constexpr double kSwitchC3 = 2.5;
inline constexpr double kSwitchC4 = 3.3;
inline constexpr double kSwitchC5 = 2.0;
inline constexpr double kSwitchC6 = 3.2;
inline constexpr auto kSeriesC2 = series_c2<12>();
inline constexpr auto kSeriesC3 = series_c3<13>();
inline constexpr auto kSeriesC4 = series_c4<14>();
inline constexpr auto kSeriesC5 = series_c5<18>();
inline constexpr auto kSeriesC6 = series_c6<34>();

/// c0 = sin φ / φ (eq. 4).
inline double c0(const Angle& a) {
  if (a.phi < kTiny) return 1.0 - a.phi2 / 6.0;
  return 2.0 * a.s * a.c / a.phi;
}
/// c1 = (1 − cos φ) / φ² (eq. 4).
inline double c1(const Angle& a) {
  if (a.phi < kTiny) return 0.5 - a.phi2 / 24.0;
  return 2.0 * a.s * a.s / a.phi2;
}
/// c2 = (φ − sin φ) / φ³ (eq. 13).
inline double c2(const Angle& a) {
  if (a.phi < kSwitchC2) return horner(kSeriesC2, a.phi2);
  return (a.phi - 2.0 * a.s * a.c) / (a.phi * a.phi2);
}
/// c3 = −c1'(φ)/φ = (2 c1 − c0) / φ² (eq. 17).
inline double c3(const Angle& a) {
  if (a.phi < kSwitchC3) return horner(kSeriesC3, a.phi2);
  return (2.0 * c1(a) - c0(a)) / a.phi2;
}
/// c4 = c2'(φ)/φ = (c1 − 3 c2) / φ² (eq. 17).
inline double c4(const Angle& a) {
  if (a.phi < kSwitchC4) return horner(kSeriesC4, a.phi2);
  return (c1(a) - 3.0 * c2(a)) / a.phi2;
}
/// c5 = (1 − (φ/2) cot(φ/2)) / φ² (eq. 15); singular at φ = 2π.
inline double c5(const Angle& a) {
  if (a.phi < kSwitchC5) return horner(kSeriesC5, a.phi2);
  return 1.0 / a.phi2 - a.c / (2.0 * a.phi * a.s);
}
/// c6 = c5'(φ)/φ (eq. 19); singular at φ = 2π.
inline double c6(const Angle& a) {
  if (a.phi < kSwitchC6) return horner(kSeriesC6, a.phi2);
  return (a.phi2 / (4.0 * a.s * a.s) + a.phi * a.c / (2.0 * a.s) - 2.0) / (a.phi2 * a.phi2);
}

/// Rodrigues from precomputed coefficients: R = (1 − c1 φ²) I + c0 θ̃ + c1 θθᵀ (eq. 6).
inline Mat3 rotation(const Vec3& theta, double k0, double k1, double phi2) {
  Mat3 R = k1 * theta * theta.transpose();
  R.diagonal().array() += 1.0 - k1 * phi2;
  R += k0 * hat(theta);
  return R;
}

/// log_so3 with the angle it found (half angles rebuilt from the matrix, eq. 10).
struct LogResult {
  Vec3 theta;
  Angle angle;
};

inline LogResult log_so3_with_angle(const Mat3& R) {
  const Vec3 w = vee(R);  // sin φ n (eq. 7)
  const double sin_raw = w.norm();
  const double cos_raw = 0.5 * (R.trace() - 1.0);
  const double phi = std::atan2(sin_raw, cos_raw);  // in [0, π]
  // normalized pair, robust to a slightly non-orthonormal R
  const double r = std::hypot(sin_raw, cos_raw);
  const double sn = r > 0.0 ? sin_raw / r : 0.0;
  const double cs = r > 0.0 ? cos_raw / r : 1.0;

  LogResult out;
  out.angle.phi = phi;
  out.angle.phi2 = phi * phi;
  if (cs >= 0.0) {
    // skew branch (eq. 8): relative error ≈ eps / sin φ ≤ eps·√2 for φ ≤ π/2
    out.theta = sin_raw > 0.0 ? Vec3((phi / sin_raw) * w) : w;
    out.angle.c = std::sqrt(0.5 * (1.0 + cs));
    out.angle.s = 0.5 * sn / out.angle.c;
  } else {
    // symmetric branch (eq. 9): ½(R + Rᵀ) − cos φ I = (1 − cos φ) n nᵀ; error ≈ eps/(1 − cos φ)
    Mat3 B = 0.5 * (R + R.transpose());
    B.diagonal().array() -= cos_raw;
    int k = 0;
    B.diagonal().maxCoeff(&k);
    Vec3 n = B.col(k).normalized();
    if (n.dot(w) < 0.0) n = -n;  // at exactly π, n·w = 0 and either sign is a valid log
    out.theta = phi * n;
    out.angle.s = std::sqrt(0.5 * (1.0 - cs));
    out.angle.c = 0.5 * sn / out.angle.s;
  }
  return out;
}

}  // namespace detail

/// R = exp(θ̃), Rodrigues (eqs. 3-6). One sin/cos pair (none for φ < 1e-4).
inline Mat3 exp_so3(const Vec3& theta) {
  const double phi = theta.norm();
  detail::Angle a;
  if (phi < detail::kTiny) {
    a.phi = phi;
    a.phi2 = phi * phi;
  } else {
    a = detail::Angle::of(phi);
  }
  return detail::rotation(theta, detail::c0(a), detail::c1(a), a.phi2);
}

/// θ = log(R) with |θ| ≤ π (eqs. 7-9). R must be a rotation (orthonormality errors of a few
/// eps are tolerated). At exactly |θ| = π both ±θ are logarithms; the one returned has
/// n·vee(R − Rᵀ) ≥ 0, else the largest component of n positive.
inline Vec3 log_so3(const Mat3& R) { return detail::log_so3_with_angle(R).theta; }

/// Right tangent T(θ) = I − c1 θ̃ + c2 θ̃² (eqs. 11-13): exp(θ+δθ) = exp(θ) exp(T(θ)δθ) + O(δθ²).
inline Mat3 tangent_so3(const Vec3& theta) {
  const auto a = detail::Angle::of(theta.norm());
  const double k2 = detail::c2(a);
  // θ̃² = θθᵀ − φ² I (eq. 2)
  Mat3 T = k2 * theta * theta.transpose();
  T.diagonal().array() += 1.0 - k2 * a.phi2;
  T -= detail::c1(a) * hat(theta);
  return T;
}

/// T(θ)⁻¹ = I + ½ θ̃ + c5 θ̃² (eq. 15); defined for |θ| < 2π.
inline Mat3 tangent_so3_inverse(const Vec3& theta) {
  const auto a = detail::Angle::of(theta.norm());
  const double k5 = detail::c5(a);
  Mat3 Ti = k5 * theta * theta.transpose();
  Ti.diagonal().array() += 1.0 - k5 * a.phi2;
  Ti += 0.5 * hat(theta);
  return Ti;
}

/// ∂/∂θ [T(θ) a] (3×3), eqs. (16), (18): T(θ + δθ) a = T(θ) a + M δθ + O(δθ²).
inline Mat3 tangent_so3_directional(const Vec3& theta, const Vec3& a) {
  const auto g = detail::Angle::of(theta.norm());
  const double k1 = detail::c1(g), k2 = detail::c2(g), k3 = detail::c3(g), k4 = detail::c4(g);
  const Vec3 txa = theta.cross(a);
  const double ta = theta.dot(a);
  // θ̃ã = aθᵀ − (θ·a) I (eq. 2); θ̃²a = θ(θ·a) − φ² a
  Mat3 M = k1 * hat(a) - k2 * (a * theta.transpose() + hat(txa));
  M.diagonal().array() += k2 * ta;
  M += (k3 * txa + k4 * (ta * theta - g.phi2 * a)) * theta.transpose();
  return M;
}

}  // namespace ff::lie
