#include "core/shell/error_indicator.h"

#include <algorithm>
#include <cmath>
#include <functional>

namespace ff::shell {

namespace {
constexpr int kComponents = 15;  // N^W and M^W (6 each, symmetric 3 x 3), Q^W (3): (Z4)
using WorldResultant = Eigen::Matrix<double, kComponents, 1>;

// (Z4): a symmetric in-plane tensor [a11 a22 a12] in the frame's t1, t2 as world components
// [xx yy zz xy yz xz] of T a T^T, T = [t1 t2]
void tensor_to_world(const Eigen::Matrix3d& frame, double a11, double a22, double a12, double* w) {
  const Eigen::Vector3d t1 = frame.col(0), t2 = frame.col(1);
  const int ij[6][2] = {{0, 0}, {1, 1}, {2, 2}, {0, 1}, {1, 2}, {0, 2}};
  for (int c = 0; c < 6; ++c) {
    const int i = ij[c][0], j = ij[c][1];
    w[c] = a11 * t1[i] * t1[j] + a22 * t2[i] * t2[j] + a12 * (t1[i] * t2[j] + t2[i] * t1[j]);
  }
}
// (Z6): the in-plane components [a11 a22 a12] of the world tensor w in the frame's t1, t2
Eigen::Vector3d tensor_from_world(const Eigen::Matrix3d& frame, const double* w) {
  Eigen::Matrix3d A;
  A << w[0], w[3], w[5], w[3], w[1], w[4], w[5], w[4], w[2];
  const Eigen::Vector3d t1 = frame.col(0), t2 = frame.col(1);
  return {t1.dot(A * t1), t2.dot(A * t2), t1.dot(A * t2)};
}

WorldResultant to_world(const Eigen::Matrix3d& frame, const Eigen::Matrix<double, 8, 1>& r) {
  WorldResultant w;
  tensor_to_world(frame, r[0], r[1], r[2], w.data());
  tensor_to_world(frame, r[3], r[4], r[5], w.data() + 6);
  w.tail<3>() = frame.col(0) * r[6] + frame.col(1) * r[7];
  return w;
}
Eigen::Matrix<double, 8, 1> from_world(const Eigen::Matrix3d& frame, const WorldResultant& w) {
  Eigen::Matrix<double, 8, 1> r;
  r.head<3>() = tensor_from_world(frame, w.data());
  r.segment<3>(3) = tensor_from_world(frame, w.data() + 6);
  r[6] = frame.col(0).dot(w.tail<3>()), r[7] = frame.col(1).dot(w.tail<3>());
  return r;
}

// What the recovery keeps of one element between its two passes: its samples (about 1 kB, so
// that the element kernel runs once per element) and their world tensors.
struct Sampled {
  ResultantSamples samples;
  std::array<WorldResultant, 4> world;
  double size2 = 0.0;  // its reference area: the patch's length scale squared
};

// bilinear functions of the corners (counter-clockwise from (-1, -1)) at (xi, eta)
std::array<double, 4> corner_weights(double xi, double eta) {
  return {0.25 * (1 - xi) * (1 - eta), 0.25 * (1 + xi) * (1 - eta), 0.25 * (1 + xi) * (1 + eta),
          0.25 * (1 - xi) * (1 + eta)};
}
}  // namespace

RecoveredErrorIndicator recovered_error_indicator(const ShellElements& elements, const std::vector<NodePose>& reference,
                                                  const std::vector<NodePose>& current) {
  RecoveredErrorIndicator out;
  const int ne = elements.size();
  const std::size_t nn = reference.size();
  out.element_error2.assign(ne, 0.0), out.element_energy2.assign(ne, 0.0), out.element.assign(ne, 0.0);
  out.nodal.assign(nn, 0.0);
  if (ne == 0) return out;

  // pass 1: every element's resultants at its points, as world tensors on the reference (Z3)-(Z4)
  std::vector<Sampled> sampled(ne);
  std::vector<std::vector<int>> on_node(nn);
  ElementPoses ref, cur;
  for (int k = 0; k < ne; ++k) {
    const ShellElement& e = elements[k];
    ShellElements::corner_poses(e, reference, ref);
    ShellElements::corner_poses(e, current, cur);
    Sampled& s = sampled[k];
    const ResultantSamples& rs = s.samples;
    e.elastic->resultant_samples(ref, cur, s.samples);
    for (int g = 0; g < 4; ++g) s.world[g] = to_world(rs.frame, rs.resultant[g]);
    s.size2 = rs.area[0] + rs.area[1] + rs.area[2] + rs.area[3];
    for (int n : e.nodes) on_node[n].push_back(k);
  }

  // pass 2: per corner the patch fit (Z5), the recovered field at the points (Z6), the error (Z7)
  const double cos_fold = std::cos(kRecoveryFoldAngleDeg * M_PI / 180.0);
  for (int k = 0; k < ne; ++k) {
    const ShellElement& e = elements[k];
    const Sampled& own = sampled[k];
    const Eigen::Matrix3d& frame = own.samples.frame;
    const Eigen::Vector3d normal = frame.col(2), u = frame.col(0), v = frame.col(1);
    std::array<WorldResultant, 4> at_corner;
    for (int c = 0; c < 4; ++c) {
      const int n = e.nodes[c];
      const Eigen::Vector3d xn = reference[n].p;
      // least squares of a0 + a1 a + a2 b over the patch's points, a and b along u and v per the
      // patch's length (a scale keeps the normal equations of a tiny or huge mesh conditioned)
      Eigen::Matrix3d PtP = Eigen::Matrix3d::Zero();
      Eigen::Matrix<double, 3, kComponents> PtY = Eigen::Matrix<double, 3, kComponents>::Zero();
      WorldResultant mean = WorldResultant::Zero();
      int count = 0;
      double scale2 = 0.0;
      for (int m : on_node[n])
        if (sampled[m].samples.frame.col(2).dot(normal) >= cos_fold) scale2 += sampled[m].size2;
      const double inv_scale = 1.0 / std::sqrt(scale2);
      for (int m : on_node[n]) {
        const Sampled& s = sampled[m];
        if (s.samples.frame.col(2).dot(normal) < cos_fold) continue;  // across a fold: (Z5)
        for (int g = 0; g < 4; ++g) {
          const Eigen::Vector3d d = (s.samples.position[g] - xn) * inv_scale;
          const Eigen::Vector3d p(1.0, d.dot(u), d.dot(v));
          PtP.noalias() += p * p.transpose();
          PtY.noalias() += p * s.world[g].transpose();
          mean += s.world[g], ++count;
        }
      }
      // a patch whose points do not span the plane (cannot happen with 2 x 2 points of a
      // non-degenerate element, kept for safety) takes the mean instead: a determinant tiny
      // beside the cube of the trace (the eigenvalues' product beside their sum's cube)
      const double trace = PtP.trace();
      if (PtP.determinant() > 1e-12 * trace * trace * trace)
        at_corner[c] = (PtP.ldlt().solve(PtY)).row(0).transpose();
      else
        at_corner[c] = mean / count;
    }
    const ResultantSamples& rs = own.samples;
    double err2 = 0.0, en2 = 0.0;
    for (int g = 0; g < 4; ++g) {
      const std::array<double, 4> w = corner_weights(rs.xi[g], rs.eta[g]);
      WorldResultant star = WorldResultant::Zero();
      for (int c = 0; c < 4; ++c) star += w[c] * at_corner[c];
      const Eigen::Matrix<double, 8, 1> diff = from_world(rs.frame, star) - rs.resultant[g];
      err2 += rs.area[g] * diff.dot(rs.compliance * diff);
      en2 += rs.area[g] * rs.resultant[g].dot(rs.compliance * rs.resultant[g]);
    }
    out.element_error2[k] = err2, out.element_energy2[k] = en2;
    out.error2 += err2, out.energy2 += en2;
    if (out.worst < 0 || err2 > out.element_error2[out.worst]) out.worst = k;
  }

  // (Z8), (Z9)
  const double total = out.energy2 + out.error2;
  out.relative = total > 0 ? std::sqrt(out.error2 / total) : 0.0;
  std::vector<int> count(nn, 0);
  for (int k = 0; k < ne; ++k) {
    out.element[k] = total > 0 ? std::sqrt(ne * out.element_error2[k] / total) : 0.0;
    for (int n : elements[k].nodes) out.nodal[n] += out.element[k], ++count[n];
  }
  for (std::size_t n = 0; n < nn; ++n)
    if (count[n]) out.nodal[n] /= count[n];
  return out;
}

FieldErrorEstimate summarize(const RecoveredErrorIndicator& ind, const ShellElements& elements,
                             const std::vector<NodePose>& reference) {
  FieldErrorEstimate s;
  s.relative_energy_error = ind.relative;
  s.elements = elements.size();
  if (ind.worst < 0) return s;
  Eigen::Vector3d c = Eigen::Vector3d::Zero();
  for (int n : elements[ind.worst].nodes) c += 0.25 * reference[n].p;
  s.worst_at = {c.x(), c.y(), c.z()};
  s.worst_indicator = ind.element[ind.worst];
  std::vector<double> e2 = ind.element_error2;
  std::sort(e2.begin(), e2.end(), std::greater<>());
  double carried = 0.0;
  std::size_t k = 0;
  while (k < e2.size() && carried < 0.5 * ind.error2) carried += e2[k++];
  s.half_error_fraction = e2.empty() ? 0.0 : static_cast<double>(k) / e2.size();
  return s;
}

}  // namespace ff::shell
