// Textbook CB shell (cb_shell.md, "Textbook oracle"): the energy of (S1)-(S13) evaluated point by
// point, templated on the scalar; force and tangent from hyper-dual numbers. Nothing here calls or
// mirrors cb_shell.cpp: no slave sums and moments, no B rows, no kernels, no stress vectors.
#include "tests/support/cb_shell_textbook.h"

#include <cmath>
#include <stdexcept>

namespace ff::shell {

namespace {

// ---- hyper-dual numbers: v + e1 ε1 + e2 ε2 + e12 ε1ε2 with ε1² = ε2² = 0 ----------------------
// f(x + ε1 a + ε2 b) = f + ε1 f'a + ε2 f'b + ε1ε2 f''(a, b) exactly (no truncation, no step), so
// one energy evaluation gives a first derivative (e1) and a mixed second derivative (e12).
struct HyperDual {
  double v = 0, e1 = 0, e2 = 0, e12 = 0;
  HyperDual() = default;
  HyperDual(double value) : v(value) {}  // NOLINT: a constant lifts implicitly, as in the maths
  HyperDual(double value, double d1, double d2, double d12) : v(value), e1(d1), e2(d2), e12(d12) {}
};
HyperDual operator+(const HyperDual& a, const HyperDual& b) { return {a.v + b.v, a.e1 + b.e1, a.e2 + b.e2, a.e12 + b.e12}; }
HyperDual operator-(const HyperDual& a, const HyperDual& b) { return {a.v - b.v, a.e1 - b.e1, a.e2 - b.e2, a.e12 - b.e12}; }
HyperDual operator-(const HyperDual& a) { return {-a.v, -a.e1, -a.e2, -a.e12}; }
HyperDual operator*(const HyperDual& a, const HyperDual& b) {
  return {a.v * b.v, a.v * b.e1 + a.e1 * b.v, a.v * b.e2 + a.e2 * b.v,
          a.v * b.e12 + a.e1 * b.e2 + a.e2 * b.e1 + a.e12 * b.v};
}
HyperDual operator*(double s, const HyperDual& a) { return {s * a.v, s * a.e1, s * a.e2, s * a.e12}; }
HyperDual& operator+=(HyperDual& a, const HyperDual& b) { return a = a + b; }

// ---- tiny 3-vectors and 3 x 3 matrices in any scalar (no Eigen custom scalar needed) ----------
template <class T>
struct V3 {
  std::array<T, 3> c{};
  T& operator[](int i) { return c[i]; }
  const T& operator[](int i) const { return c[i]; }
};
template <class T>
V3<T> lift(const Vec3& a) {
  return {{T(a[0]), T(a[1]), T(a[2])}};
}
template <class T>
V3<T> operator+(const V3<T>& a, const V3<T>& b) {
  return {{a[0] + b[0], a[1] + b[1], a[2] + b[2]}};
}
template <class T>
V3<T> operator-(const V3<T>& a, const V3<T>& b) {
  return {{a[0] - b[0], a[1] - b[1], a[2] - b[2]}};
}
template <class T, class S>
V3<T> operator*(const S& s, const V3<T>& a) {
  return {{s * a[0], s * a[1], s * a[2]}};
}
template <class T>
T dot(const V3<T>& a, const V3<T>& b) {
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
template <class T>
V3<T> cross(const V3<T>& a, const V3<T>& b) {
  return {{a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]}};
}

template <class T>
struct M3 {  // m[i][j]: row i, column j
  std::array<std::array<T, 3>, 3> m{};
};
template <class T>
V3<T> operator*(const M3<T>& A, const V3<T>& b) {
  V3<T> r;
  for (int i = 0; i < 3; ++i) r[i] = A.m[i][0] * b[0] + A.m[i][1] * b[1] + A.m[i][2] * b[2];
  return r;
}
template <class T>
M3<T> operator*(const M3<T>& A, const M3<T>& B) {
  M3<T> C;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) C.m[i][j] = A.m[i][0] * B.m[0][j] + A.m[i][1] * B.m[1][j] + A.m[i][2] * B.m[2][j];
  return C;
}

}  // namespace

template <class T>
struct CbShellTextbook::Node {
  M3<T> R;  // columns e1, e2, director
  V3<T> x;
};

namespace {

template <class T>
std::array<CbShellTextbook::Node<T>, 4> lift(const ElementPoses& poses) {
  std::array<CbShellTextbook::Node<T>, 4> n;
  for (int I = 0; I < 4; ++I) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) n[I].R.m[i][j] = T(poses[I].R(i, j));
    n[I].x = lift<T>(poses[I].p);
  }
  return n;
}

// exp(v~) for a purely infinitesimal hyper-dual v (zero real part): every product of three
// infinitesimal parts contains ε1² or ε2² and vanishes, so v~³ = 0 and the series
// I + v~ + v~²/2 is exact, not an approximation (for one infinitesimal even v~² = 0). increment()
// only ever passes such v.
M3<HyperDual> exp_infinitesimal(const V3<HyperDual>& v) {
  M3<HyperDual> h;  // v~
  h.m[0][1] = -v[2], h.m[0][2] = v[1];
  h.m[1][0] = v[2], h.m[1][2] = -v[0];
  h.m[2][0] = -v[1], h.m[2][1] = v[0];
  const M3<HyperDual> h2 = h * h;
  M3<HyperDual> E;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) E.m[i][j] = (i == j ? HyperDual(1.0) : HyperDual()) + h.m[i][j] + 0.5 * h2.m[i][j];
  return E;
}

// the local increment of cb_shell.h by the infinitesimal d on DoF k: x ← x + R d e_c, R ← R exp(d e_c~)
void increment(std::array<CbShellTextbook::Node<HyperDual>, 4>& n, int k, const HyperDual& d) {
  auto& node = n[k / 6];
  const int c = k % 6;
  V3<HyperDual> e;
  e[c % 3] = d;
  if (c < 3) node.x = node.x + node.R * e;
  else node.R = node.R * exp_infinitesimal(e);
}

// bilinear quad functions (counter-clockwise corners) and the trilinear slave functions of §2:
// N_I^s = N_I(ξ, η)(1 + sζ)/2; slave A = I (s = +1) or 4 + I (s = −1)
constexpr double kXi[4] = {-1, 1, 1, -1}, kEta[4] = {-1, -1, 1, 1};
double quad_N(int I, double xi, double eta) { return 0.25 * (1 + kXi[I] * xi) * (1 + kEta[I] * eta); }
double quad_dxi(int I, double eta) { return 0.25 * kXi[I] * (1 + kEta[I] * eta); }
double quad_deta(int I, double xi) { return 0.25 * kEta[I] * (1 + kXi[I] * xi); }
double slave_sign(int A) { return A < 4 ? 1.0 : -1.0; }

// covariant base vectors g_i = Σ_A N_A,i x_A (i = ξ, η, ζ) of the trilinear brick, §2
template <class T>
std::array<V3<T>, 3> base_vectors(const std::array<V3<T>, 8>& slaves, double xi, double eta, double zeta) {
  std::array<V3<T>, 3> g{};
  for (int A = 0; A < 8; ++A) {
    const int I = A % 4;
    const double s = slave_sign(A), layer = 0.5 * (1 + s * zeta);
    g[0] = g[0] + (quad_dxi(I, eta) * layer) * slaves[A];
    g[1] = g[1] + (quad_deta(I, xi) * layer) * slaves[A];
    g[2] = g[2] + (quad_N(I, xi, eta) * 0.5 * s) * slaves[A];
  }
  return g;
}

Vec3 to_eigen(const V3<double>& a) { return {a[0], a[1], a[2]}; }
V3<double> to_v3(const Vec3& a) { return {{a[0], a[1], a[2]}}; }

const double kGauss = 1.0 / std::sqrt(3.0);

}  // namespace

CbShellTextbook::CbShellTextbook(const ElementPoses& ref, const ShellSection& sec, const ShellOptions& opt)
    : sec_(sec), opt_(opt) {
  const double hh = 0.5 * sec.thickness, E = sec.youngs_modulus, nu = sec.poisson_ratio;
  for (int A = 0; A < 8; ++A)  // (S1)
    ref_slaves_[A] = ref[A % 4].p + (slave_sign(A) * hh) * ref[A % 4].R.col(2);
  std::array<V3<double>, 8> X;
  for (int A = 0; A < 8; ++A) X[A] = to_v3(ref_slaves_[A]);

  // (S7): plane-stress block, its compliance written out (not inverted numerically), shear
  const double cm = E / (1 - nu * nu), shear_modulus = E / (2 * (1 + nu));
  Cm_ << cm, cm * nu, 0, cm * nu, cm, 0, 0, 0, cm * (1 - nu) / 2;
  Eigen::Matrix3d Cm_inv;
  Cm_inv << 1 / E, -nu / E, 0, -nu / E, 1 / E, 0, 0, 0, 2 * (1 + nu) / E;
  kG_ = sec.shear_factor * shear_modulus;
  gamma_ = opt.drilling_factor * shear_modulus * sec.thickness;  // (S13)

  // (S9): element frame at the centre, J0 = [[a1, a2], [b1, b2]]
  const auto Gc = base_vectors(X, 0, 0, 0);
  const Vec3 Gc1 = to_eigen(Gc[0]), Gc2 = to_eigen(Gc[1]);
  const Vec3 t1c = Gc1.normalized(), t3c = Gc1.cross(Gc2).normalized(), t2c = t3c.cross(t1c);
  j0_ = {Gc1.dot(t1c), Gc2.dot(t1c), Gc1.dot(t2c), Gc2.dot(t2c)};

  Eigen::Matrix<double, 10, 10> H = Eigen::Matrix<double, 10, 10>::Zero();
  int k = 0;
  for (double zeta : {-kGauss, kGauss})
    for (double eta : {-kGauss, kGauss})
      for (double xi : {-kGauss, kGauss}) {
        Point& p = pts_[k++];
        p.xi = xi, p.eta = eta, p.zeta = zeta;
        const auto Gv = base_vectors(X, xi, eta, zeta);
        const Vec3 G[3] = {to_eigen(Gv[0]), to_eigen(Gv[1]), to_eigen(Gv[2])};
        const double detJ = G[0].dot(G[1].cross(G[2]));
        if (!(detJ > 0)) throw std::invalid_argument("CB shell textbook: det J <= 0");
        p.weight = detJ;  // Gauss weights are 1
        // dual basis G^i (G^i . G_j = δ_ij) and the lamina frame of §3
        const Vec3 Gd[3] = {G[1].cross(G[2]) / detJ, G[2].cross(G[0]) / detJ, G[0].cross(G[1]) / detJ};
        const Vec3 t3 = G[0].cross(G[1]).normalized();
        const Vec3 t1 = (t1c - t1c.dot(t3) * t3).normalized();
        const Vec3 t2 = t3.cross(t1);
        const Vec3 t[3] = {t1, t2, t3};
        // (S6): ε_kl = Σ_ij E_ij (G^i.t_k)(G^j.t_l); row r = [ε11, ε22, 2ε12, 2ε13, 2ε23], column c =
        // [E_ξξ, E_ηη, E_ζζ, E_ξη, E_ηζ, E_ξζ], an off-diagonal E_ij counted as E_ij and E_ji
        const int row_kl[5][2] = {{0, 0}, {1, 1}, {0, 1}, {0, 2}, {1, 2}};
        const int col_ij[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
        for (int r = 0; r < 5; ++r) {
          const Vec3 &tk = t[row_kl[r][0]], &tl = t[row_kl[r][1]];
          const double engineering = row_kl[r][0] == row_kl[r][1] ? 1.0 : 2.0;
          for (int c = 0; c < 6; ++c) {
            const Vec3 &Gi = Gd[col_ij[c][0]], &Gj = Gd[col_ij[c][1]];
            double q = Gi.dot(tk) * Gj.dot(tl);
            if (col_ij[c][0] != col_ij[c][1]) q += Gj.dot(tk) * Gi.dot(tl);
            p.Q[r][c] = engineering * q;
          }
        }
        if (opt.hr) {  // (S10): H = ∫ P̂ᵀ C_m⁻¹ P̂ dV
          const auto [a1, a2, b1, b2] = j0_;
          Eigen::Matrix<double, 3, 5> P;
          P << 1, 0, 0, a1 * a1 * eta, a2 * a2 * xi,  //
              0, 1, 0, b1 * b1 * eta, b2 * b2 * xi,   //
              0, 0, 1, a1 * b1 * eta, a2 * b2 * xi;
          Eigen::Matrix<double, 3, 10> Ph;
          Ph << P, zeta * P;
          H += p.weight * Ph.transpose() * Cm_inv * Ph;
        }
      }
  h_inv_ = opt.hr ? Eigen::Matrix<double, 10, 10>(H.fullPivLu().inverse()) : Eigen::Matrix<double, 10, 10>::Zero();

  // (S12): drilling points on the master mid-surface
  k = 0;
  for (double eta : {-kGauss, kGauss})
    for (double xi : {-kGauss, kGauss}) {
      DrillPoint& d = drill_[k++];
      d.xi = xi, d.eta = eta;
      Vec3 Gx = Vec3::Zero(), Ge = Vec3::Zero();
      for (int I = 0; I < 4; ++I) Gx += quad_dxi(I, eta) * ref[I].p, Ge += quad_deta(I, xi) * ref[I].p;
      d.area = Gx.cross(Ge).norm();
      for (int I = 0; I < 4; ++I) {
        d.g1_local[I] = ref[I].R.transpose() * Gx;
        d.g2_local[I] = ref[I].R.transpose() * Ge;
      }
    }
}

template <class T>
T CbShellTextbook::energy_of(const std::array<Node<T>, 4>& n) const {
  const double hh = 0.5 * sec_.thickness;
  std::array<V3<T>, 8> x;     // (S1): x_I^s = x_I + s (h0/2) R_I e3
  std::array<V3<double>, 8> X;
  for (int A = 0; A < 8; ++A) {
    const auto& node = n[A % 4];
    const V3<T> d = {{node.R.m[0][2], node.R.m[1][2], node.R.m[2][2]}};
    x[A] = node.x + (slave_sign(A) * hh) * d;
    X[A] = to_v3(ref_slaves_[A]);
  }
  // (S3): E_ij = ½ (g_i.g_j − G_i.G_j) at any point of the brick
  auto strain = [&](double xi, double eta, double zeta) {
    const auto g = base_vectors(x, xi, eta, zeta);
    const auto G = base_vectors(X, xi, eta, zeta);
    std::array<std::array<T, 3>, 3> Eij;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Eij[i][j] = 0.5 * (dot(g[i], g[j]) - T(dot(G[i], G[j])));
    return Eij;
  };

  T energy = T(0.0);
  std::array<T, 10> gv{};  // (S10): g = ∫ P̂ᵀ ε_m dV
  for (const Point& p : pts_) {
    auto Eij = strain(p.xi, p.eta, p.zeta);
    if (opt_.ans) {  // (S8): tying points A(−1,0), C(1,0) for E_ηζ; B(0,−1), D(0,1) for E_ξζ, same ζ
      const T e_xz = 0.5 * (1 - p.eta) * strain(0, -1, p.zeta)[0][2] + 0.5 * (1 + p.eta) * strain(0, 1, p.zeta)[0][2];
      const T e_ez = 0.5 * (1 - p.xi) * strain(-1, 0, p.zeta)[1][2] + 0.5 * (1 + p.xi) * strain(1, 0, p.zeta)[1][2];
      Eij[0][2] = Eij[2][0] = e_xz;
      Eij[1][2] = Eij[2][1] = e_ez;
    }
    const std::array<T, 6> e_cov = {Eij[0][0], Eij[1][1], Eij[2][2], Eij[0][1], Eij[1][2], Eij[0][2]};
    std::array<T, 5> eps{};  // (S6): ε = Q e_cov
    for (int r = 0; r < 5; ++r)
      for (int c = 0; c < 6; ++c) eps[r] += p.Q[r][c] * e_cov[c];
    // transverse shear, displacement based in both formulations: ½ w κG ε_sᵀ ε_s, (S7)
    energy += (0.5 * p.weight * kG_) * (eps[3] * eps[3] + eps[4] * eps[4]);
    if (opt_.hr) {
      const auto [a1, a2, b1, b2] = j0_;  // (S9): P, P̂ = [P, ζP]
      const double P[3][5] = {{1, 0, 0, a1 * a1 * p.eta, a2 * a2 * p.xi},
                              {0, 1, 0, b1 * b1 * p.eta, b2 * b2 * p.xi},
                              {0, 0, 1, a1 * b1 * p.eta, a2 * b2 * p.xi}};
      for (int m = 0; m < 3; ++m)
        for (int j = 0; j < 5; ++j) {
          gv[j] += (p.weight * P[m][j]) * eps[m];
          gv[5 + j] += (p.weight * p.zeta * P[m][j]) * eps[m];
        }
    } else {  // ½ w ε_mᵀ C_m ε_m, (S7)
      for (int m = 0; m < 3; ++m)
        for (int l = 0; l < 3; ++l) energy += (0.5 * p.weight * Cm_(m, l)) * eps[m] * eps[l];
    }
  }
  if (opt_.hr)  // (S11): Π_m = ½ gᵀ H⁻¹ g
    for (int i = 0; i < 10; ++i)
      for (int j = 0; j < 10; ++j) energy += (0.5 * h_inv_(i, j)) * gv[i] * gv[j];

  if (opt_.drilling)  // (S12), (S13): Π_d = ½ γ Σ_q w_q A ω², master nodes directly
    for (const DrillPoint& d : drill_) {
      V3<T> gx{}, ge{};
      T sum = T(0.0);
      for (int I = 0; I < 4; ++I) {
        gx = gx + quad_dxi(I, d.eta) * n[I].x;
        ge = ge + quad_deta(I, d.xi) * n[I].x;
      }
      for (int I = 0; I < 4; ++I) {
        const V3<T> a = n[I].R * lift<T>(d.g1_local[I]), b = n[I].R * lift<T>(d.g2_local[I]);
        sum += quad_N(I, d.xi, d.eta) * (dot(a, ge) - dot(b, gx));
      }
      const T omega = (1.0 / (2.0 * d.area)) * sum;
      energy += (0.5 * gamma_ * d.area) * omega * omega;
    }
  return energy;
}

double CbShellTextbook::energy(const ElementPoses& current) const { return energy_of(lift<double>(current)); }

void CbShellTextbook::evaluate(const ElementPoses& current, Vec24& force, Mat24& tangent) const {
  const auto base = lift<HyperDual>(current);
  for (int b = 0; b < 24; ++b) {
    auto outer = base;
    increment(outer, b, HyperDual(0, 0, 1, 0));  // X ∘ exp(ε2 e_b)
    for (int a = 0; a < 24; ++a) {
      auto nodes = outer;
      increment(nodes, a, HyperDual(0, 1, 0, 0));  // ... ∘ exp(ε1 e_a), inner: f_a at the moved state
      const HyperDual pi = energy_of(nodes);
      if (b == 0) force[a] = pi.e1;  // ε2-free part of the ε1 coefficient: f_a at X itself
      tangent(a, b) = pi.e12;
    }
  }
}

}  // namespace ff::shell
