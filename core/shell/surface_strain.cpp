#include "core/shell/surface_strain.h"

#include <algorithm>
#include <cmath>

namespace ff::shell {

namespace {
// dN/dxi and dN/deta of the bilinear corners at the centre (counter-clockwise corners
// (-1,-1), (1,-1), (1,1), (-1,1))
constexpr double kDxi[4] = {-0.25, 0.25, 0.25, -0.25};
constexpr double kDeta[4] = {-0.25, -0.25, 0.25, 0.25};

/// Covariant base vectors at the centre on the surface zeta (cb_shell.md eq. V1).
/// X_WC: the element's corner poses.
void base_vectors(const ElementPoses& X_WC, double half_h, double zeta, Vec3& g1, Vec3& g2) {
  g1.setZero();
  g2.setZero();
  for (int c = 0; c < 4; ++c) {
    const Vec3 point = X_WC[c].p + zeta * half_h * X_WC[c].R.col(2);
    g1 += kDxi[c] * point;
    g2 += kDeta[c] * point;
  }
}
}  // namespace

double max_surface_strain(const ElementPoses& ref, const ElementPoses& cur, double thickness) {
  double largest = 0.0;
  for (double zeta : {-1.0, 0.0, 1.0}) {
    Vec3 G1, G2, g1, g2;
    base_vectors(ref, 0.5 * thickness, zeta, G1, G2);
    base_vectors(cur, 0.5 * thickness, zeta, g1, g2);
    // metric M and covariant strain E_ab = (g_a.g_b - G_a.G_b) / 2 (eq. V2)
    const double m11 = G1.dot(G1), m12 = G1.dot(G2), m22 = G2.dot(G2);
    const double e11 = 0.5 * (g1.dot(g1) - m11), e12 = 0.5 * (g1.dot(g2) - m12), e22 = 0.5 * (g2.dot(g2) - m22);
    // principal strains: eigenvalues of the mixed tensor M^-1 E (eq. V3)
    const double det_m = m11 * m22 - m12 * m12;
    const double a11 = (m22 * e11 - m12 * e12) / det_m, a12 = (m22 * e12 - m12 * e22) / det_m;
    const double a21 = (m11 * e12 - m12 * e11) / det_m, a22 = (m11 * e22 - m12 * e12) / det_m;
    const double mean = 0.5 * (a11 + a22), det = a11 * a22 - a12 * a21;
    const double radius = std::sqrt(std::max(0.0, mean * mean - det));
    largest = std::max({largest, std::abs(mean + radius), std::abs(mean - radius)});
  }
  return largest;
}

std::vector<double> average_to_nodes(const std::vector<double>& values, const std::vector<std::array<int, 4>>& nodes,
                                     int node_count) {
  std::vector<double> sum(node_count, 0.0);
  std::vector<int> count(node_count, 0);
  for (std::size_t e = 0; e < values.size(); ++e)
    for (int n : nodes[e]) {
      sum[n] += values[e];
      ++count[n];
    }
  for (int n = 0; n < node_count; ++n)
    if (count[n] > 0) sum[n] /= count[n];
  return sum;
}

}  // namespace ff::shell
