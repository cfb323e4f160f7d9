#pragma once
/// \file mesh_quality.h
/// The shape quality of every quad of a ShellMesh: aspect ratio, skew, warping and Jacobian
/// ratio (definitions, sources and default limits in core/mesh/mesh_quality.md), a summary per
/// metric (worst quad, median, the quads beyond the user's limit), and the quads no element can
/// be built on (inverted or degenerate), found by the same rules as validate() so that the two
/// never disagree.

#include <array>
#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"

namespace ff::mesh {

/// The four metrics, in the order of MeshQuality::metrics.
enum class QualityMetric { aspect_ratio, skew, warping, jacobian_ratio };
constexpr int quality_metric_count = 4;

/// Limits beyond which a quad is poor (a warning, never a refusal). Defaults: mesh_quality.md §6.
struct QualityThresholds {
  double max_aspect_ratio = 10.0;   ///< longest / shortest edge
  double max_skew = 60.0;           ///< degrees
  double max_warping = 10.0;        ///< degrees
  double min_jacobian_ratio = 0.3;  ///< min / max corner Jacobian determinant
};

/// One quad's metrics (mesh_quality.md §2-§5). For a quad validate() refuses, the values are
/// still computed where they are finite (a collapsed edge gives aspect ratio inf).
struct QuadQuality {
  double aspect_ratio = 1.0;    ///< >= 1; 1 for a square or rhombus
  double skew = 0.0;            ///< degrees in [0, 90]; 0 when the midside lines are perpendicular
  double warping = 0.0;         ///< degrees in [0, 180]; 0 for a flat quad
  double jacobian_ratio = 1.0;  ///< <= 1; 1 for a parallelogram; <= 0 inverted or collapsed
  double value(QualityMetric m) const;
};

/// Summary of one metric over the mesh.
struct MetricSummary {
  QualityMetric metric = QualityMetric::aspect_ratio;
  double worst = 0.0;       ///< largest (smallest for the Jacobian ratio) over the measured quads
  int worst_quad = -1;      ///< the quad that has it (the lowest number among equals); -1: no quads
  double typical = 0.0;     ///< median over the measured quads (mean of the two middle ones)
  double limit = 0.0;       ///< the threshold it was compared with
  std::vector<int> beyond;  ///< measured quads past the limit, worst first (equals by number)
};

struct MeshQuality {
  int node_count = 0;
  int quad_count = 0;
  QualityThresholds thresholds;
  std::vector<QuadQuality> quads;  ///< per quad of the mesh
  /// The quads validate() finds degenerate, inverted or running against their directors, and
  /// any layout / non-finite issue (then no metric is computed). Such a mesh cannot be run.
  std::vector<MeshIssue> refused;
  /// Per metric (index = QualityMetric), over the quads not refused.
  std::array<MetricSummary, quality_metric_count> metrics;

  bool ok() const { return refused.empty(); }
  const MetricSummary& summary(QualityMetric m) const { return metrics[static_cast<int>(m)]; }
  /// Quads past at least one limit.
  int poor_count() const;
};

/// "aspect_ratio", "skew", "warping", "jacobian_ratio": the metric's name in summary.json.
const char* metric_key(QualityMetric m);
/// "aspect ratio", "skew", ... for sentences.
const char* metric_label(QualityMetric m);
/// "" or "deg".
const char* metric_unit(QualityMetric m);
/// True for the Jacobian ratio (a small value is poor), false for the others.
bool smaller_is_worse(QualityMetric m);
/// The scene key of the metric's threshold in [mesh_quality], e.g. "max_aspect_ratio".
const char* threshold_key(QualityMetric m);
double threshold(const QualityThresholds& t, QualityMetric m);
/// Whether value v is past the limit of metric m.
bool beyond_limit(QualityMetric m, double v, double limit);

/// The metrics of quad q (corner directors from mesh.corner_normals).
QuadQuality quad_quality(const ShellMesh& mesh, int q);

/// Every quad measured, summarized and compared with the thresholds; refused quads from
/// validate() (they take no part in the summaries).
MeshQuality measure_quality(const ShellMesh& mesh, const QualityThresholds& thresholds = {});

}  // namespace ff::mesh
