#include "core/scene/mesh_quality_report.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>

#include "core/scene/scene_context.h"
#include "core/scene/structure_parts.h"

namespace ff::scene {

namespace {

using mesh::QualityMetric;
constexpr int named_in_warning = 5;   // poor quads named per metric
constexpr int named_in_refusal = 5;   // refused quads named per part

QualityMetric metric_at(int k) { return static_cast<QualityMetric>(k); }

std::string limit_sentence(QualityMetric m, double limit) {
  return std::string(mesh::smaller_is_worse(m) ? "below" : "above") + " mesh_quality." + mesh::threshold_key(m) +
         " = " + quality_value_text(m, limit);
}

}  // namespace

void declare_mesh_quality_keys(Schema& s) {
  const mesh::QualityThresholds defaults;
  s.table("mesh_quality",
          "limits of the mesh quality report (core/mesh/mesh_quality.md): a quad past one is named in a warning by "
          "`check` and `run`, never refused; inverted or degenerate quads are always refused")
      .number("mesh_quality.max_aspect_ratio",
              "longest over shortest edge of a quad; 10 is the limit the Polyflow manual advises (HyperMesh's guide: "
              "rarely above 5; OptiStruct warns only at 100)",
              defaults.max_aspect_ratio, Range::at_least(1.0))
      .number("mesh_quality.max_skew",
              "90 deg less the acute angle between the lines joining a quad's opposite edge midpoints; 60 is the "
              "warning limit of Nastran (GEOMCHECK Q4_SKEW = 30 deg between the lines) and OptiStruct",
              defaults.max_skew, Range::left_open(0.0, 90.0), "deg")
      .number("mesh_quality.max_warping",
              "the larger over a quad's two diagonal splits of the angle between the two triangles' normals; 10 is "
              "a unit square with one corner lifted 0.124 (OptiStruct warns at 30)",
              defaults.max_warping, Range::left_open(0.0, 180.0), "deg")
      .number("mesh_quality.min_jacobian_ratio",
              "smallest over largest mid-surface Jacobian determinant at a quad's corners (1 for a parallelogram; "
              "0.3 is a trapezoid whose parallel sides differ 3.3 times, 0.53 at the 2x2 Gauss points, below "
              "HyperMesh's 0.7 there)",
              defaults.min_jacobian_ratio, Range::closed(0.0, 1.0));
}

std::string quality_value_text(QualityMetric m, double v) {
  char buf[48];
  if (!std::isfinite(v)) return v > 0 ? "inf" : "-inf";
  switch (m) {
    case QualityMetric::aspect_ratio: std::snprintf(buf, sizeof buf, "%.3g", v); break;
    case QualityMetric::skew:
    case QualityMetric::warping: std::snprintf(buf, sizeof buf, "%.1f deg", v); break;
    case QualityMetric::jacobian_ratio: std::snprintf(buf, sizeof buf, "%.3f", v); break;
  }
  return buf;
}

std::string MeshQualityReport::quad_name(int q) const {
  std::string name = "quad " + std::to_string(q);
  if (part_names.size() < 2) return name;
  std::size_t p = 0;
  while (p + 1 < part_first_quad.size() && part_first_quad[p + 1] <= q) ++p;
  return name + " (part '" + part_names[p] + "' quad " + std::to_string(q - part_first_quad[p]) + ")";
}

std::vector<std::string> MeshQualityReport::warnings() const {
  std::vector<std::string> out;
  for (int k = 0; k < mesh::quality_metric_count; ++k) {
    const QualityMetric m = metric_at(k);
    const mesh::MetricSummary& s = quality.metrics[k];
    if (s.beyond.empty()) continue;
    const std::size_t n = s.beyond.size();
    const bool vowel = std::string("aeiou").find(mesh::metric_label(m)[0]) != std::string::npos;
    std::string line = std::to_string(n) + (n == 1 ? " quad has " : " quads have ") + (vowel ? "an " : "a ") +
                       mesh::metric_label(m) + " " + limit_sentence(m, s.limit) + ": ";
    for (std::size_t i = 0; i < n && i < static_cast<std::size_t>(named_in_warning); ++i)
      line += (i ? ", " : "") + quad_name(s.beyond[i]) + " = " +
              quality_value_text(m, quality.quads[s.beyond[i]].value(m));
    if (n > static_cast<std::size_t>(named_in_warning))
      line += ", and " + std::to_string(n - named_in_warning) + " more";
    out.push_back(line);
  }
  return out;
}

std::string MeshQualityReport::text() const {
  std::string out = "mesh quality: " + std::to_string(quality.quad_count) + " quads, " +
                    std::to_string(quality.node_count) + " nodes";
  if (part_names.size() > 1) out += " in " + std::to_string(part_names.size()) + " parts";
  const int poor = quality.poor_count();
  out += "; " + (poor == 0 ? std::string("none past the limits") : std::to_string(poor) + " past a limit") + "\n";
  for (int k = 0; k < mesh::quality_metric_count; ++k) {
    const QualityMetric m = metric_at(k);
    const mesh::MetricSummary& s = quality.metrics[k];
    char head[32];
    std::snprintf(head, sizeof head, "  %-15s", mesh::metric_label(m));
    out += head;
    if (s.worst_quad < 0) {
      out += "not measured\n";
      continue;
    }
    out += "worst " + quality_value_text(m, s.worst) + " at " + quad_name(s.worst_quad) + ", typical " +
           quality_value_text(m, s.typical) + ", limit " + quality_value_text(m, s.limit) + ": " +
           std::to_string(s.beyond.size()) + " past it\n";
  }
  for (const std::string& w : warnings()) out += "warning: " + w + "\n";
  return out;
}

MeshQualityReport report_mesh_quality(const Document& d, const Structure& structure, const SceneContext& ctx) {
  mesh::QualityThresholds t;
  t.max_aspect_ratio = d.number("mesh_quality.max_aspect_ratio");
  t.max_skew = d.number("mesh_quality.max_skew");
  t.max_warping = d.number("mesh_quality.max_warping");
  t.min_jacobian_ratio = d.number("mesh_quality.min_jacobian_ratio");
  MeshQualityReport r;
  r.quality = mesh::measure_quality(structure.joined, t);
  for (std::size_t p = 0; p < structure.parts.size(); ++p) {
    r.part_names.push_back(structure.parts[p].name);
    r.part_first_quad.push_back(structure.first_quad(static_cast<int>(p)));
  }
  if (!r.quality.ok()) {
    // one issue per part, at the key that made its mesh, naming its first refused quads
    std::map<std::size_t, std::vector<const mesh::MeshIssue*>> by_part;
    for (const mesh::MeshIssue& issue : r.quality.refused) {
      std::size_t p = 0;
      if (issue.quad >= 0 && issue.quad < static_cast<int>(structure.quad_part.size()))
        p = static_cast<std::size_t>(structure.quad_part[issue.quad]);
      by_part[p].push_back(&issue);
    }
    std::vector<Issue> issues;
    for (const auto& [p, list] : by_part) {
      std::string message = std::to_string(list.size()) + (list.size() == 1 ? " quad" : " quads") +
                            " of the mesh cannot be an element (inverted or degenerate; fix the mesh): ";
      for (std::size_t i = 0; i < list.size() && i < static_cast<std::size_t>(named_in_refusal); ++i) {
        const mesh::MeshIssue& issue = *list[i];
        message += (i ? "; " : "") + std::string(mesh::to_string(issue.kind)) + ": " + issue.message;
        if (issue.quad >= 0 && r.part_names.size() > 1) message += " [" + r.quad_name(issue.quad) + "]";
      }
      if (list.size() > static_cast<std::size_t>(named_in_refusal))
        message += "; and " + std::to_string(list.size() - named_in_refusal) + " more";
      const bool from_file = p < structure.parts.size() && structure.parts[p].from_file;
      issues.push_back(d.issue(from_file ? "part.file" : "part.generator", p, message));
    }
    throw SceneError(std::move(issues));
  }
  if (ctx.mesh_quality) *ctx.mesh_quality = r;
  return r;
}

}  // namespace ff::scene
