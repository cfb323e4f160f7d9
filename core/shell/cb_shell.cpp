#include "core/shell/cb_shell.h"

#include <cmath>
#include <stdexcept>

namespace ff::shell {

namespace {
using Mat8 = Eigen::Matrix<double, 8, 8>;
using Mat36 = Eigen::Matrix<double, 3, 6>;

constexpr double kXiNode[4] = {-1.0, 1.0, 1.0, -1.0};
constexpr double kEtaNode[4] = {-1.0, -1.0, 1.0, 1.0};
// covariant components in e_cov order: xx, ee, zz, xe, ez, xz (eq. 6)
constexpr int kPair[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
constexpr int kEtaZeta = 4, kXiZeta = 5;

Mat3 skew(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

// bilinear quad functions and derivatives at (xi, eta)
void quad_shape(double xi, double eta, Eigen::Vector4d& N, Eigen::Vector4d& dxi, Eigen::Vector4d& deta) {
  for (int i = 0; i < 4; ++i) {
    N[i] = 0.25 * (1 + kXiNode[i] * xi) * (1 + kEtaNode[i] * eta);
    dxi[i] = 0.25 * kXiNode[i] * (1 + kEtaNode[i] * eta);
    deta[i] = 0.25 * kEtaNode[i] * (1 + kXiNode[i] * xi);
  }
}

// slave node A: master I = A % 4, side s = +1 (A < 4) or -1; trilinear derivatives
Eigen::Matrix<double, 8, 3> solid_derivatives(double xi, double eta, double zeta) {
  Eigen::Vector4d N, dxi, deta;
  quad_shape(xi, eta, N, dxi, deta);
  Eigen::Matrix<double, 8, 3> d;
  for (int A = 0; A < 8; ++A) {
    const int I = A % 4;
    const double s = A < 4 ? 1.0 : -1.0;
    d(A, 0) = dxi[I] * 0.5 * (1 + s * zeta);
    d(A, 1) = deta[I] * 0.5 * (1 + s * zeta);
    d(A, 2) = N[I] * 0.5 * s;
  }
  return d;
}

std::array<Vec3, 8> slave_positions(const ElementPoses& p, double h) {
  std::array<Vec3, 8> xs;
  for (int I = 0; I < 4; ++I) {
    const Vec3 d = p[I].R.col(2);
    xs[I] = p[I].x + 0.5 * h * d;      // eq. (1)
    xs[I + 4] = p[I].x - 0.5 * h * d;
  }
  return xs;
}

void base_vectors(const Eigen::Matrix<double, 8, 3>& dN, const std::array<Vec3, 8>& xs, Vec3 g[3]) {
  for (int i = 0; i < 3; ++i) {
    g[i].setZero();
    for (int A = 0; A < 8; ++A) g[i] += dN(A, i) * xs[A];
  }
}
}  // namespace

struct CbShellElement::Strains {
  Eigen::Matrix<double, 6, 1> e;        // covariant E_ij, eq. (3)
  Eigen::Matrix<double, 6, 24> B;       // eq. (4)
  std::array<Mat8, 6> M;                // eq. (5), scalar (times I3)
};

namespace {
// one covariant component (i, j) with its variations, eqs. (3)-(5)
// (M only when a tangent is wanted: it feeds the geometric stiffness alone)
void covariant_component(const Eigen::Matrix<double, 8, 3>& dN, const Vec3 g[3], int i, int j, double ref,
                         double& e, Eigen::Matrix<double, 1, 24>& b, Mat8* M) {
  e = 0.5 * (g[i].dot(g[j]) - ref);
  for (int A = 0; A < 8; ++A) b.segment<3>(3 * A) = 0.5 * (dN(A, i) * g[j] + dN(A, j) * g[i]).transpose();
  if (M) M->noalias() = 0.5 * (dN.col(i) * dN.col(j).transpose() + dN.col(j) * dN.col(i).transpose());
}
}  // namespace

CbShellElement::CbShellElement(const ElementPoses& ref, const ShellSection& sec, const ShellOptions& opt)
    : sec_(sec), opt_(opt) {
  const double h = sec.thickness, E = sec.youngs_modulus, nu = sec.poisson_ratio;
  const double shear_modulus = E / (2.0 * (1.0 + nu));
  // eq. (7)
  C_.setZero();
  const double cm = E / (1.0 - nu * nu);
  C_(0, 0) = C_(1, 1) = cm;
  C_(0, 1) = C_(1, 0) = cm * nu;
  C_(2, 2) = cm * 0.5 * (1.0 - nu);
  C_(3, 3) = C_(4, 4) = sec.shear_factor * shear_modulus;
  gamma_ = opt.drilling_factor * shear_modulus * h;  // eq. (13)

  const std::array<Vec3, 8> Xs = slave_positions(ref, h);
  // centre frame for the assumed stress, eq. (9)
  Vec3 Gc[3];
  base_vectors(solid_derivatives(0, 0, 0), Xs, Gc);
  const Vec3 t1c = Gc[0].normalized();
  const Vec3 t3c = Gc[0].cross(Gc[1]).normalized();
  const Vec3 t2c = t3c.cross(t1c);
  const double a1 = Gc[0].dot(t1c), b1 = Gc[0].dot(t2c), a2 = Gc[1].dot(t1c), b2 = Gc[1].dot(t2c);
  if (!(Gc[0].cross(Gc[1]).norm() > 0)) throw std::invalid_argument("CB shell: degenerate element");

  const double gp = 1.0 / std::sqrt(3.0);
  const double gpts[2] = {-gp, gp};
  Eigen::Matrix3d Cm_inv = C_.topLeftCorner<3, 3>().inverse();
  Eigen::Matrix<double, 10, 10> H = Eigen::Matrix<double, 10, 10>::Zero();
  int k = 0;
  for (int l = 0; l < 2; ++l)
    for (int jy = 0; jy < 2; ++jy)
      for (int jx = 0; jx < 2; ++jx, ++k) {
        SolidPoint& p = pts_[k];
        p.xi = gpts[jx];
        p.eta = gpts[jy];
        p.layer = l;
        const double zeta = gpts[l];
        p.dN = solid_derivatives(p.xi, p.eta, zeta);
        Vec3 G[3];
        base_vectors(p.dN, Xs, G);
        Mat3 J;
        J << G[0], G[1], G[2];
        const double detJ = J.determinant();
        if (!(detJ > 0)) throw std::invalid_argument("CB shell: inverted or degenerate element (det J <= 0)");
        p.weight = detJ;
        for (int c = 0; c < 6; ++c) p.ref_metric[c] = G[kPair[c][0]].dot(G[kPair[c][1]]);
        // lamina frame: normal at the point, t1 from the centre frame (common in-plane orientation)
        const Vec3 t3 = G[0].cross(G[1]).normalized();
        const Vec3 t1 = (t1c - t1c.dot(t3) * t3).normalized();
        const Vec3 t2 = t3.cross(t1);
        const Mat3 dual = J.inverse();  // rows: contravariant G^i
        Mat3 c;                         // c(i, k) = G^i . t_k
        for (int i = 0; i < 3; ++i) c.row(i) << dual.row(i).dot(t1), dual.row(i).dot(t2), dual.row(i).dot(t3);
        // eq. (6): rows eps11, eps22, 2eps12, 2eps13, 2eps23
        const int kl[5][2] = {{0, 0}, {1, 1}, {0, 1}, {0, 2}, {1, 2}};
        for (int r = 0; r < 5; ++r) {
          const int kk = kl[r][0], ll = kl[r][1];
          const double eng = kk == ll ? 1.0 : 2.0;
          for (int q = 0; q < 6; ++q) {
            const int i = kPair[q][0], j = kPair[q][1];
            const double coef = i == j ? c(i, kk) * c(j, ll) : c(i, kk) * c(j, ll) + c(j, kk) * c(i, ll);
            p.Q(r, q) = eng * coef;
          }
        }
        Eigen::Matrix<double, 3, 5> P;
        P << 1, 0, 0, a1 * a1 * p.eta, a2 * a2 * p.xi, 0, 1, 0, b1 * b1 * p.eta, b2 * b2 * p.xi, 0, 0, 1,
            a1 * b1 * p.eta, a2 * b2 * p.xi;
        p.P << P, zeta * P;
        H.noalias() += p.weight * p.P.transpose() * Cm_inv * p.P;  // eq. (10)
      }
  h_inv_ = H.inverse();

  // tying points of eq. (8): A(-1,0), B(0,-1), C(1,0), D(0,1) at each layer
  const double tp[4][2] = {{-1, 0}, {0, -1}, {1, 0}, {0, 1}};
  for (int l = 0; l < 2; ++l)
    for (int t = 0; t < 4; ++t) {
      TyingPoint& tpnt = tying_[l][t];
      tpnt.dN = solid_derivatives(tp[t][0], tp[t][1], gpts[l]);
      Vec3 G[3];
      base_vectors(tpnt.dN, Xs, G);
      const int comp = (t == 0 || t == 2) ? kEtaZeta : kXiZeta;
      tpnt.ref_value = G[kPair[comp][0]].dot(G[kPair[comp][1]]);
    }

  // drilling points, eq. (12)
  k = 0;
  for (int jy = 0; jy < 2; ++jy)
    for (int jx = 0; jx < 2; ++jx, ++k) {
      DrillPoint& d = drill_[k];
      quad_shape(gpts[jx], gpts[jy], d.N, d.dNxi, d.dNeta);
      Vec3 Gx = Vec3::Zero(), Ge = Vec3::Zero();
      for (int I = 0; I < 4; ++I) Gx += d.dNxi[I] * ref[I].x, Ge += d.dNeta[I] * ref[I].x;
      const double A = Gx.cross(Ge).norm();
      d.weight = A;
      d.inv2A = 0.5 / A;
      for (int I = 0; I < 4; ++I) {
        d.g1_local[I] = ref[I].R.transpose() * Gx;
        d.g2_local[I] = ref[I].R.transpose() * Ge;
      }
    }
}

void CbShellElement::solid_point(const SolidPoint& p, const std::array<Vec3, 8>& xs, Strains& s, bool second) const {
  Vec3 g[3];
  base_vectors(p.dN, xs, g);
  for (int c = 0; c < 6; ++c) {
    Eigen::Matrix<double, 1, 24> b;
    covariant_component(p.dN, g, kPair[c][0], kPair[c][1], p.ref_metric[c], s.e[c], b, second ? &s.M[c] : nullptr);
    s.B.row(c) = b;
  }
  if (!opt_.ans) return;
  // eq. (8): transverse shears interpolated from the tying points of this layer
  const double wA = 0.5 * (1 - p.xi), wC = 0.5 * (1 + p.xi), wB = 0.5 * (1 - p.eta), wD = 0.5 * (1 + p.eta);
  const double w[4] = {wA, wB, wC, wD};
  s.e[kEtaZeta] = s.e[kXiZeta] = 0.0;
  s.B.row(kEtaZeta).setZero();
  s.B.row(kXiZeta).setZero();
  if (second) s.M[kEtaZeta].setZero(), s.M[kXiZeta].setZero();
  for (int t = 0; t < 4; ++t) {
    const TyingPoint& tpnt = tying_[p.layer][t];
    const int comp = (t == 0 || t == 2) ? kEtaZeta : kXiZeta;
    Vec3 gt[3];
    base_vectors(tpnt.dN, xs, gt);
    double e;
    Eigen::Matrix<double, 1, 24> b;
    Mat8 M;
    covariant_component(tpnt.dN, gt, kPair[comp][0], kPair[comp][1], tpnt.ref_value, e, b, second ? &M : nullptr);
    s.e[comp] += w[t] * e;
    s.B.row(comp) += w[t] * b;
    if (second) s.M[comp] += w[t] * M;
  }
}

double CbShellElement::solid_terms(const ElementPoses& cur, Vec24& f, Mat24* K) const {
  const std::array<Vec3, 8> xs = slave_positions(cur, sec_.thickness);
  std::array<Strains, kPoints> st;
  f.setZero();
  if (K) K->setZero();
  Mat8 geo = Mat8::Zero();
  double energy = 0.0;
  Eigen::Matrix<double, 10, 1> g = Eigen::Matrix<double, 10, 1>::Zero();
  Eigen::Matrix<double, 10, 24> G = Eigen::Matrix<double, 10, 24>::Zero();
  const Eigen::Matrix2d Cs = C_.bottomRightCorner<2, 2>();
  const Eigen::Matrix3d Cm = C_.topLeftCorner<3, 3>();
  for (int k = 0; k < kPoints; ++k) {
    const SolidPoint& p = pts_[k];
    Strains& s = st[k];
    solid_point(p, xs, s, K != nullptr);
    const Eigen::Matrix<double, 5, 1> eps = p.Q * s.e;
    const Eigen::Matrix<double, 5, 24> B = p.Q * s.B;
    // transverse shear: displacement based (with ANS strains when on)
    const Eigen::Vector2d Ss = Cs * eps.tail<2>();
    f.noalias() += p.weight * B.bottomRows<2>().transpose() * Ss;
    energy += 0.5 * p.weight * eps.tail<2>().dot(Ss);
    Eigen::Matrix<double, 6, 1> Scov = p.Q.bottomRows<2>().transpose() * Ss;
    if (K) K->noalias() += p.weight * B.bottomRows<2>().transpose() * Cs * B.bottomRows<2>();
    if (opt_.hr) {
      g.noalias() += p.weight * p.P.transpose() * eps.head<3>();  // eq. (10)
      G.noalias() += p.weight * p.P.transpose() * B.topRows<3>();  // eq. (11)
    } else {
      const Eigen::Vector3d Sm = Cm * eps.head<3>();
      f.noalias() += p.weight * B.topRows<3>().transpose() * Sm;
      energy += 0.5 * p.weight * eps.head<3>().dot(Sm);
      Scov.noalias() += p.Q.topRows<3>().transpose() * Sm;
      if (K) K->noalias() += p.weight * B.topRows<3>().transpose() * Cm * B.topRows<3>();
    }
    if (K)
      for (int c = 0; c < 6; ++c) geo.noalias() += (p.weight * Scov[c]) * s.M[c];
  }
  if (opt_.hr) {
    const Eigen::Matrix<double, 10, 1> beta = h_inv_ * g;  // eq. (10)
    f.noalias() += G.transpose() * beta;                  // eq. (11)
    energy += 0.5 * g.dot(beta);
    if (K) {
      K->noalias() += G.transpose() * h_inv_ * G;
      for (int k = 0; k < kPoints; ++k) {
        const Eigen::Vector3d Sm = pts_[k].P * beta;  // assumed stress at the point
        const Eigen::Matrix<double, 6, 1> Scov = pts_[k].Q.topRows<3>().transpose() * Sm;
        for (int c = 0; c < 6; ++c) geo.noalias() += (pts_[k].weight * Scov[c]) * st[k].M[c];
      }
    }
  }
  if (K)
    for (int A = 0; A < 8; ++A)
      for (int Bn = 0; Bn < 8; ++Bn) K->block<3, 3>(3 * A, 3 * Bn).diagonal().array() += geo(A, Bn);
  return energy;
}

double CbShellElement::drilling_terms(const ElementPoses& cur, Vec24& f, Mat24* K) const {
  double energy = 0.0;
  for (const DrillPoint& d : drill_) {
    Vec3 gx = Vec3::Zero(), ge = Vec3::Zero(), abar = Vec3::Zero(), bbar = Vec3::Zero();
    std::array<Vec3, 4> a, b;
    for (int I = 0; I < 4; ++I) {
      gx += d.dNxi[I] * cur[I].x;
      ge += d.dNeta[I] * cur[I].x;
      a[I] = cur[I].R * d.g1_local[I];
      b[I] = cur[I].R * d.g2_local[I];
      abar += d.N[I] * a[I];
      bbar += d.N[I] * b[I];
    }
    const double omega = d.inv2A * (abar.dot(ge) - bbar.dot(gx));  // eq. (12)
    energy += 0.5 * gamma_ * d.weight * omega * omega;              // eq. (13)
    // local gradient c of omega, eq. (14)
    Vec24 c;
    std::array<Vec3, 4> pa, pb, px;  // local-frame partials of omega w.r.t. a_I, b_I, x_I
    for (int I = 0; I < 4; ++I) {
      const Mat3 Rt = cur[I].R.transpose();
      px[I] = Rt * (d.inv2A * (d.dNeta[I] * abar - d.dNxi[I] * bbar));
      pa[I] = Rt * (d.inv2A * d.N[I] * ge);
      pb[I] = Rt * (-d.inv2A * d.N[I] * gx);
      c.segment<3>(6 * I) = px[I];
      c.segment<3>(6 * I + 3) = skew(d.g1_local[I]) * pa[I] + skew(d.g2_local[I]) * pb[I];
    }
    const double scale = gamma_ * d.weight;
    f.noalias() += (scale * omega) * c;
    if (!K) continue;
    Mat24 Hw = Mat24::Zero();
    for (int I = 0; I < 4; ++I) {
      // primitive cross terms a_I/b_I with x_J (rows theta_I, columns u_J), and transposes
      for (int J = 0; J < 4; ++J) {
        const Mat3 RiRj = cur[I].R.transpose() * cur[J].R;
        const Mat3 blk = d.inv2A * d.N[I] *
                         (d.dNeta[J] * skew(d.g1_local[I]) - d.dNxi[J] * skew(d.g2_local[I])) * RiRj;
        Hw.block<3, 3>(6 * I + 3, 6 * J) += blk;
        Hw.block<3, 3>(6 * J, 6 * I + 3) += blk.transpose();
      }
      // second variations of the primitives at fixed local directions, eq. (17)
      Hw.block<3, 3>(6 * I + 3, 6 * I + 3) += pa[I] * d.g1_local[I].transpose() -
                                               pa[I].dot(d.g1_local[I]) * Mat3::Identity() +
                                               pb[I] * d.g2_local[I].transpose() -
                                               pb[I].dot(d.g2_local[I]) * Mat3::Identity();
      Hw.block<3, 3>(6 * I, 6 * I + 3) += skew(px[I]);
    }
    K->noalias() += scale * (c * c.transpose() + omega * Hw);
  }
  return energy;
}

void CbShellElement::evaluate(const ElementPoses& cur, Vec24& F, Mat24* K) const {
  Vec24 fs;
  Mat24 Ks;
  solid_terms(cur, fs, K ? &Ks : nullptr);
  F.setZero();
  if (K) K->setZero();
  const double hh = 0.5 * sec_.thickness;
  const Vec3 e3(0, 0, 1);
  const Mat3 e3x = skew(e3);
  std::array<Mat36, 8> T;  // eq. (2)
  for (int A = 0; A < 8; ++A) {
    const int I = A % 4;
    const double s = A < 4 ? 1.0 : -1.0;
    T[A] << cur[I].R, -s * hh * cur[I].R * e3x;
  }
  for (int A = 0; A < 8; ++A) {
    const int I = A % 4;
    const double s = A < 4 ? 1.0 : -1.0;
    F.segment<6>(6 * I).noalias() += T[A].transpose() * fs.segment<3>(3 * A);  // eq. (15)
    if (!K) continue;
    for (int B = 0; B < 8; ++B)
      K->block<6, 6>(6 * I, 6 * (B % 4)).noalias() += T[A].transpose() * Ks.block<3, 3>(3 * A, 3 * B) * T[B];
    // eq. (16): variation of T at fixed slave force
    const Mat3 fl = skew(cur[I].R.transpose() * fs.segment<3>(3 * A));
    K->block<3, 3>(6 * I, 6 * I + 3) += fl;
    K->block<3, 3>(6 * I + 3, 6 * I + 3) += s * hh * e3x * fl;
  }
  if (opt_.drilling) drilling_terms(cur, F, K);
}

double CbShellElement::energy(const ElementPoses& cur) const {
  Vec24 f;
  double e = solid_terms(cur, f, nullptr);
  if (opt_.drilling) {
    Vec24 fd = Vec24::Zero();
    e += drilling_terms(cur, fd, nullptr);
  }
  return e;
}

}  // namespace ff::shell
