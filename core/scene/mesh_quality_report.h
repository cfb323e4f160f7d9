#pragma once
/// \file mesh_quality_report.h
/// The mesh quality report of a shell structure (core/mesh/mesh_quality.h) as a scene gives it:
/// thresholds from its [mesh_quality] table, quads named with their part, inverted or degenerate
/// quads refused at the part's mesh key, poor quads as warnings. `flexframe check` prints it and
/// a run's summary.json carries it ("mesh_quality").

#include <string>
#include <vector>

#include "core/mesh/mesh_quality.h"
#include "core/scene/schema.h"

namespace ff::scene {

struct Structure;
struct SceneContext;

/// Declares [mesh_quality] (the four thresholds); declare_structure_keys calls it.
void declare_mesh_quality_keys(Schema& s);

struct MeshQualityReport {
  mesh::MeshQuality quality;
  /// per part (in part order): its name and its first quad in the joined structure
  std::vector<std::string> part_names;
  std::vector<int> part_first_quad;
  /// "quad 17", or "quad 17 (part 'skin' quad 5)" in a structure of several parts
  std::string quad_name(int q) const;
  /// one sentence per metric that has quads past its limit, naming the worst few with values
  std::vector<std::string> warnings() const;
  /// the report as `check` prints it: counts, worst and typical per metric, then the warnings
  /// (each line starting "warning: ")
  std::string text() const;
};

/// Measures the joined structure against the document's thresholds. Inverted or degenerate quads
/// are refused: a SceneError at each affected part's mesh key (part.file or part.generator)
/// naming the quads. When ctx.mesh_quality is set, the report is left there.
MeshQualityReport report_mesh_quality(const Document& d, const Structure& structure, const SceneContext& ctx);

/// A metric's value for sentences: aspect ratio to 3 significant digits ("2.59"), skew and warping
/// to 0.1 deg ("26.6 deg"), Jacobian ratio to 3 decimals ("0.808").
std::string quality_value_text(mesh::QualityMetric m, double v);

}  // namespace ff::scene
