#include "core/shell/cb_shell.h"

#include <type_traits>

#include "core/shell/counted_scalar.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <mutex>
#include <stdexcept>

namespace ff::shell {

namespace {
using Mat8 = Eigen::Matrix<double, 8, 8>;
using Mat83 = Eigen::Matrix<double, 8, 3>;
using Mat38 = Eigen::Matrix<double, 3, 8>;
using Vec10 = Eigen::Matrix<double, 10, 1>;
using Mat20 = Eigen::Matrix<double, 20, 20>;
using Mat20x5 = Eigen::Matrix<double, 20, 5>;
// the kernels' types in the element's scalar T (double, or CountedDouble to count flops)
template <class T, int R, int C>
using Mat = Eigen::Matrix<T, R, C>;

constexpr double kXiNode[4] = {-1.0, 1.0, 1.0, -1.0};
constexpr double kEtaNode[4] = {-1.0, -1.0, 1.0, 1.0};
// covariant components kept (eq. 6): xx, ee, xe, ez, xz; E_zz has no weight in eq. (6)
constexpr int kPair[5][2] = {{0, 0}, {1, 1}, {0, 1}, {1, 2}, {0, 2}};
constexpr int kEtaZeta = 3, kXiZeta = 4;
// reference data of a disabled effect are not built; NaN instead, so that any evaluation of a
// disabled term (even one multiplied by zero) would show as a non-finite force (test_cb_shell)
constexpr double kUnused = std::numeric_limits<double>::quiet_NaN();

using lie::hat;  // [a]x, the one skew matrix of core/lie

// bilinear quad functions and derivatives at (xi, eta)
void quad_shape(double xi, double eta, Eigen::Vector4d& N, Eigen::Vector4d& dxi, Eigen::Vector4d& deta) {
  for (int i = 0; i < 4; ++i) {
    N[i] = 0.25 * (1 + kXiNode[i] * xi) * (1 + kEtaNode[i] * eta);
    dxi[i] = 0.25 * kXiNode[i] * (1 + kEtaNode[i] * eta);
    deta[i] = 0.25 * kEtaNode[i] * (1 + kXiNode[i] * xi);
  }
}

// trilinear derivatives of the slaves of master I (N_I (1 + s zeta) / 2), summed over s = +-1
// (rows I) and weighted by s (rows 4 + I): g_i = sum_I phi(I, i) x_I + (h0/2) phi(4 + I, i) d_I
Mat83 master_derivatives(double xi, double eta, double zeta) {
  Eigen::Vector4d N, dxi, deta;
  quad_shape(xi, eta, N, dxi, deta);
  Mat83 phi;
  for (int I = 0; I < 4; ++I) {
    phi.row(I) << dxi[I], deta[I], 0.0;
    phi.row(4 + I) << zeta * dxi[I], zeta * deta[I], N[I];
  }
  return phi;
}

// columns x_I and (h0/2) d_I, eq. (1)
template <class T>
Mat<T, 3, 8> node_columns(const ElementPoses& p, T hh) {
  Mat<T, 3, 8> X;
  for (int I = 0; I < 4; ++I) {
    X.col(I) = p[I].p.template cast<T>();
    X.col(4 + I) = hh * p[I].R.col(2).template cast<T>();
  }
  return X;
}

// K = Y Y^T for Y 20 x N (column-major): upper 4 x 4 tiles, mirrored (the material stiffness is
// symmetric; this is the largest product of the element)
template <int N, typename Derived, class T>
void gram20(const Eigen::MatrixBase<Derived>& Y, Mat<T, 20, 20>& K) {
  static_assert(Derived::RowsAtCompileTime == 20 && Derived::ColsAtCompileTime == N);
  const T* data = Y.derived().data();
  const Eigen::Index stride = Y.derived().outerStride();
  for (int jb = 0; jb < 20; jb += 4)
    for (int ib = 0; ib <= jb; ib += 4) {
      T acc[4][4] = {};
      for (int k = 0; k < N; ++k) {
        const T* y = data + stride * k;
        for (int c = 0; c < 4; ++c)
          for (int r = 0; r < 4; ++r) acc[c][r] += y[ib + r] * y[jb + c];
      }
      for (int c = 0; c < 4; ++c)
        for (int r = 0; r < 4; ++r) K(ib + r, jb + c) = K(jb + c, ib + r) = acc[c][r];
    }
}

// master rows from the kernels of one point: u rows (R_I^T g) Ku_I, theta rows
// [-(R_I^T g) row 1; (R_I^T g) row 0] Kt_I (theta = (h0/2) e3~ R_I^T sum_s s b, eq. 2)
template <int NC, class T>
void master_rows(const std::array<Mat<T, 3, 3>, 4>& Rt, const Mat<T, 3, 3>& g, const std::array<Mat<T, 3, 7>, 4>& Ku,
                 const std::array<Mat<T, 3, 7>, 4>& Kt, Mat<T, 20, NC>& B) {
  for (int I = 0; I < 4; ++I) {
    const Mat<T, 3, 3> gl = Rt[I].lazyProduct(g);
    Mat<T, 2, 3> glr;
    glr << -gl.row(1), gl.row(0);
    B.template block<3, NC>(5 * I, 0).noalias() = gl.lazyProduct(Ku[I].template leftCols<NC>());
    B.template block<2, NC>(5 * I + 3, 0).noalias() = glr.lazyProduct(Kt[I].template leftCols<NC>());
  }
}

// symmetric 3 x 3 S with sum_c v_c (a_i b_j + a_j b_i) / 2 = a^T S b over covariant components c
template <class T>
[[gnu::always_inline]] inline Mat<T, 3, 3> covariant_matrix(const Mat<T, 5, 1>& v, bool with_shear) {
  Mat<T, 3, 3> S = Mat<T, 3, 3>::Zero();
  for (int c = 0; c < (with_shear ? 5 : 3); ++c) {
    const int i = kPair[c][0], j = kPair[c][1];
    if (i == j) S(i, i) += v[c];
    else S(i, j) += 0.5 * v[c], S(j, i) += 0.5 * v[c];
  }
  return S;
}

}  // namespace

// What is the same for every element with the same layer interval [lo, hi] of the thickness
// coordinate: the fixed points and the shape derivatives there (master_derivatives, eq. 5 of the
// tied components, the drilling points' quad functions). Shared by all such elements, so the
// per-element data a force evaluation streams stay small. An isotropic section is one layer on
// [-1, 1]; a laminate has one per ply (laminate.md (L6)): 2 Gauss points on its own interval.
namespace cb_detail {
constexpr int kPoints = 8;
template <class T = double>
struct SolidConst {
  T xi, eta, zeta;  // zeta: the section's thickness coordinate of the point
  T zeta_hat;       // the layer's own coordinate (+-1/sqrt 3): the assumed stress's, (L7)
  int layer;        // thickness station (tying values)
  Mat<T, 8, 3> phi;  // rows I: sum over the two slaves of master I of dN/d(xi, eta, zeta); rows 4 + I:
                   // the same weighted by s, so g = [x_I, h0/2 d_I] * phi (eqs. 1, 3)
};
template <class T = double>
struct TyingConst {  // eq. (8) at one thickness station
  Mat<T, 8, 3> phi;  // as SolidConst::phi
  Mat<T, 8, 8> M;    // eq. (5) of the tied component in phi's basis
  int i;             // 1 (eta-zeta) or 0 (xi-zeta)
};
template <class T = double>
struct DrillConst {
  Mat<T, 4, 1> N, dNxi, dNeta;
};
template <class T = double>
struct Tables {
  std::array<SolidConst<T>, kPoints> pts;
  std::array<std::array<TyingConst<T>, 4>, 2> tying;  // [station][A, B, C, D]
  std::array<DrillConst<T>, 4> drill;
  T gpts[2];                // the layer's Gauss points, -+1/sqrt 3
  T zeta[2];                // the stations in the section's coordinate, (L6)
  T zeta_mid, zeta_half;    // zeta = zeta_mid + zeta_half zeta_hat; the Gauss weight is zeta_half
};
}  // namespace cb_detail

namespace {
using cb_detail::kPoints;
using cb_detail::DrillConst;
using cb_detail::SolidConst;
using cb_detail::Tables;
using cb_detail::TyingConst;

Tables<> make_tables(double lo, double hi) {
  Tables<> t;
  const double gp = 1.0 / std::sqrt(3.0);
  t.gpts[0] = -gp, t.gpts[1] = gp;
  t.zeta_mid = 0.5 * (lo + hi), t.zeta_half = 0.5 * (hi - lo);
  for (int l = 0; l < 2; ++l) t.zeta[l] = t.zeta_mid + t.zeta_half * t.gpts[l];  // [-1, 1]: exactly -+gp
  int k = 0;
  for (int l = 0; l < 2; ++l)
    for (int jy = 0; jy < 2; ++jy)
      for (int jx = 0; jx < 2; ++jx, ++k) {
        SolidConst<>& p = t.pts[k];
        p.xi = t.gpts[jx];
        p.eta = t.gpts[jy];
        p.zeta = t.zeta[l];
        p.zeta_hat = t.gpts[l];
        p.layer = l;
        p.phi = master_derivatives(p.xi, p.eta, p.zeta);
      }
  // tying points of eq. (8): A(-1,0), B(0,-1), C(1,0), D(0,1) at each station
  const double tp[4][2] = {{-1, 0}, {0, -1}, {1, 0}, {0, 1}};
  for (int l = 0; l < 2; ++l)
    for (int q = 0; q < 4; ++q) {
      TyingConst<>& c = t.tying[l][q];
      c.phi = master_derivatives(tp[q][0], tp[q][1], t.zeta[l]);
      c.i = (q == 0 || q == 2) ? 1 : 0;
      c.M = 0.5 * (c.phi.col(c.i) * c.phi.col(2).transpose() + c.phi.col(2) * c.phi.col(c.i).transpose());
    }
  k = 0;
  for (int jy = 0; jy < 2; ++jy)
    for (int jx = 0; jx < 2; ++jx, ++k) {
      Eigen::Vector4d N, dxi, deta;
      quad_shape(t.gpts[jx], t.gpts[jy], N, dxi, deta);
      t.drill[k] = {N, dxi, deta};
    }
  return t;
}

// the tables in another scalar: the same numbers (a conversion, no arithmetic)
template <class T>
Tables<T> convert_tables(const Tables<>& d) {
  Tables<T> t;
  for (int k = 0; k < kPoints; ++k)
    t.pts[k] = {d.pts[k].xi, d.pts[k].eta, d.pts[k].zeta, d.pts[k].zeta_hat, d.pts[k].layer,
                d.pts[k].phi.template cast<T>()};
  for (int l = 0; l < 2; ++l)
    for (int q = 0; q < 4; ++q) {
      const TyingConst<>& c = d.tying[l][q];
      t.tying[l][q] = {c.phi.template cast<T>(), c.M.template cast<T>(), c.i};
    }
  for (int k = 0; k < 4; ++k)
    t.drill[k] = {d.drill[k].N.template cast<T>(), d.drill[k].dNxi.template cast<T>(), d.drill[k].dNeta.template cast<T>()};
  for (int l = 0; l < 2; ++l) t.gpts[l] = d.gpts[l], t.zeta[l] = d.zeta[l];
  t.zeta_mid = d.zeta_mid, t.zeta_half = d.zeta_half;
  return t;
}

// The tables of the layer [lo, hi], made once per interval and scalar and kept for the process
// (a laminate's plies repeat across its elements; element construction is not a hot path).
template <class T = double>
const Tables<T>* layer_tables(double lo, double hi) {
  static std::mutex mutex;
  static std::map<std::pair<double, double>, std::unique_ptr<const Tables<T>>> made;
  const std::lock_guard<std::mutex> lock(mutex);
  std::unique_ptr<const Tables<T>>& t = made[{lo, hi}];
  if (!t) {
    if constexpr (std::is_same_v<T, double>) t = std::make_unique<const Tables<>>(make_tables(lo, hi));
    else t = std::make_unique<const Tables<T>>(convert_tables<T>(*layer_tables<double>(lo, hi)));
  }
  return t.get();
}
// the whole section's interval [-1, 1]: the isotropic layer, and the drilling points (in-plane
// only, the same for every interval)
template <class T = double>
const Tables<T>& section_tables() {
  static const Tables<T>* t = layer_tables<T>(-1.0, 1.0);
  return *t;
}

// Lamina strains of a point from its base vectors g, eqs. (3), (6), with the tied transverse
// components of eq. (8) when `tied` (the tying values of the point's station) is given
template <class T, class Point>
[[gnu::always_inline]] inline void point_strains(const Mat<T, 3, 3>& g, const Point& p, const SolidConst<T>& pc,
                                                 const T* tied, Mat<T, 3, 1>& em, Mat<T, 2, 1>& es) {
  T e[5];
  for (int c = 0; c < 5; ++c) e[c] = 0.5 * (g.col(kPair[c][0]).dot(g.col(kPair[c][1])) - p.ref_metric[c]);
  if (tied) {  // eq. (8)
    e[kEtaZeta] = 0.5 * (1 - pc.xi) * tied[0] + 0.5 * (1 + pc.xi) * tied[2];
    e[kXiZeta] = 0.5 * (1 - pc.eta) * tied[1] + 0.5 * (1 + pc.eta) * tied[3];
  }
  // Q e as columns times the strain scalars (a strain vector stored whole and read back in halves
  // stalled the store forwarding)
  em.noalias() = p.Qm.col(0) * e[0] + p.Qm.col(1) * e[1] + p.Qm.col(2) * e[2];
  es.noalias() = p.Qs.col(0) * e[0] + p.Qs.col(1) * e[1] + p.Qs.col(2) * e[2] + p.Qs.col(3) * e[3] + p.Qs.col(4) * e[4];
}

// g is affine in zeta at every in-plane point q: g_j = X_x D_j + zeta X_d D_j (j = xi, eta),
// g_zeta = X_d N, with D, N the same in every layer (rows I of phi, and N in rows 4 + I); the
// tied components likewise at A..D, eq. (8). The zeta-free parts, formed once per evaluation
// for every layer (column by column, as 3-vectors: whole 3 x 2 temporaries were written and read
// back in differently split packets, which stalls the store forwarding).
template <class T>
struct ZetaFreeBases {
  Mat<T, 3, 1> in[4][2], th[4][2], z[4];
  Mat<T, 3, 1> tie_x[4], tie_d[4], tie_z[4];
  ZetaFreeBases(const Mat<T, 3, 8>& X, const Tables<T>& section, bool ans) {
    for (int q = 0; q < 4; ++q) {
      const Mat<T, 8, 3>& phi = section.pts[q].phi;
      for (int j = 0; j < 2; ++j) {
        in[q][j].noalias() = X.template leftCols<4>().lazyProduct(phi.template block<4, 1>(0, j));
        th[q][j].noalias() = X.template rightCols<4>().lazyProduct(phi.template block<4, 1>(0, j));
      }
      z[q].noalias() = X.template rightCols<4>().lazyProduct(phi.template block<4, 1>(4, 2));
    }
    for (int t = 0; t < 4 && ans; ++t) {
      const Mat<T, 8, 3>& phi = section.tying[0][t].phi;
      const int i = section.tying[0][t].i;
      tie_x[t].noalias() = X.template leftCols<4>().lazyProduct(phi.col(i).template head<4>());
      tie_d[t].noalias() = X.template rightCols<4>().lazyProduct(phi.col(i).template head<4>());
      tie_z[t].noalias() = X.template rightCols<4>().lazyProduct(phi.col(2).template tail<4>());
    }
  }
  void at(int q, const T& zeta, Mat<T, 3, 3>& g) const {
    for (int j = 0; j < 2; ++j) g.col(j).noalias() = in[q][j] + zeta * th[q][j];
    g.col(2) = z[q];
  }
  /// the tied component of tying point t at zeta, (3) with (8)'s base vectors
  T tied(int t, const T& zeta, const T& reference) const {
    return 0.5 * ((tie_x[t] + zeta * tie_d[t]).dot(tie_z[t]) - reference);
  }
};

// P-hat of eq. (9) at a point from the element's coefficients a1^2, b1^2, a1 b1, a2^2, b2^2, a2 b2
template <class T>
Mat<T, 3, 10> p_hat(const std::array<T, 6>& c, const SolidConst<T>& p) {
  Mat<T, 3, 5> P;
  P << 1, 0, 0, c[0] * p.eta, c[3] * p.xi, 0, 1, 0, c[1] * p.eta, c[4] * p.xi, 0, 0, 1, c[2] * p.eta, c[5] * p.xi;
  Mat<T, 3, 10> Ph;
  Ph << P, p.zeta_hat * P;  // the layer's own coordinate, (L7)
  return Ph;
}
}  // namespace

// The tangent-only kernels (cb_shell.md, "Implementation notes"), one heap block per element
template <class Scalar>
struct BasicCbShellElement<Scalar>::TangentData {
  using Mat37 = Eigen::Matrix<Scalar, 3, 7>;
  struct Point {
    // master rows of node I from R_I^T g: u part Ku, theta part Kt; columns: with hr the five
    // columns of w B_m^T P (eq. 11, per station) then the two scaled shear rows; without hr the
    // three membrane rows times sqrt(w) L_c (C_m = L_c L_c^T), the two shear rows, two unused
    std::array<Mat37, 4> Ku, Kt;
    Eigen::Matrix<Scalar, 4, 2> ans;  // tying rows into the shear rows, eq. (8)
  };
  struct Layer {
    std::array<Point, kPoints> pts;
    Eigen::Matrix<Scalar, 10, 10> h_inv_factor;  // L with L L^T = the layer's h_inv
  };
  std::vector<Layer> layers;
};

namespace {
// A layer's stiffness in the element frame (t1 = the centre's G_xi direction): the isotropic
// section by eq. (7), a ply by (L1), (L3)-(L5) turned by psi from t1 to its fibre, and kappa (L9).
struct LayerMaterial {
  double lo, hi;          // its interval of the thickness coordinate, (L6)
  Eigen::Matrix3d Cm;
  Eigen::Matrix2d Cs;
  double fibre_angle;
};

std::vector<LayerMaterial> layer_materials(const ShellSection& sec, double reference_angle) {
  std::vector<LayerMaterial> out;
  if (!sec.plies) {
    const double E = sec.youngs_modulus, nu = sec.poisson_ratio, cm = E / (1.0 - nu * nu);
    LayerMaterial m{-1.0, 1.0, Eigen::Matrix3d::Zero(), Eigen::Matrix2d::Zero(), 0.0};
    m.Cm(0, 0) = m.Cm(1, 1) = cm;
    m.Cm(0, 1) = m.Cm(1, 0) = cm * nu;
    m.Cm(2, 2) = cm * 0.5 * (1.0 - nu);
    m.Cs(0, 0) = m.Cs(1, 1) = sec.shear_factor * (E / (2.0 * (1.0 + nu)));
    out.push_back(m);
    return out;
  }
  const std::vector<Ply>& plies = *sec.plies;
  if (plies.empty() || static_cast<int>(plies.size()) > kMaxPlies)
    throw std::invalid_argument("CB shell: a laminated section needs 1 to " + std::to_string(kMaxPlies) + " plies");
  double below = 0.0;  // thickness under the ply
  for (std::size_t k = 0; k < plies.size(); ++k) {
    const Ply& p = plies[k];
    const double nu21 = p.nu12 * p.e2 / p.e1, den = 1.0 - p.nu12 * nu21;
    if (!(p.e1 > 0 && p.e2 > 0 && p.g12 > 0 && p.g13 > 0 && p.g23 > 0 && den > 0 && p.thickness > 0))  // (L2)
      throw std::invalid_argument("CB shell: ply " + std::to_string(k + 1) + " is not a stable material");
    Eigen::Matrix3d Q = Eigen::Matrix3d::Zero();  // (L1)
    Q(0, 0) = p.e1 / den, Q(1, 1) = p.e2 / den, Q(0, 1) = Q(1, 0) = p.nu12 * p.e2 / den, Q(2, 2) = p.g12;
    const double psi = reference_angle + p.angle, c = std::cos(psi), s = std::sin(psi);
    Eigen::Matrix3d T;  // (L3): material strains from element-frame strains (engineering shear)
    T << c * c, s * s, c * s, s * s, c * c, -c * s, -2 * c * s, 2 * c * s, c * c - s * s;
    Eigen::Matrix2d R;  // (L4)
    R << c, s, -s, c;
    LayerMaterial m;
    // (L6): zeta_{k+1} = zeta_k + 2 h_k / h; the top ply ends at 1 exactly
    m.lo = -1.0 + 2.0 * below / sec.thickness;
    below += p.thickness;
    m.hi = k + 1 == plies.size() ? 1.0 : -1.0 + 2.0 * below / sec.thickness;
    m.Cm = T.transpose() * Q * T;                                                          // (L5)
    m.Cs = sec.shear_factor * (R.transpose() * Eigen::Vector2d(p.g13, p.g23).asDiagonal() * R);  // (L5), (L9)
    m.fibre_angle = psi;
    out.push_back(m);
  }
  return out;
}

// L with L L^T = A for a symmetric positive definite 2 x 2 (written out: for a diagonal A it is
// exactly the square roots, so an isotropic layer's shear rows are scaled as by sqrt(w kappa G))
Eigen::Matrix2d cholesky2(const Eigen::Matrix2d& A) {
  Eigen::Matrix2d L = Eigen::Matrix2d::Zero();
  L(0, 0) = std::sqrt(A(0, 0));
  L(1, 0) = A(1, 0) / L(0, 0);
  L(1, 1) = std::sqrt(A(1, 1) - L(1, 0) * L(1, 0));
  return L;
}
}  // namespace

// The reference data are computed in double only (other scalars convert a built element).
template <>
BasicCbShellElement<double>::BasicCbShellElement(const ElementPoses& ref, const ShellSection& sec,
                                                 const ShellOptions& opt)
    : sec_(sec), opt_(opt) {
  const double h = sec.thickness, hh = 0.5 * h;
  const Mat38 X0 = node_columns(ref, hh);
  // centre frame for the assumed stress, eq. (9)
  const Mat3 Gc = X0 * master_derivatives(0, 0, 0);
  const Vec3 t1c = Gc.col(0).normalized();
  const Vec3 t3c = Gc.col(0).cross(Gc.col(1)).normalized();
  const Vec3 t2c = t3c.cross(t1c);
  const double a1 = Gc.col(0).dot(t1c), b1 = Gc.col(0).dot(t2c), a2 = Gc.col(1).dot(t1c), b2 = Gc.col(1).dot(t2c);
  if (!(Gc.col(0).cross(Gc.col(1)).norm() > 0)) throw std::invalid_argument("CB shell: degenerate element");
  p_coef_ = {a1 * a1, b1 * b1, a1 * b1, a2 * a2, b2 * b2, a2 * b2};
  // the section's x1: its reference direction projected on the tangent plane (laminate.md section 2)
  if (sec.reference_direction.squaredNorm() > 0) {
    const Vec3& r = sec.reference_direction;
    const Vec3 rt = r - r.dot(t3c) * t3c;
    if (!(rt.norm() >= 1e-3 * r.norm()))
      throw std::invalid_argument("CB shell: the reference direction is parallel to the element's normal");
    reference_angle_ = std::atan2(rt.dot(t2c), rt.dot(t1c));
  }
  const std::vector<LayerMaterial> materials = layer_materials(sec, reference_angle_);
  // eq. (13); a laminate's G is the thickness mean of its plies' in-plane shear moduli
  double shear_modulus = sec.youngs_modulus / (2.0 * (1.0 + sec.poisson_ratio));
  if (sec.plies) {
    shear_modulus = 0.0;
    for (const Ply& p : *sec.plies) shear_modulus += p.g12 * p.thickness / h;
  }
  gamma_ = opt.drilling_factor * shear_modulus * h;

  auto td = std::make_shared<TangentData>();
  layers_.resize(materials.size());
  td->layers.resize(materials.size());
  for (std::size_t layer_index = 0; layer_index < materials.size(); ++layer_index) {
    const LayerMaterial& mat = materials[layer_index];
    Layer& layer = layers_[layer_index];
    typename TangentData::Layer& tl = td->layers[layer_index];
    const Tables<>& tab = *layer_tables(mat.lo, mat.hi);
    layer.tab = &tab;
    layer.zeta_lo = mat.lo, layer.zeta_hi = mat.hi;
    layer.Cm = mat.Cm;
    layer.Cs = mat.Cs;
    layer.fibre_angle = mat.fibre_angle;
    const Eigen::Matrix3d Cm_inv = mat.Cm.inverse();
    const Eigen::Matrix3d Lc = mat.Cm.llt().matrixL();
    Eigen::Matrix<double, 10, 10> H = Eigen::Matrix<double, 10, 10>::Zero();
    for (int k = 0; k < kPoints; ++k) {
      const SolidConst<>& pc = tab.pts[k];
      SolidPoint& p = layer.pts[k];
      TangentData::Point& pt = tl.pts[k];
      const Mat3 J = X0 * pc.phi;  // columns G_xi, G_eta, G_zeta
      const double detJ = J.determinant();
      if (!(detJ > 0)) throw std::invalid_argument("CB shell: inverted or degenerate element (det J <= 0)");
      p.weight = detJ * tab.zeta_half;  // the layer's Gauss weight, (L6)
      for (int c = 0; c < 5; ++c) p.ref_metric[c] = J.col(kPair[c][0]).dot(J.col(kPair[c][1]));
      // lamina frame: normal at the point, t1 from the centre frame (common in-plane orientation)
      const Vec3 t3 = J.col(0).cross(J.col(1)).normalized();
      const Vec3 t1 = (t1c - t1c.dot(t3) * t3).normalized();
      const Vec3 t2 = t3.cross(t1);
      const Mat3 dual = J.inverse();  // rows: contravariant G^i
      Mat3 c;                         // c(i, k) = G^i . t_k
      for (int i = 0; i < 3; ++i) c.row(i) << dual.row(i).dot(t1), dual.row(i).dot(t2), dual.row(i).dot(t3);
      // eq. (6): rows eps11, eps22, 2eps12, 2eps13, 2eps23. G^zeta is parallel to t3, so the
      // in-plane rows have no ez, xz (and no row has a zz) weight: those entries are round-off
      const int kl[5][2] = {{0, 0}, {1, 1}, {0, 1}, {0, 2}, {1, 2}};
      Eigen::Matrix<double, 5, 5> Q;
      for (int r = 0; r < 5; ++r) {
        const int kk = kl[r][0], ll = kl[r][1];
        const double eng = kk == ll ? 1.0 : 2.0;
        for (int q = 0; q < 5; ++q) {
          const int i = kPair[q][0], j = kPair[q][1];
          const double coef = i == j ? c(i, kk) * c(j, ll) : c(i, kk) * c(j, ll) + c(j, kk) * c(i, ll);
          Q(r, q) = eng * coef;
        }
      }
      p.Qm = Q.topLeftCorner<3, 3>();
      p.Qs = Q.bottomRows<2>();
      Eigen::Matrix<double, 3, 5> P;
      if (opt.hr) {
        const Eigen::Matrix<double, 3, 10> Ph = p_hat(p_coef_, pc);
        P = Ph.leftCols<5>();
        H.noalias() += p.weight * Ph.transpose() * Cm_inv * Ph;  // eq. (10), (L8)
      }

      // B rows of eps (eq. 4 through 6) on master increments: row r at slave A is
      // sum_ij dN_A,i S_r(i, j) g_j; summed over the two slaves of master I and rotated to its
      // frame this is (R_I^T g) Su (u part) and, weighted by s, the theta part (speed notes).
      // The shear rows are scaled by L_s, L_s L_s^T = w C_s (sqrt(w kappa G) when isotropic)
      const Eigen::Matrix2d Ls = cholesky2(p.weight * mat.Cs);
      Eigen::Matrix<double, 3, 5> Su, St;  // columns: sum_i phi(I, i) S_r(i, :) per row r
      for (int I = 0; I < 4; ++I) {
        for (int r = 0; r < 5; ++r) {
          Vec5 q = Q.row(r).transpose();
          if (r < 3) q.tail<2>().setZero();
          const Mat3 S = covariant_matrix(q, !(opt.ans && r >= 3));
          Su.col(r) = S * pc.phi.row(I).transpose();
          St.col(r) = hh * (S * pc.phi.row(4 + I).transpose());
        }
        for (Eigen::Matrix<double, 3, 5>* M : {&Su, &St}) {
          const Vec3 s0 = M->col(3), s1 = M->col(4);
          M->col(3) = Ls(0, 0) * s0 + Ls(1, 0) * s1;
          M->col(4) = Ls(1, 1) * s1;
        }
        TangentData::Mat37& ku = pt.Ku[I];
        TangentData::Mat37& kt = pt.Kt[I];
        ku.setZero();
        kt.setZero();
        if (opt.hr) {  // this point's share of G^T (first five columns of P-hat), eq. (11)
          ku.leftCols<5>() = p.weight * Su.leftCols<3>() * P;
          kt.leftCols<5>() = p.weight * St.leftCols<3>() * P;
          ku.rightCols<2>() = Su.rightCols<2>();
          kt.rightCols<2>() = St.rightCols<2>();
        } else {      // K = Y Y^T with the membrane rows times sqrt(w) L_c
          ku.leftCols<3>() = Su.leftCols<3>() * (std::sqrt(p.weight) * Lc);
          kt.leftCols<3>() = St.leftCols<3>() * (std::sqrt(p.weight) * Lc);
          ku.middleCols<2>(3) = Su.rightCols<2>();
          kt.middleCols<2>(3) = St.rightCols<2>();
        }
      }
      // eq. (8): tying points A, B, C, D feed ez (A, C) and xz (B, D) of the shear rows
      const double w[4] = {0.5 * (1 - pc.xi), 0.5 * (1 - pc.eta), 0.5 * (1 + pc.xi), 0.5 * (1 + pc.eta)};
      if (!opt.ans) pt.ans.setConstant(kUnused);
      for (int t = 0; t < 4 && opt.ans; ++t) {
        const int comp = (t == 0 || t == 2) ? kEtaZeta : kXiZeta;
        const double row0 = p.Qs(0, comp) * Ls(0, 0) + p.Qs(1, comp) * Ls(1, 0), row1 = p.Qs(1, comp) * Ls(1, 1);
        pt.ans(t, 0) = row0 * w[t];
        pt.ans(t, 1) = row1 * w[t];
      }
    }
    if (opt.hr) {
      layer.h_inv = H.inverse();
      tl.h_inv_factor = layer.h_inv.llt().matrixL();
    } else {
      layer.h_inv.setConstant(kUnused);
      tl.h_inv_factor.setConstant(kUnused);
    }
    // reference values of the tied components, eq. (8)
    for (auto& station : layer.tie_ref) station.fill(kUnused);
    for (int l = 0; l < 2 && opt.ans; ++l)
      for (int t = 0; t < 4; ++t) {
        const TyingConst<>& tc = tab.tying[l][t];
        const Mat3 G = X0 * tc.phi;
        layer.tie_ref[l][t] = G.col(tc.i).dot(G.col(2));
      }
  }
  tan_ = std::move(td);

  // drilling points, eq. (12)
  const Tables<>& tab = section_tables();
  for (DrillPoint& d : drill_) {
    d.weight = d.inv2A = kUnused;
    d.g1_local.fill(Vec3::Constant(kUnused));
    d.g2_local.fill(Vec3::Constant(kUnused));
  }
  for (int k = 0; k < 4 && opt.drilling; ++k) {
    const DrillConst<>& dc = tab.drill[k];
    DrillPoint& d = drill_[k];
    Vec3 Gx = Vec3::Zero(), Ge = Vec3::Zero();
    for (int I = 0; I < 4; ++I) Gx += dc.dNxi[I] * ref[I].p, Ge += dc.dNeta[I] * ref[I].p;
    const double A = Gx.cross(Ge).norm();
    d.weight = A;
    d.inv2A = 0.5 / A;
    for (int I = 0; I < 4; ++I) {
      d.g1_local[I] = ref[I].R.transpose() * Gx;
      d.g2_local[I] = ref[I].R.transpose() * Ge;
    }
  }
}

// Solid part (eqs. 3-11) mapped to master DoFs (eqs. 15, 16) without forming slave matrices:
// force from the stress vectors g Sigma (eq. 4), geometric stiffness from the 8 x 8 scalar
// matrix of eq. (5) in the (sum, s-weighted) slave basis, material stiffness K = Y Y^T with Y
// the scaled master B rows (and H^{-1/2} G for the assumed stress). See cb_shell.md, speed notes.
// Layer by layer (laminate.md (L6)-(L8)): each has its stations, stiffness and assumed stress;
// the force, the geometric matrix and the material stiffness are sums over the layers.
template <class Scalar>
Scalar BasicCbShellElement<Scalar>::solid_terms(const ElementPoses& cur, Vector24& F, Matrix24* K) const {
  using Vec3 = Mat<Scalar, 3, 1>;
  using Mat3 = Mat<Scalar, 3, 3>;
  using Mat38 = Mat<Scalar, 3, 8>;
  using Mat8 = Mat<Scalar, 8, 8>;
  using Vec5 = Mat<Scalar, 5, 1>;
  using Vec10 = Mat<Scalar, 10, 1>;
  using Mat20 = Mat<Scalar, 20, 20>;
  using Mat20x5 = Mat<Scalar, 20, 5>;
  const Scalar hh = 0.5 * sec_.thickness;
  const TangentData* td = K ? tan_.get() : nullptr;  // only the tangent reads its kernels
  const Mat38 X = node_columns(cur, hh);
  std::array<Mat3, 4> Rt;
  for (int I = 0; I < 4; ++I) Rt[I] = cur[I].R.transpose().template cast<Scalar>();

  const ZetaFreeBases<Scalar> bases(X, section_tables<Scalar>(), opt_.ans);
  const int shear_col = opt_.hr ? 10 : 24;
  Scalar energy = 0.0;
  Mat38 Fg = Mat38::Zero();  // columns: sum over s of slave forces of I, and weighted by s
  // eq. (5) weighted by stresses in the basis of phi: rows I of phi are (D_I, 0), rows 4 + I are
  // (zeta D_I, N_I), so the 8 x 8 matrix is [[A0, A1], [A1, A2]] + the N terms
  Mat<Scalar, 4, 4> A0, A1, A2, V1, V2;
  if (K) A0.setZero(), A1.setZero(), A2.setZero(), V1.setZero(), V2.setZero();
  Scalar sig_tie[kMaxPlies][2][4];  // tied stresses per layer, station, tying point
  Mat20 Km, Km_layer;               // material stiffness on the 5 bending DoFs per node
  const int layer_count = static_cast<int>(layers_.size());
  for (int li = 0; li < layer_count; ++li) {
    const Layer& L = layers_[li];
    const Tables<Scalar>& tab = *L.tab;
    const typename TangentData::Layer* tl = td ? &td->layers[li] : nullptr;
    // the layer's stations: sum_l zeta_l x_l = zm (x0 + x1) + zd (x1 - x0), and
    // sum_l zeta_l^2 x_l = (zm^2 + zd^2)(x0 + x1) + 2 zm zd (x1 - x0); zm = 0 for [-1, 1]
    const Scalar zm = tab.zeta_mid, zd = tab.zeta[1] - tab.zeta_mid;
    const Scalar zsq = zm * zm + zd * zd, zcross = 2.0 * zm * zd;

    // tying values and their master B rows, eq. (8)
    Scalar e_tie[2][4] = {};
    Vec3 g_tie[2][4][2];  // g_i, g_zeta
    Eigen::Matrix<Scalar, 20, 4> B_tie[2];
    if (opt_.ans)
      for (int l = 0; l < 2; ++l)
        for (int t = 0; t < 4; ++t) {
          g_tie[l][t][0].noalias() = bases.tie_x[t] + tab.zeta[l] * bases.tie_d[t];
          g_tie[l][t][1] = bases.tie_z[t];
          const TyingConst<Scalar>& tp = tab.tying[l][t];
          const Vec3 &gi = g_tie[l][t][0], &gz = g_tie[l][t][1];
          e_tie[l][t] = 0.5 * (gi.dot(gz) - L.tie_ref[l][t]);
          if (!K) continue;
          for (int I = 0; I < 4; ++I) {
            const Vec3 gzl = Rt[I] * gz;
            const Scalar gx = Rt[I].row(0).dot(gi), gy = Rt[I].row(1).dot(gi);
            B_tie[l].template block<3, 1>(5 * I, t) = (0.5 * tp.phi(I, tp.i)) * gzl;
            const Scalar wx = 0.5 * (tp.phi(4 + I, tp.i) * gzl.x() + tp.phi(4 + I, 2) * gx);
            const Scalar wy = 0.5 * (tp.phi(4 + I, tp.i) * gzl.y() + tp.phi(4 + I, 2) * gy);
            B_tie[l](5 * I + 3, t) = -hh * wy;
            B_tie[l](5 * I + 4, t) = hh * wx;
          }
        }

    // strains at the points; B rows when a tangent is wanted
    Eigen::Matrix<Scalar, 20, 40> Y;  // K_material = Y Y^T (first 26 columns with hr)
    Mat20x5 G_layer[2];                // G^T per station (hr), eq. (11)
    if (K && opt_.hr) G_layer[0].setZero(), G_layer[1].setZero();
    std::array<Mat3, kPoints> g;
    std::array<Vec3, kPoints> em;
    std::array<Mat<Scalar, 2, 1>, kPoints> es;
    Vec10 gv = Vec10::Zero();
    for (int k = 0; k < kPoints; ++k) bases.at(k % 4, tab.pts[k].zeta, g[k]);
    for (int k = 0; k < kPoints; ++k) {
      const SolidPoint& p = L.pts[k];
      const SolidConst<Scalar>& pc = tab.pts[k];
      point_strains(g[k], p, pc, opt_.ans ? e_tie[pc.layer] : nullptr, em[k], es[k]);
      if (opt_.hr) {  // eq. (10): w P-hat^T em, with P-hat = [P, zeta-hat P] and P = [I, c eta, c' xi] of (9)
        const Vec3& m = em[k];
        Mat<Scalar, 5, 1> pe;
        pe << m[0], m[1], m[2], pc.eta * (p_coef_[0] * m[0] + p_coef_[1] * m[1] + p_coef_[2] * m[2]),
            pc.xi * (p_coef_[3] * m[0] + p_coef_[4] * m[1] + p_coef_[5] * m[2]);
        for (int c = 0; c < 5; ++c) {
          const Scalar wpe = p.weight * pe[c];
          gv[c] += wpe;
          gv[5 + c] += pc.zeta_hat * wpe;
        }
      }
      if (!K) continue;
      const typename TangentData::Point& pt = tl->pts[k];
      if (opt_.hr) {
        Eigen::Matrix<Scalar, 20, 7> B;
        master_rows<7>(Rt, g[k], pt.Ku, pt.Kt, B);
        G_layer[pc.layer] += B.template leftCols<5>();
        if (opt_.ans) B.template rightCols<2>().noalias() += B_tie[pc.layer].lazyProduct(pt.ans);
        Y.template middleCols<2>(shear_col + 2 * k) = B.template rightCols<2>();
      } else {
        Eigen::Matrix<Scalar, 20, 5> B;
        master_rows<5>(Rt, g[k], pt.Ku, pt.Kt, B);
        if (opt_.ans) B.template rightCols<2>().noalias() += B_tie[pc.layer].lazyProduct(pt.ans);
        Y.template middleCols<2>(shear_col + 2 * k) = B.template rightCols<2>();
        Y.template middleCols<3>(3 * k) = B.template leftCols<3>();
      }
    }
    Vec10 beta = Vec10::Zero();  // read only with hr (zero keeps the compiler from guessing)
    if (opt_.hr) {
      beta.noalias() = L.h_inv.lazyProduct(gv);  // eq. (10), (L8)
      energy += 0.5 * gv.dot(beta);
    }

    // stresses: force and the scalar geometric matrix, eqs. (4), (5), (11)
    Scalar(&st_layer)[2][4] = sig_tie[li];
    for (auto& station : st_layer)
      for (Scalar& v : station) v = 0.0;
    std::array<Mat3, kPoints> S, T;  // covariant stress matrix (weighted) and stress vectors g S
    for (int k = 0; k < kPoints; ++k) {
      const SolidPoint& p = L.pts[k];
      const SolidConst<Scalar>& pc = tab.pts[k];
      Vec3 Sm;
      if (opt_.hr) {  // assumed stress at the point, P-hat beta = P (beta_0:5 + zeta-hat beta_5:10), eq. (9)
        const Mat<Scalar, 5, 1> b = beta.template head<5>() + pc.zeta_hat * beta.template tail<5>();
        const Scalar b3 = pc.eta * b[3], b4 = pc.xi * b[4];
        Sm << b[0] + p_coef_[0] * b3 + p_coef_[3] * b4, b[1] + p_coef_[1] * b3 + p_coef_[4] * b4,
            b[2] + p_coef_[2] * b3 + p_coef_[5] * b4;
      } else {
        Sm.noalias() = L.Cm * em[k];
        energy += 0.5 * p.weight * em[k].dot(Sm);
      }
      const Mat<Scalar, 2, 1> Ss = L.Cs * es[k];
      energy += 0.5 * p.weight * es[k].dot(Ss);
      Vec5 sig = p.Qs.transpose().lazyProduct(Ss);
      sig.template head<3>().noalias() += p.Qm.transpose().lazyProduct(Sm);
      sig *= p.weight;  // covariant stress x weight
      if (opt_.ans) {
        Scalar* st = st_layer[pc.layer];
        st[0] += 0.5 * (1 - pc.xi) * sig[kEtaZeta];
        st[2] += 0.5 * (1 + pc.xi) * sig[kEtaZeta];
        st[1] += 0.5 * (1 - pc.eta) * sig[kXiZeta];
        st[3] += 0.5 * (1 + pc.eta) * sig[kXiZeta];
      }
      // stress vectors T = g S with S = covariant_matrix(sig) written out (its (2, 2) entry is 0):
      // forming S in memory first and reading it back whole stalled the store forwarding
      const Scalar s0 = sig[0], s1 = sig[1], h2 = 0.5 * sig[2];
      const Scalar h3 = opt_.ans ? Scalar(0) : 0.5 * sig[3], h4 = opt_.ans ? Scalar(0) : 0.5 * sig[4];
      T[k].col(0).noalias() = s0 * g[k].col(0) + h2 * g[k].col(1) + h4 * g[k].col(2);
      T[k].col(1).noalias() = h2 * g[k].col(0) + s1 * g[k].col(1) + h3 * g[k].col(2);
      T[k].col(2).noalias() = h4 * g[k].col(0) + h3 * g[k].col(1);
      if (K) S[k] = covariant_matrix(sig, !opt_.ans);  // the geometric matrix reads S itself
    }
    // per in-plane point (the layer's two stations): T phi^T summed over the stations is
    // [(T0 + T1)_xy D^T, sum zeta T_xy D^T + (T0 + T1)_z N^T], and the geometric 4 x 4 blocks
    // D (sum zeta^j S_xy) D^T
    for (int q = 0; q < 4; ++q) {
      const Mat<Scalar, 8, 3>& phi = tab.pts[q].phi;
      const auto D = phi.template topLeftCorner<4, 2>();
      // column by column as 3-vectors, for the store forwarding (as g above)
      for (int j = 0; j < 2; ++j) {
        const Vec3 tsum = T[q].col(j) + T[q + 4].col(j);
        const Vec3 tmom = zm * tsum + zd * (T[q + 4].col(j) - T[q].col(j));
        Fg.template leftCols<4>().noalias() += tsum.lazyProduct(D.col(j).transpose());
        Fg.template rightCols<4>().noalias() += tmom.lazyProduct(D.col(j).transpose());
      }
      const Vec3 tz = T[q].col(2) + T[q + 4].col(2);
      Fg.template rightCols<4>().noalias() += tz.lazyProduct(phi.template block<4, 1>(4, 2).transpose());
      if (!K) continue;
      const Mat<Scalar, 2, 2> Ssum = S[q].template topLeftCorner<2, 2>() + S[q + 4].template topLeftCorner<2, 2>();
      const Mat<Scalar, 2, 2> Sdiff = S[q + 4].template topLeftCorner<2, 2>() - S[q].template topLeftCorner<2, 2>();
      const Mat<Scalar, 2, 2> Smom = zm * Ssum + zd * Sdiff;
      const Mat<Scalar, 2, 2> Ssq = zsq * Ssum + zcross * Sdiff;
      A0.noalias() += D.lazyProduct(Ssum.lazyProduct(D.transpose()));
      A1.noalias() += D.lazyProduct(Smom.lazyProduct(D.transpose()));
      A2.noalias() += D.lazyProduct(Ssq.lazyProduct(D.transpose()));
      if (!opt_.ans) {  // S(0:2, 2) with phi(4 + J, 2) = N_J
        const auto N = phi.template block<4, 1>(4, 2);
        const Mat<Scalar, 2, 1> vsum = S[q].template block<2, 1>(0, 2) + S[q + 4].template block<2, 1>(0, 2);
        const Mat<Scalar, 2, 1> vdiff = S[q + 4].template block<2, 1>(0, 2) - S[q].template block<2, 1>(0, 2);
        V1.noalias() += (D * vsum) * N.transpose();
        V2.noalias() += (D * (zm * vsum + zd * vdiff)) * N.transpose();
      }
    }
    // tying forces 1/2 s (g_zeta phi_i^T + g_i phi_zeta^T), eqs. (4), (8), per layer: phi_i
    // is (d, zeta d) and phi_zeta (0, N) with d, N the same at both stations, and g_zeta too
    if (opt_.ans)
      for (int t = 0; t < 4; ++t) {
        const TyingConst<Scalar>& tp = tab.tying[0][t];
        const auto d = tp.phi.col(tp.i).template head<4>();
        const auto N = tp.phi.col(2).template tail<4>();
        const Scalar s0 = 0.5 * st_layer[0][t], s1 = 0.5 * st_layer[1][t];
        const Vec3& gz = g_tie[0][t][1];
        const Vec3 gz_sum = (s0 + s1) * gz, gz_mom = (zm * (s0 + s1) + zd * (s1 - s0)) * gz;
        const Vec3 gi_sum = s0 * g_tie[0][t][0] + s1 * g_tie[1][t][0];
        Fg.template leftCols<4>().noalias() += gz_sum.lazyProduct(d.transpose());
        Fg.template rightCols<4>().noalias() += gz_mom.lazyProduct(d.transpose());
        Fg.template rightCols<4>().noalias() += gi_sum.lazyProduct(N.transpose());
      }
    if (!K) continue;
    // the layer's material stiffness, summed over the layers (the first one written in place)
    Mat20& Kl = li == 0 ? Km : Km_layer;
    if (opt_.hr) {
      Eigen::Matrix<Scalar, 20, 10> Gt;
      Gt.template leftCols<5>() = G_layer[0] + G_layer[1];
      Gt.template rightCols<5>() = tab.pts[0].zeta_hat * G_layer[0] + tab.pts[kPoints - 1].zeta_hat * G_layer[1];
      const Eigen::Matrix<Scalar, 10, 10>& Lh = tl->h_inv_factor;
      for (int j = 0; j < 10; ++j) {  // W = G^T L, L lower triangular: W W^T = G^T H^{-1} G
        Y.col(j) = Lh(j, j) * Gt.col(j);
        for (int i = j + 1; i < 10; ++i) Y.col(j) += Lh(i, j) * Gt.col(i);
      }
      gram20<26>(Y.template leftCols<26>(), Kl);
    } else {
      gram20<40>(Y, Kl);
    }
    if (li > 0) Km += Km_layer;
  }

  // master force, eq. (15): F_u = R^T sum f, F_theta = (h0/2) e3~ R^T sum s f
  std::array<Vec3, 4> fu, fs;
  for (int I = 0; I < 4; ++I) {
    fu[I].noalias() = Rt[I].lazyProduct(Fg.col(I));
    fs[I].noalias() = Rt[I].lazyProduct(Fg.col(4 + I));
    F.template segment<3>(6 * I) = fu[I];
    F.template segment<3>(6 * I + 3) << -hh * fs[I].y(), hh * fs[I].x(), 0.0;
  }
  if (!K) return energy;

  Mat8 Gb;
  Gb.template topLeftCorner<4, 4>() = A0;
  Gb.template topRightCorner<4, 4>() = A1 + V1;
  Gb.template bottomLeftCorner<4, 4>() = A1 + V1.transpose();
  Gb.template bottomRightCorner<4, 4>() = A2 + V2 + V2.transpose();
  if (opt_.ans)  // eq. (5) of the tied components, eq. (8)
    for (int li = 0; li < layer_count; ++li) {
      const Tables<Scalar>& tab = *layers_[li].tab;
      for (int t = 0; t < 4; ++t) Gb.noalias() += sig_tie[li][0][t] * tab.tying[0][t].M + sig_tie[li][1][t] * tab.tying[1][t].M;
    }
  // geometric stiffness and the variation of T, eqs. (15), (16), node block by node block
  const Scalar hh2 = hh * hh;
  for (int I = 0; I < 4; ++I)
    for (int J = 0; J < 4; ++J) {
      const Mat3 Rij = Rt[I] * cur[J].R.template cast<Scalar>();
      const Scalar g00 = Gb(I, J), g01 = Gb(I, 4 + J), g10 = Gb(4 + I, J), g11 = Gb(4 + I, 4 + J);
      auto blk = K->template block<6, 6>(6 * I, 6 * J);
      blk.template topLeftCorner<3, 3>() = Km.template block<3, 3>(5 * I, 5 * J) + g00 * Rij;
      // -(h0/2) g01 R_ij e3~ and (h0/2) g10 e3~ R_ij
      blk.template block<3, 1>(0, 3) = Km.template block<3, 1>(5 * I, 5 * J + 3) - (hh * g01) * Rij.col(1);
      blk.template block<3, 1>(0, 4) = Km.template block<3, 1>(5 * I, 5 * J + 4) + (hh * g01) * Rij.col(0);
      blk.template block<1, 3>(3, 0) = Km.template block<1, 3>(5 * I + 3, 5 * J) - (hh * g10) * Rij.row(1);
      blk.template block<1, 3>(4, 0) = Km.template block<1, 3>(5 * I + 4, 5 * J) + (hh * g10) * Rij.row(0);
      // -(h0/2)^2 g11 e3~ R_ij e3~
      blk(3, 3) = Km(5 * I + 3, 5 * J + 3) + hh2 * g11 * Rij(1, 1);
      blk(3, 4) = Km(5 * I + 3, 5 * J + 4) - hh2 * g11 * Rij(1, 0);
      blk(4, 3) = Km(5 * I + 4, 5 * J + 3) - hh2 * g11 * Rij(0, 1);
      blk(4, 4) = Km(5 * I + 4, 5 * J + 4) + hh2 * g11 * Rij(0, 0);
      blk.col(5).setZero();
      blk.row(5).template head<5>().setZero();
    }
  const Mat3 e3x = hat(Vec3::UnitZ());
  for (int I = 0; I < 4; ++I) {
    const Mat3 fl = hat(fs[I]);
    K->template block<3, 3>(6 * I, 6 * I + 3) += hat(fu[I]);
    K->template block<3, 3>(6 * I + 3, 6 * I + 3) += hh * e3x * fl;
  }
  return energy;
}

// eqs. (12)-(14), (17); the second-variation terms are summed over the points first (they are
// linear in the point data) and rotated once per node pair
template <class Scalar>
Scalar BasicCbShellElement<Scalar>::drilling_terms(const ElementPoses& cur, Vector24& f, Matrix24* K) const {
  using Vec3 = Mat<Scalar, 3, 1>;
  using Mat3 = Mat<Scalar, 3, 3>;
  Scalar energy = 0.0;
  Eigen::Matrix<Scalar, 24, 4> c, c_scaled;  // local gradients of omega per point, eq. (14)
  Vec3 v_cross[4][4];                        // (theta_I, u_J) blocks before R_I^T R_J
  Mat3 k_tt[4];                              // (theta_I, theta_I), eq. (17)
  Vec3 p_ut[4];                              // (u_I, theta_I) = hat(sum p_x)
  if (K)
    for (int I = 0; I < 4; ++I) {
      k_tt[I].setZero();
      p_ut[I].setZero();
      for (int J = 0; J < 4; ++J) v_cross[I][J].setZero();
    }
  for (int q = 0; q < 4; ++q) {
    const DrillPoint& d = drill_[q];
    const DrillConst<Scalar>& dc = section_tables<Scalar>().drill[q];
    Vec3 gx = Vec3::Zero(), ge = Vec3::Zero(), abar = Vec3::Zero(), bbar = Vec3::Zero();
    for (int I = 0; I < 4; ++I) {
      gx += dc.dNxi[I] * cur[I].p.template cast<Scalar>();
      ge += dc.dNeta[I] * cur[I].p.template cast<Scalar>();
      abar += dc.N[I] * (cur[I].R.template cast<Scalar>() * d.g1_local[I]);
      bbar += dc.N[I] * (cur[I].R.template cast<Scalar>() * d.g2_local[I]);
    }
    const Scalar omega = d.inv2A * (abar.dot(ge) - bbar.dot(gx));  // eq. (12)
    energy += 0.5 * gamma_ * d.weight * omega * omega;              // eq. (13)
    const Scalar scale = gamma_ * d.weight, so = scale * omega;
    for (int I = 0; I < 4; ++I) {
      const Mat3 Rt = cur[I].R.transpose().template cast<Scalar>();
      const Vec3 px = Rt * (d.inv2A * (dc.dNeta[I] * abar - dc.dNxi[I] * bbar));
      const Vec3 pa = Rt * (d.inv2A * dc.N[I] * ge);
      const Vec3 pb = Rt * (-d.inv2A * dc.N[I] * gx);
      c.template block<3, 1>(6 * I, q) = px;
      c.template block<3, 1>(6 * I + 3, q) = d.g1_local[I].cross(pa) + d.g2_local[I].cross(pb);
      if (!K) continue;
      // second variations of the primitives at fixed local directions, eq. (17)
      k_tt[I] += so * (pa * d.g1_local[I].transpose() + pb * d.g2_local[I].transpose());
      k_tt[I].diagonal().array() -= so * (pa.dot(d.g1_local[I]) + pb.dot(d.g2_local[I]));
      p_ut[I] += so * px;
      // primitive cross terms a_I / b_I with x_J
      for (int J = 0; J < 4; ++J)
        v_cross[I][J] += (so * d.inv2A * dc.N[I]) * (dc.dNeta[J] * d.g1_local[I] - dc.dNxi[J] * d.g2_local[I]);
    }
    f.noalias() += so * c.col(q);
    c_scaled.col(q) = scale * c.col(q);
  }
  if (!K) return energy;
  K->noalias() += c.lazyProduct(c_scaled.transpose());
  for (int I = 0; I < 4; ++I) {
    for (int J = 0; J < 4; ++J) {
      const Mat3 blk = hat(v_cross[I][J]) * (cur[I].R.transpose().template cast<Scalar>() * cur[J].R.template cast<Scalar>());
      K->template block<3, 3>(6 * I + 3, 6 * J) += blk;
      K->template block<3, 3>(6 * J, 6 * I + 3) += blk.transpose();
    }
    K->template block<3, 3>(6 * I + 3, 6 * I + 3) += k_tt[I];
    K->template block<3, 3>(6 * I, 6 * I + 3) += hat(p_ut[I]);
  }
  return energy;
}

template <class Scalar>
void BasicCbShellElement<Scalar>::evaluate(const ElementPoses& cur, Vector24& F, Matrix24* K) const {
  solid_terms(cur, F, K);
  if (opt_.drilling) drilling_terms(cur, F, K);
}

template <class Scalar>
Scalar BasicCbShellElement<Scalar>::energy(const ElementPoses& cur) const {
  Vector24 f;
  Scalar e = solid_terms(cur, f, nullptr);
  if (opt_.drilling) e += drilling_terms(cur, f, nullptr);
  return e;
}

// Converting copy: every reference datum in the other scalar (a conversion, no arithmetic).
template <class Scalar>
template <class Other>
BasicCbShellElement<Scalar>::BasicCbShellElement(const BasicCbShellElement<Other>& o)
    : sec_(o.sec_), opt_(o.opt_), reference_angle_(Scalar(o.reference_angle_)), gamma_(Scalar(o.gamma_)) {
  for (int c = 0; c < 6; ++c) p_coef_[c] = Scalar(o.p_coef_[c]);
  auto td = std::make_shared<TangentData>();
  layers_.resize(o.layers_.size());
  td->layers.resize(o.layers_.size());
  for (std::size_t li = 0; li < o.layers_.size(); ++li) {
    const auto& ol = o.layers_[li];
    Layer& l = layers_[li];
    l.tab = layer_tables<Scalar>(ol.zeta_lo, ol.zeta_hi);
    l.zeta_lo = ol.zeta_lo, l.zeta_hi = ol.zeta_hi;
    for (int k = 0; k < kPoints; ++k) {
      l.pts[k].weight = Scalar(ol.pts[k].weight);
      l.pts[k].ref_metric = ol.pts[k].ref_metric.template cast<Scalar>();
      l.pts[k].Qm = ol.pts[k].Qm.template cast<Scalar>();
      l.pts[k].Qs = ol.pts[k].Qs.template cast<Scalar>();
    }
    for (int s = 0; s < 2; ++s)
      for (int t = 0; t < 4; ++t) l.tie_ref[s][t] = Scalar(ol.tie_ref[s][t]);
    l.h_inv = ol.h_inv.template cast<Scalar>();
    l.Cm = ol.Cm.template cast<Scalar>();
    l.Cs = ol.Cs.template cast<Scalar>();
    l.fibre_angle = Scalar(ol.fibre_angle);
    const auto& otl = o.tan_->layers[li];
    auto& tl = td->layers[li];
    for (int k = 0; k < kPoints; ++k) {
      for (int I = 0; I < 4; ++I) {
        tl.pts[k].Ku[I] = otl.pts[k].Ku[I].template cast<Scalar>();
        tl.pts[k].Kt[I] = otl.pts[k].Kt[I].template cast<Scalar>();
      }
      tl.pts[k].ans = otl.pts[k].ans.template cast<Scalar>();
    }
    tl.h_inv_factor = otl.h_inv_factor.template cast<Scalar>();
  }
  tan_ = std::move(td);
  for (int q = 0; q < 4; ++q) {
    drill_[q].weight = Scalar(o.drill_[q].weight);
    drill_[q].inv2A = Scalar(o.drill_[q].inv2A);
    for (int I = 0; I < 4; ++I) {
      drill_[q].g1_local[I] = o.drill_[q].g1_local[I].template cast<Scalar>();
      drill_[q].g2_local[I] = o.drill_[q].g2_local[I].template cast<Scalar>();
    }
  }
}

template class BasicCbShellElement<double>;
// the counting instance: only what count_element_flops runs
template BasicCbShellElement<CountedDouble>::BasicCbShellElement(const BasicCbShellElement<double>&);
template void BasicCbShellElement<CountedDouble>::evaluate(const ElementPoses&, Vector24&, Matrix24*) const;

ElementFlops count_element_flops(const CbShellElement& element, const ElementPoses& current) {
  const BasicCbShellElement<CountedDouble> counting(element);
  BasicCbShellElement<CountedDouble>::Vector24 f;
  BasicCbShellElement<CountedDouble>::Matrix24 K;
  ElementFlops out;
  counted_flops = 0;
  counting.evaluate(current, f, nullptr);
  out.force = counted_flops;
  counted_flops = 0;
  counting.evaluate(current, f, &K);
  out.force_tangent = counted_flops;
  for (int i = 0; i < 24; ++i) {
    out.counted_force[i] = f[i].value;
    for (int j = 0; j < 24; ++j) out.counted_tangent(i, j) = K(i, j).value;
  }
  return out;
}

}  // namespace ff::shell

namespace ff::shell {

namespace {
// in-plane stress [s11, s22, s12] and transverse shear [s13, s23] of a station turned into axes
// at angle a from the element's t1 (the stress transformation, Jones ch. 2)
Vec5 turn_stress(const Vec5& s, double a) {
  const double c = std::cos(a), n = std::sin(a);
  Vec5 r;
  r[0] = c * c * s[0] + n * n * s[1] + 2 * c * n * s[2];
  r[1] = n * n * s[0] + c * c * s[1] - 2 * c * n * s[2];
  r[2] = c * n * (s[1] - s[0]) + (c * c - n * n) * s[2];
  r[3] = c * s[3] + n * s[4];
  r[4] = -n * s[3] + c * s[4];
  return r;
}
double tsai_wu(const Vec5& s, const std::array<double, 5>& strength) {  // laminate.md (L12)
  const double Xt = strength[0], Xc = strength[1], Yt = strength[2], Yc = strength[3], S = strength[4];
  const double F1 = 1 / Xt - 1 / Xc, F2 = 1 / Yt - 1 / Yc, F11 = 1 / (Xt * Xc), F22 = 1 / (Yt * Yc), F66 = 1 / (S * S);
  const double F12 = -0.5 * std::sqrt(F11 * F22);
  return F1 * s[0] + F2 * s[1] + F11 * s[0] * s[0] + F22 * s[1] * s[1] + F66 * s[2] * s[2] + 2 * F12 * s[0] * s[1];
}
}  // namespace

// laminate.md section 6: per layer the stresses the energy uses at its 8 points (the assumed
// in-plane stress with hr, the tied shear with ans), averaged over the 2 x 2 in-plane points of
// each station (or extrapolated from them to a corner), are linear in the layer's own coordinate (exactly so for the assumed stress), so
// the bottom, middle and top of a layer follow from its two stations; the resultants integrate
// the same stations (2-point Gauss, exact for a linear stress times z).
// The stresses the energy uses at a layer's 8 points, element frame [s11 s22 s12 s13 s23]: the
// assumed in-plane stress with hr (eq. 10, (L8)) or C_m eps, the (tied with ans) shear C_s gamma;
// visit(layer index, layer, its tables, the 8 stresses) for every layer, bottom up.
template <>
template <class Visit>
void BasicCbShellElement<double>::visit_layer_stresses(const ElementPoses& cur, Visit&& visit) const {
  const double hh = 0.5 * sec_.thickness;
  const Mat38 X = node_columns(cur, hh);
  const ZetaFreeBases<double> bases(X, section_tables(), opt_.ans);
  for (int li = 0; li < static_cast<int>(layers_.size()); ++li) {
    const Layer& L = layers_[li];
    const Tables<>& tab = *L.tab;
    double tied[2][4] = {};
    for (int l = 0; l < 2 && opt_.ans; ++l)
      for (int t = 0; t < 4; ++t) tied[l][t] = bases.tied(t, tab.zeta[l], L.tie_ref[l][t]);
    std::array<Vec3, kPoints> em;
    std::array<Eigen::Vector2d, kPoints> es;
    Vec10 gv = Vec10::Zero();
    for (int k = 0; k < kPoints; ++k) {
      const SolidConst<>& pc = tab.pts[k];
      Mat3 g;
      bases.at(k % 4, pc.zeta, g);
      point_strains(g, L.pts[k], pc, opt_.ans ? tied[pc.layer] : nullptr, em[k], es[k]);
      if (opt_.hr) gv += L.pts[k].weight * p_hat(p_coef_, pc).transpose() * em[k];  // eq. (10)
    }
    const Vec10 beta = opt_.hr ? Vec10(L.h_inv * gv) : Vec10::Zero();
    std::array<Vec5, kPoints> sk;
    for (int k = 0; k < kPoints; ++k) {
      const SolidConst<>& pc = tab.pts[k];
      sk[k].head<3>() = opt_.hr ? Vec3(p_hat(p_coef_, pc) * beta) : Vec3(L.Cm * em[k]);
      sk[k].tail<2>() = L.Cs * es[k];
    }
    visit(li, L, tab, sk);
  }
}

template <>
void BasicCbShellElement<double>::stresses(const ElementPoses& cur, ElementStress& out, int corner) const {
  // weights of the 2 x 2 points: the mean (centre), or the bilinear function through the four
  // points (at -+1/sqrt 3) evaluated at the corner, 1/4 (1 + 3 xi_c xi_q)(1 + 3 eta_c eta_q)
  const bool at_corner = corner >= 0 && corner < 4;
  const double xi_c = at_corner ? kXiNode[corner] : 0.0, eta_c = at_corner ? kEtaNode[corner] : 0.0;
  const double hh = 0.5 * sec_.thickness;
  out.N.setZero(), out.M.setZero(), out.Q.setZero();
  out.plies = sec_.plies ? static_cast<int>(layers_.size()) : 0;
  const int last = static_cast<int>(layers_.size()) - 1;
  visit_layer_stresses(cur, [&](int li, const Layer& L, const Tables<>& tab, const std::array<Vec5, kPoints>& sk) {
    Vec5 station[2] = {Vec5::Zero(), Vec5::Zero()};  // element frame, mean over the in-plane points
    for (int k = 0; k < kPoints; ++k) {
      const SolidConst<>& pc = tab.pts[k];
      station[pc.layer] += (0.25 * (1 + 3 * xi_c * pc.xi) * (1 + 3 * eta_c * pc.eta)) * sk[k];
    }
    // resultants per unit length, in the section axes: dz = (h/2) zeta_half dzeta-hat
    const double w = hh * tab.zeta_half;
    for (int l = 0; l < 2; ++l) {
      const Vec5 s = turn_stress(station[l], reference_angle_);
      out.N += w * s.head<3>();
      out.M += w * hh * tab.zeta[l] * s.head<3>();
      out.Q += w * s.tail<2>();
    }
    // the layer's stress at its own coordinate zh (linear through the two stations at -+gp)
    const double gp = tab.gpts[1];
    auto at = [&](double zh) -> Vec5 { return 0.5 * (station[0] + station[1]) + (zh / (2 * gp)) * (station[1] - station[0]); };
    if (li == 0) out.surface[0] = turn_stress(at(-1.0), reference_angle_);
    if (li == last) out.surface[2] = turn_stress(at(1.0), reference_angle_);
    if (L.zeta_lo <= 0.0 && (0.0 < L.zeta_hi || li == last))  // the reference surface (the upper ply at an interface)
      out.surface[1] = turn_stress(at(-tab.zeta_mid / tab.zeta_half), reference_angle_);
    if (!sec_.plies) return;
    const Ply& ply = (*sec_.plies)[li];
    const bool failure = ply.strength[0] > 0;
    out.tsai_wu[li] = failure ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::quiet_NaN();
    for (int j = 0; j < 3; ++j) {
      out.ply[li][j] = turn_stress(at(j - 1.0), L.fibre_angle);
      if (failure) out.tsai_wu[li] = std::max(out.tsai_wu[li], tsai_wu(out.ply[li][j], ply.strength));
    }
  });
}

// error_indicator.md (Z2)-(Z3): the resultants at the 2 x 2 in-plane points (the same stations as
// stresses(), not averaged), the reference geometry there, and the section's compliance.
template <>
void BasicCbShellElement<double>::resultant_samples(const ElementPoses& reference, const ElementPoses& cur,
                                                     ResultantSamples& out) const {
  const double hh = 0.5 * sec_.thickness;
  const Mat38 X0 = node_columns(reference, hh);
  const Mat3 Gc = X0 * master_derivatives(0, 0, 0);
  const Vec3 t1 = Gc.col(0).normalized(), t3 = Gc.col(0).cross(Gc.col(1)).normalized();
  out.frame.col(0) = t1, out.frame.col(1) = t3.cross(t1), out.frame.col(2) = t3;
  Eigen::Matrix3d A = Eigen::Matrix3d::Zero(), B = A, D = A;
  Eigen::Matrix2d As = Eigen::Matrix2d::Zero();
  for (int g = 0; g < 4; ++g) out.resultant[g].setZero();
  bool points_set = false;
  visit_layer_stresses(cur, [&](int, const Layer& L, const Tables<>& tab, const std::array<Vec5, kPoints>& sk) {
    const double w = hh * tab.zeta_half;
    for (int l = 0; l < 2; ++l) {  // (Z2): 2-point Gauss per layer, exact for z^2 C_m
      const double z = hh * tab.zeta[l];
      A += w * L.Cm, B += w * z * L.Cm, D += w * z * z * L.Cm, As += w * L.Cs;
    }
    for (int k = 0; k < kPoints; ++k) {  // (Z3)
      const SolidConst<>& pc = tab.pts[k];
      const double z = hh * tab.zeta[pc.layer];
      Eigen::Matrix<double, 8, 1>& r = out.resultant[k % 4];
      r.head<3>() += w * sk[k].head<3>();
      r.segment<3>(3) += w * z * sk[k].head<3>();
      r.tail<2>() += w * sk[k].tail<2>();
      if (points_set || k >= 4) continue;
      // in-plane point k: its mid-surface position and area element on the reference (zeta = 0)
      const Mat3 J = X0 * master_derivatives(pc.xi, pc.eta, 0.0);
      Eigen::Vector4d N, dxi, deta;
      quad_shape(pc.xi, pc.eta, N, dxi, deta);
      Vec3 x = Vec3::Zero();
      for (int i = 0; i < 4; ++i) x += N[i] * reference[i].p;
      out.position[k] = x;
      out.area[k] = J.col(0).cross(J.col(1)).norm();  // Gauss weight 1 at the 2 x 2 points
      out.xi[k] = pc.xi, out.eta[k] = pc.eta;
    }
    points_set = true;
  });
  Eigen::Matrix<double, 6, 6> S6;  // (Z1): [A B; B D]^-1, and As^-1
  S6 << A, B, B, D;
  out.compliance.setZero();
  out.compliance.topLeftCorner<6, 6>() = S6.inverse();
  out.compliance.bottomRightCorner<2, 2>() = As.inverse();
}
}  // namespace ff::shell
