// The mesh quality report as a scene gives it (core/scene/mesh_quality_report.h): inverted quads
// of a structure are refused at the part's mesh key with their numbers, the [mesh_quality] limits
// reach the measurement, and quads of a structure of several parts are named with their part.
#include <gtest/gtest.h>

#include "core/scene/mesh_quality_report.h"
#include "core/scene/scene_context.h"
#include "core/scene/shell_scene.h"
#include "core/scene/structure_parts.h"

using namespace ff::scene;

namespace {
const std::string kPlate = std::string(FF_SOURCE_DIR) + "/assets/scenes/clamped_plate_pressure.toml";

int line_of(const std::string& path, const std::string& text) {
  const Document d = validate_file(shell_static_schema(), path);
  const std::string& all = d.text();
  const auto at = all.find(text);
  return at == std::string::npos ? -1 : 1 + static_cast<int>(std::count(all.begin(), all.begin() + at, '\n'));
}
}  // namespace

TEST(MeshQualityReport, InvertedQuadsAreRefusedAtThePartWithTheirNumbers) {
  const Document d = validate_file(shell_static_schema(), kPlate);
  Structure s = read_structure(d, kPlate, {});
  // the plate's node (1, 1) at (0.125, 0.125) pushed past node (2, 2): the quads around it fold
  int moved = -1;
  for (int i = 0; i < s.joined.node_count(); ++i)
    if ((s.joined.points[i] - Eigen::Vector3d(0.125, 0.125, 0)).norm() < 1e-12) moved = i;
  ASSERT_GE(moved, 0);
  s.joined.points[moved] = {0.3, 0.3, 0.0};
  try {
    report_mesh_quality(d, s, {});
    FAIL() << "an inverted quad was accepted";
  } catch (const SceneError& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("key 'part[0].generator'"), std::string::npos) << what;
    EXPECT_NE(what.find(":" + std::to_string(line_of(kPlate, "generator = \"rectangular_plate\"")) + ":"),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("cannot be an element"), std::string::npos) << what;
    // the two quads beside the node get a reflex corner, the one beyond it turns over entirely
    EXPECT_NE(what.find("3 quads of the mesh cannot be an element"), std::string::npos) << what;
    EXPECT_NE(what.find("inverted quad: quad 1 has 1 corner"), std::string::npos) << what;
    EXPECT_NE(what.find("inverted quad: quad 8 has 1 corner"), std::string::npos) << what;
    EXPECT_NE(what.find("normal mismatch: quad 9 runs clockwise"), std::string::npos) << what;
  }
}

TEST(MeshQualityReport, LimitsComeFromTheScene) {
  const Document plain = validate_file(shell_static_schema(), kPlate);
  const Document strict = validate_file(shell_static_schema(), kPlate,
                                        {"mesh_quality.max_aspect_ratio=1.5", "mesh_quality.max_skew=5",
                                         "mesh_quality.max_warping=2", "mesh_quality.min_jacobian_ratio=0.9"});
  Structure s = read_structure(plain, kPlate, {});
  const ff::mesh::QualityThresholds defaults;
  MeshQualityReport context_copy;
  SceneContext ctx;
  ctx.mesh_quality = &context_copy;
  const MeshQualityReport a = report_mesh_quality(plain, s, ctx);
  EXPECT_EQ(a.quality.thresholds.max_aspect_ratio, defaults.max_aspect_ratio);
  EXPECT_EQ(a.quality.thresholds.min_jacobian_ratio, defaults.min_jacobian_ratio);
  EXPECT_EQ(context_copy.quality.quad_count, 64);  // left where the context points
  const MeshQualityReport b = report_mesh_quality(strict, s, {});
  EXPECT_EQ(b.quality.thresholds.max_aspect_ratio, 1.5);
  EXPECT_EQ(b.quality.thresholds.max_skew, 5.0);
  EXPECT_EQ(b.quality.thresholds.max_warping, 2.0);
  EXPECT_EQ(b.quality.thresholds.min_jacobian_ratio, 0.9);
  EXPECT_TRUE(b.warnings().empty());  // squares pass even these
  EXPECT_EQ(b.text().find("warning"), std::string::npos);
}

TEST(MeshQualityReport, QuadsOfSeveralPartsAreNamedWithTheirPart) {
  MeshQualityReport r;
  EXPECT_EQ(r.quad_name(12), "quad 12");
  r.part_names = {"skin", "stringer"};
  r.part_first_quad = {0, 10};
  EXPECT_EQ(r.quad_name(3), "quad 3 (part 'skin' quad 3)");
  EXPECT_EQ(r.quad_name(12), "quad 12 (part 'stringer' quad 2)");
}
