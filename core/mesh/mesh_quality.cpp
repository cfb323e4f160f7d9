#include "core/mesh/mesh_quality.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

namespace ff::mesh {

namespace {

using Vec3 = Eigen::Vector3d;
constexpr double rad_to_deg = 180.0 / 3.14159265358979323846;

// the angle between two vectors in degrees, [0, 180]; 0 when either is zero (atan2 of |a x b|
// and a.b stays accurate near 0 and 180 where acos of the cosine does not)
double angle_deg(const Vec3& a, const Vec3& b) { return std::atan2(a.cross(b).norm(), a.dot(b)) * rad_to_deg; }

bool shape_issue(IssueKind k) {
  return k == IssueKind::degenerate_quad || k == IssueKind::inverted_quad || k == IssueKind::normal_mismatch ||
         k == IssueKind::layout || k == IssueKind::non_finite;
}

}  // namespace

double QuadQuality::value(QualityMetric m) const {
  switch (m) {
    case QualityMetric::aspect_ratio: return aspect_ratio;
    case QualityMetric::skew: return skew;
    case QualityMetric::warping: return warping;
    case QualityMetric::jacobian_ratio: return jacobian_ratio;
  }
  return 0.0;
}

int MeshQuality::poor_count() const {
  int n = 0;
  std::vector<char> poor(quads.size(), 0);
  for (const MetricSummary& s : metrics)
    for (int q : s.beyond)
      if (!poor[q]) poor[q] = 1, ++n;
  return n;
}

const char* metric_key(QualityMetric m) {
  switch (m) {
    case QualityMetric::aspect_ratio: return "aspect_ratio";
    case QualityMetric::skew: return "skew";
    case QualityMetric::warping: return "warping";
    case QualityMetric::jacobian_ratio: return "jacobian_ratio";
  }
  return "";
}

const char* metric_label(QualityMetric m) {
  switch (m) {
    case QualityMetric::aspect_ratio: return "aspect ratio";
    case QualityMetric::skew: return "skew";
    case QualityMetric::warping: return "warping";
    case QualityMetric::jacobian_ratio: return "Jacobian ratio";
  }
  return "";
}

const char* metric_unit(QualityMetric m) {
  return m == QualityMetric::skew || m == QualityMetric::warping ? "deg" : "";
}

bool smaller_is_worse(QualityMetric m) { return m == QualityMetric::jacobian_ratio; }

const char* threshold_key(QualityMetric m) {
  switch (m) {
    case QualityMetric::aspect_ratio: return "max_aspect_ratio";
    case QualityMetric::skew: return "max_skew";
    case QualityMetric::warping: return "max_warping";
    case QualityMetric::jacobian_ratio: return "min_jacobian_ratio";
  }
  return "";
}

double threshold(const QualityThresholds& t, QualityMetric m) {
  switch (m) {
    case QualityMetric::aspect_ratio: return t.max_aspect_ratio;
    case QualityMetric::skew: return t.max_skew;
    case QualityMetric::warping: return t.max_warping;
    case QualityMetric::jacobian_ratio: return t.min_jacobian_ratio;
  }
  return 0.0;
}

bool beyond_limit(QualityMetric m, double v, double limit) { return smaller_is_worse(m) ? v < limit : v > limit; }

QuadQuality quad_quality(const ShellMesh& mesh, int q) {
  const auto& c = mesh.quads[q];
  std::array<Vec3, 4> x;
  for (int k = 0; k < 4; ++k) x[k] = mesh.points[c[k]];
  QuadQuality r;

  // §2 aspect ratio: longest over shortest edge
  double longest = 0.0, shortest = std::numeric_limits<double>::infinity();
  for (int k = 0; k < 4; ++k) {
    const double e = (x[(k + 1) % 4] - x[k]).norm();
    longest = std::max(longest, e), shortest = std::min(shortest, e);
  }
  r.aspect_ratio = shortest > 0 ? longest / shortest : std::numeric_limits<double>::infinity();

  // §3 skew: 90 deg less the acute angle between the lines joining opposite edge midpoints
  const Vec3 across_u = (x[1] + x[2]) - (x[0] + x[3]);  // twice the line from edge 3-0 to edge 1-2
  const Vec3 across_v = (x[2] + x[3]) - (x[0] + x[1]);  // twice the line from edge 0-1 to edge 2-3
  const double between = angle_deg(across_u, across_v);
  r.skew = 90.0 - std::min(between, 180.0 - between);

  // §4 warping: the larger over the two diagonal splits of the angle between the triangles' normals
  const double split_02 = angle_deg((x[1] - x[0]).cross(x[2] - x[0]), (x[2] - x[0]).cross(x[3] - x[0]));
  const double split_13 = angle_deg((x[2] - x[1]).cross(x[3] - x[1]), (x[3] - x[1]).cross(x[0] - x[1]));
  r.warping = std::max(split_02, split_13);

  // §5 Jacobian ratio: the mid-surface Jacobian determinant (x_xi x x_eta) . d at the corners,
  // d the corner director; the smallest over the largest magnitude (<= 0 when a corner turns
  // clockwise about its director or collapses, the corners validate() refuses)
  std::array<double, 4> det{};
  for (int k = 0; k < 4; ++k) {
    const Vec3 along = x[(k + 1) % 4] - x[k], back = x[(k + 3) % 4] - x[k];
    const Vec3& d = q < static_cast<int>(mesh.corner_normals.size()) ? mesh.corner_normals[q][k] : mesh.normals[c[k]];
    // the corner's two edges are +-2 x_xi and +-2 x_eta in the order that keeps the sign
    det[k] = 0.25 * along.cross(back).dot(d);
  }
  double largest = 0.0;
  for (double v : det) largest = std::max(largest, std::abs(v));
  r.jacobian_ratio = largest > 0 ? *std::min_element(det.begin(), det.end()) / largest : 0.0;
  return r;
}

MeshQuality measure_quality(const ShellMesh& mesh, const QualityThresholds& thresholds) {
  MeshQuality out;
  out.node_count = mesh.node_count();
  out.quad_count = mesh.quad_count();
  out.thresholds = thresholds;
  for (int m = 0; m < quality_metric_count; ++m) {
    out.metrics[m].metric = static_cast<QualityMetric>(m);
    out.metrics[m].limit = threshold(thresholds, static_cast<QualityMetric>(m));
  }
  // the refusals are validate()'s own shape rules, so `check`, the importer and the scene agree
  const MeshCheck check = validate(mesh);
  std::vector<char> refused(mesh.quads.size(), 0);
  bool layout_broken = false;
  for (const MeshIssue& issue : check.issues) {
    if (!shape_issue(issue.kind)) continue;
    out.refused.push_back(issue);
    if (issue.kind == IssueKind::layout || issue.kind == IssueKind::non_finite) layout_broken = true;
    if (issue.quad >= 0 && issue.quad < out.quad_count) refused[issue.quad] = 1;
  }
  if (layout_broken) return out;  // indices or coordinates cannot be trusted: nothing is measured

  out.quads.resize(mesh.quads.size());
  std::vector<int> measured;
  for (int q = 0; q < out.quad_count; ++q) {
    out.quads[q] = quad_quality(mesh, q);
    if (!refused[q]) measured.push_back(q);
  }
  if (measured.empty()) return out;
  for (int m = 0; m < quality_metric_count; ++m) {
    const QualityMetric metric = static_cast<QualityMetric>(m);
    MetricSummary& s = out.metrics[m];
    const bool low_bad = smaller_is_worse(metric);
    auto worse = [&](int a, int b) {  // a before b: worse value, then lower number
      const double va = out.quads[a].value(metric), vb = out.quads[b].value(metric);
      if (va != vb) return low_bad ? va < vb : va > vb;
      return a < b;
    };
    std::vector<double> values;
    values.reserve(measured.size());
    for (int q : measured) {
      values.push_back(out.quads[q].value(metric));
      if (beyond_limit(metric, out.quads[q].value(metric), s.limit)) s.beyond.push_back(q);
    }
    s.worst_quad = *std::min_element(measured.begin(), measured.end(), worse);
    s.worst = out.quads[s.worst_quad].value(metric);
    std::sort(s.beyond.begin(), s.beyond.end(), worse);
    const std::size_t n = values.size(), mid = n / 2;
    std::nth_element(values.begin(), values.begin() + mid, values.end());
    s.typical = values[mid];
    if (n % 2 == 0) s.typical = 0.5 * (s.typical + *std::max_element(values.begin(), values.begin() + mid));
  }
  return out;
}

}  // namespace ff::mesh
