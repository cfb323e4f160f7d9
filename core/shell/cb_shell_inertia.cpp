#include "core/shell/cb_shell_inertia.h"

#include <cmath>
#include <stdexcept>

namespace ff::shell {

namespace {
constexpr double kXiNode[4] = {-1.0, 1.0, 1.0, -1.0};
constexpr double kEtaNode[4] = {-1.0, -1.0, 1.0, 1.0};

using lie::hat;  // [a]x, the one skew matrix of core/lie
double side(int A) { return A < 4 ? 1.0 : -1.0; }  // slave A: master A % 4, top (+) or bottom (-)

// Ť_A^T X Ť_B for Ť = [I, -s h2 ẽ3] (D1): the 6x6 block [[X, -t h2 X ẽ3], [s h2 ẽ3 X, -s t h2² ẽ3 X ẽ3]]
Eigen::Matrix<double, 6, 6> sandwich(const Mat3& X, double sh, double th, const Mat3& e3x) {
  Eigen::Matrix<double, 6, 6> b;
  b.topLeftCorner<3, 3>() = X;
  b.topRightCorner<3, 3>() = -th * X * e3x;
  b.bottomLeftCorner<3, 3>() = sh * e3x * X;
  b.bottomRightCorner<3, 3>() = -sh * th * e3x * X * e3x;
  return b;
}
// Ť_A^T Y for a 3x6 Y: rows [Y; s h2 ẽ3 Y]
Eigen::Matrix<double, 6, 6> left(const Eigen::Matrix<double, 3, 6>& Y, double sh, const Mat3& e3x) {
  Eigen::Matrix<double, 6, 6> b;
  b.topRows<3>() = Y;
  b.bottomRows<3>() = sh * e3x * Y;
  return b;
}
}  // namespace

CbShellInertia::CbShellInertia(const ElementPoses& ref, double thickness, double density)
    : CbShellInertia(ref, thickness, std::vector<DensityLayer>{{-1.0, 1.0, density}}) {
  if (!(density > 0)) throw std::invalid_argument("CB shell inertia needs a positive thickness and density");
}

CbShellInertia::CbShellInertia(const ElementPoses& ref, const ShellSection& section, double density)
    : CbShellInertia(ref, section.thickness, density_layers(section, density)) {}

std::vector<CbShellInertia::DensityLayer> CbShellInertia::density_layers(const ShellSection& section, double density) {
  if (!section.plies) {
    if (!(density > 0)) throw std::invalid_argument("CB shell inertia needs a positive thickness and density");
    return {{-1.0, 1.0, density}};
  }
  std::vector<DensityLayer> layers;
  double below = 0.0, mass = 0.0;
  const std::vector<Ply>& plies = *section.plies;
  for (std::size_t k = 0; k < plies.size(); ++k) {  // (L6), as the element's layers
    const double lo = -1.0 + 2.0 * below / section.thickness;
    below += plies[k].thickness;
    const double hi = k + 1 == plies.size() ? 1.0 : -1.0 + 2.0 * below / section.thickness;
    layers.push_back({lo, hi, plies[k].density});
    mass += plies[k].density * plies[k].thickness;
  }
  if (!(mass > 0)) throw std::invalid_argument("CB shell inertia: the section's plies have no mass");
  return layers;
}

// (D3) with 3x3x3 Gauss points per layer: N_A N_B det J has degree <= 4 per direction, and the
// density is constant within a layer (L10)
CbShellInertia::CbShellInertia(const ElementPoses& ref, double thickness, const std::vector<DensityLayer>& layers)
    : half_h_(0.5 * thickness) {
  if (!(thickness > 0)) throw std::invalid_argument("CB shell inertia needs a positive thickness and density");
  Vec3 X[8];
  for (int A = 0; A < 8; ++A) X[A] = ref[A % 4].p + side(A) * half_h_ * ref[A % 4].R.col(2);  // (S1)
  const double gp[3] = {-std::sqrt(0.6), 0.0, std::sqrt(0.6)};
  const double gw[3] = {5.0 / 9.0, 8.0 / 9.0, 5.0 / 9.0};
  mass_matrix_.setZero();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      for (const DensityLayer& layer : layers) {
        const double mid = 0.5 * (layer.lo + layer.hi), half = 0.5 * (layer.hi - layer.lo);
        for (int k = 0; k < 3; ++k) {
          const double xi = gp[i], eta = gp[j], zeta = mid + half * gp[k];
          Eigen::Matrix<double, 8, 1> N;
          Vec3 G[3] = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
          for (int A = 0; A < 8; ++A) {
            const int I = A % 4;
            const double s = side(A), a = kXiNode[I], b = kEtaNode[I];
            const double nq = 0.25 * (1 + a * xi) * (1 + b * eta), nz = 0.5 * (1 + s * zeta);
            N[A] = nq * nz;
            G[0] += 0.25 * a * (1 + b * eta) * nz * X[A];
            G[1] += 0.25 * b * (1 + a * xi) * nz * X[A];
            G[2] += nq * 0.5 * s * X[A];
          }
          const double detJ = std::abs(G[0].dot(G[1].cross(G[2])));
          mass_matrix_.noalias() += (layer.density * gw[i] * gw[j] * (gw[k] * half) * detJ) * (N * N.transpose());
        }
      }
  slave_mass_ = mass_matrix_.rowwise().sum();
  for (int I = 0; I < 4; ++I)
    for (int J = 0; J < 4; ++J) {
      PairSums& ps = pair_sums_[I][J];
      ps = PairSums{};
      for (int si = 0; si < 2; ++si)
        for (int sj = 0; sj < 2; ++sj) {
          const int A = I + 4 * si, B = J + 4 * sj;
          const double m = mass_matrix_(A, B), sa = side(A) * half_h_, sb = side(B) * half_h_;
          ps.m += m, ps.m_a += m * sa, ps.m_b += m * sb, ps.m_ab += m * sa * sb;
          ps.c0[sj] += m, ps.c1[sj] += m * sa;
        }
    }
}

// (D5)-(D7) without the D term, term by term over the slave pairs A, B: the plain form of the
// sum, kept as the oracle of the per-pair form in evaluate()
void CbShellInertia::add_rate_and_position_blocks_plain(const ElementPoses& cur, const ElementRates& v,
                                                        const Vec3 w[8], const Vec3 b[8],
                                                        const InertiaJacobians& jac) const {
  const Mat3 e3x = hat(Vec3::UnitZ());
  for (int I = 0; I < 4; ++I)
    for (int J = 0; J < 4; ++J) {
      const Mat3 R_IJ = cur[I].R.transpose() * cur[J].R;  // R_IJ = R_WIᵀ R_WJ, I and J the node (corner) frames
      const Vec3 omJ = v[J].tail<3>();
      for (int si = 0; si < 2; ++si)
        for (int sj = 0; sj < 2; ++sj) {
          const int A = I + 4 * si, B = J + 4 * sj;
          const double mAB = mass_matrix_(A, B), shA = side(A) * half_h_, shB = side(B) * half_h_;
          if (jac.mass) jac.mass->block<6, 6>(6 * I, 6 * J) += mAB * sandwich(R_IJ, shA, shB, e3x);  // (D5)
          if (jac.gyroscopic) {                                                                   // (D6)
            Eigen::Matrix<double, 3, 6> G;
            G.leftCols<3>() = R_IJ * hat(omJ);
            G.rightCols<3>() = R_IJ * (-hat(w[B]) - shB * hat(omJ) * e3x);
            jac.gyroscopic->block<6, 6>(6 * I, 6 * J) += mAB * left(G, shA, e3x);
          }
          if (jac.stiffness) {                                                                    // (D7)
            Eigen::Matrix<double, 3, 6> G = Eigen::Matrix<double, 3, 6>::Zero();
            G.rightCols<3>() = -R_IJ * hat(b[B]);
            jac.stiffness->block<6, 6>(6 * I, 6 * J) += mAB * left(G, shA, e3x);
          }
        }
    }
}

void CbShellInertia::evaluate(const ElementPoses& cur, const ElementRates& v, const ElementRates& a, Vec24& F,
                              const InertiaJacobians& jac, const Vec3* g) const {
  const Vec3 e3 = Vec3::UnitZ();
  const Mat3 e3x = hat(e3);
  Vec3 w[8], b[8], acc[8];
  for (int A = 0; A < 8; ++A) {
    const int I = A % 4;
    const double sh = side(A) * half_h_;
    const Vec3 om = v[I].tail<3>();
    w[A] = v[I].head<3>() + sh * om.cross(e3);                                    // (D1)
    b[A] = a[I].head<3>() + sh * Vec3(a[I].tail<3>()).cross(e3) + om.cross(w[A]);  // (D2)
    acc[A] = cur[I].R * b[A];
  }
  Vec3 phi[8];
  for (int I = 0; I < 4; ++I) {  // the node's two slaves A = I, I + 4, summed in registers and
    Vec3 fu = Vec3::Zero(), ft = Vec3::Zero();  // written once (no read-back of F's segments)
    for (int A = I; A < 8; A += 4) {
      Vec3 f = Vec3::Zero();
      for (int B = 0; B < 8; ++B) f += mass_matrix_(A, B) * acc[B];
      if (g) f -= slave_mass_[A] * *g;                           // (D8), same slave and frame
      phi[A] = cur[I].R.transpose() * f;                        // (D4)
      fu += phi[A];
      ft += side(A) * half_h_ * e3.cross(phi[A]);
    }
    F.segment<3>(6 * I) = fu;
    F.segment<3>(6 * I + 3) = ft;
  }
  if (!jac.mass && !jac.gyroscopic && !jac.stiffness) return;
  if (jac.mass) jac.mass->setZero();
  if (jac.gyroscopic) jac.gyroscopic->setZero();
  if (jac.stiffness) jac.stiffness->setZero();
  if (plain_jacobians_) {
    add_rate_and_position_blocks_plain(cur, v, w, b, jac);
  } else {
    // (D5)-(D7) per node pair: the slaves' four thickness combinations enter only through
    // m_AB, s_A h/2 and s_B h/2, so their sums (pair_sums_, from the constructor) replace the
    // four blocks; the rate-dependent parts (w_B, b_B) keep the two slaves of J apart.
    // add_rate_and_position_blocks_plain is the same sum term by term (the test oracle).
    for (int I = 0; I < 4; ++I)
      for (int J = 0; J < 4; ++J) {
        const PairSums& ps = pair_sums_[I][J];
        const Mat3 R_IJ = cur[I].R.transpose() * cur[J].R;
        if (jac.mass) {  // (D5)
          auto blk = jac.mass->block<6, 6>(6 * I, 6 * J);
          const Mat3 Xe = R_IJ * e3x;
          blk.topLeftCorner<3, 3>() = ps.m * R_IJ;
          blk.topRightCorner<3, 3>() = -ps.m_b * Xe;
          blk.bottomLeftCorner<3, 3>() = ps.m_a * (e3x * R_IJ);
          blk.bottomRightCorner<3, 3>() = -ps.m_ab * (e3x * Xe);
        }
        if (jac.gyroscopic) {  // (D6)
          const Mat3 hom = hat(v[J].tail<3>());
          const Mat3 left3 = R_IJ * hom;
          Eigen::Matrix<double, 3, 6> G0, G1;
          G0.leftCols<3>() = (ps.c0[0] + ps.c0[1]) * left3;
          G1.leftCols<3>() = (ps.c1[0] + ps.c1[1]) * left3;
          Mat3 r0 = Mat3::Zero(), r1 = Mat3::Zero();
          for (int sj = 0; sj < 2; ++sj) {
            const int B = J + 4 * sj;
            const Mat3 right = R_IJ * (-hat(w[B]) - (side(B) * half_h_) * hom * e3x);
            r0 += ps.c0[sj] * right;
            r1 += ps.c1[sj] * right;
          }
          G0.rightCols<3>() = r0;
          G1.rightCols<3>() = r1;
          auto blk = jac.gyroscopic->block<6, 6>(6 * I, 6 * J);
          blk.topRows<3>() = G0;
          blk.bottomRows<3>() = e3x * G1;
        }
        if (jac.stiffness) {  // (D7) without its D term
          Mat3 r0 = Mat3::Zero(), r1 = Mat3::Zero();
          for (int sj = 0; sj < 2; ++sj) {
            const Mat3 right = -R_IJ * hat(b[J + 4 * sj]);
            r0 += ps.c0[sj] * right;
            r1 += ps.c1[sj] * right;
          }
          auto blk = jac.stiffness->block<6, 6>(6 * I, 6 * J);
          blk.topRightCorner<3, 3>() = r0;
          blk.bottomRightCorner<3, 3>() = e3x * r1;
        }
      }
  }
  if (jac.stiffness)
    for (int A = 0; A < 8; ++A) {  // D term of (D7) (and of (D8) with g): the local components of f_A turn with R_I
      const int I = A % 4;
      const Mat3 px = hat(phi[A]);
      jac.stiffness->block<3, 3>(6 * I, 6 * I + 3) += px;
      jac.stiffness->block<3, 3>(6 * I + 3, 6 * I + 3) += side(A) * half_h_ * e3x * px;
    }
}

void CbShellInertia::gravity(const ElementPoses& cur, const Vec3& g, Vec24& F, Mat24* dF) const {
  const Vec3 e3 = Vec3::UnitZ();
  const Mat3 e3x = hat(e3);
  F.setZero();
  if (dF) dF->setZero();
  for (int A = 0; A < 8; ++A) {  // (D8)
    const int I = A % 4;
    const double sh = side(A) * half_h_;
    const Vec3 phi = cur[I].R.transpose() * (slave_mass_[A] * g);
    F.segment<3>(6 * I) += phi;
    F.segment<3>(6 * I + 3) += sh * e3.cross(phi);
    if (!dF) continue;
    const Mat3 px = hat(phi);
    dF->block<3, 3>(6 * I, 6 * I + 3) += px;
    dF->block<3, 3>(6 * I + 3, 6 * I + 3) += sh * e3x * px;
  }
}

namespace {
void slave_states(const ElementPoses& cur, const ElementRates& v, double h2, Vec3 x[8], Vec3 xd[8]) {
  const Vec3 e3 = Vec3::UnitZ();
  for (int A = 0; A < 8; ++A) {
    const int I = A % 4;
    const double sh = side(A) * h2;
    x[A] = cur[I].p + sh * cur[I].R.col(2);
    xd[A] = cur[I].R * (v[I].head<3>() + sh * Vec3(v[I].tail<3>()).cross(e3));  // (D1)
  }
}
}  // namespace

double CbShellInertia::kinetic_energy(const ElementPoses& cur, const ElementRates& v) const {
  Vec3 x[8], xd[8];
  slave_states(cur, v, half_h_, x, xd);
  double t = 0.0;
  for (int A = 0; A < 8; ++A)
    for (int B = 0; B < 8; ++B) t += mass_matrix_(A, B) * xd[A].dot(xd[B]);
  return 0.5 * t;
}

void CbShellInertia::add_momenta(const ElementPoses& cur, const ElementRates& v, Vec3& p, Vec3& L) const {
  Vec3 x[8], xd[8];
  slave_states(cur, v, half_h_, x, xd);
  for (int A = 0; A < 8; ++A) {
    Vec3 pa = Vec3::Zero();
    for (int B = 0; B < 8; ++B) pa += mass_matrix_(A, B) * xd[B];
    p += pa;
    L += x[A].cross(pa);  // (D15)
  }
}

double CbShellInertia::gravity_potential(const ElementPoses& cur, const Vec3& g) const {
  double u = 0.0;
  for (int A = 0; A < 8; ++A) {
    const int I = A % 4;
    u -= slave_mass_[A] * g.dot(cur[I].p + side(A) * half_h_ * cur[I].R.col(2));
  }
  return u;
}

}  // namespace ff::shell
