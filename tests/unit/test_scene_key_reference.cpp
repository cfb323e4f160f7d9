// The scene-key reference (docs/reference/scene-keys.md) is generated from the schema; this keeps
// the two from drifting.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/scene/scene.h"
#include "core/scene/shell_dynamic_scene.h"
#include "core/scene/shell_scene.h"

TEST(SceneKeyReference, MatchesSchema) {
  std::ifstream in(std::string(FF_SOURCE_DIR) + "/docs/reference/scene-keys.md");
  ASSERT_TRUE(in) << "docs/reference/scene-keys.md not found";
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string text = ss.str(), begin = "<!-- scene-reference:begin -->\n", end = "<!-- scene-reference:end -->";
  const auto b = text.find(begin), e = text.find(end);
  ASSERT_NE(b, std::string::npos);
  ASSERT_NE(e, std::string::npos);
  EXPECT_EQ(text.substr(b + begin.size(), e - b - begin.size()), ff::scene::scene_reference_markdown())
      << "regenerate with: flexframe scenes --reference > docs/reference/scene-keys.md (between the markers)";
}

// issue 30, item 11: the dynamic model's patch_edge keys promised the generators' edge names
// ("x_min", "rim"), which its bodies' meshes do not have: each dynamic .edge key now names only
// what dynamics accepts, the static ones keep the names their generators give, and the double
// pendulum indeed refuses "x_min" at the key and takes "u=1".
// Issue 31: one set of edge names per generator, the same in every model. The dynamic model's
// parts come from the same generators as the static one's, so a cut cylinder's edges are
// start_angle/end_angle/bottom/top there too (and u=0 ... v=1 still), and an edge the generator
// does not have is refused at the key.
TEST(SceneKeyReference, EdgeNamesAreTheGeneratorsInEveryModel) {
  for (const auto* schema : {&ff::scene::shell_dynamic_schema(), &ff::scene::shell_static_schema()})
    for (const char* key : {"joint.edge", "probe.edge", "bc.edge", "load.edge"}) {
      const auto* k = schema->find_key(key);
      if (!k) continue;
      EXPECT_NE(k->doc.find("x_min"), std::string::npos) << key << ": " << k->doc;
      EXPECT_NE(k->doc.find("generator's name"), std::string::npos) << key << ": " << k->doc;
    }
  const std::string scene = std::string(FF_SOURCE_DIR) + "/assets/scenes/double_pendulum_shells.toml";
  try {
    ff::scene::load_scene(scene, {"joint[1].edge=\"x_min\""});
    ADD_FAILURE() << "edge \"x_min\" of a cylinder part was accepted";
  } catch (const ff::scene::SceneError& e) {
    EXPECT_NE(std::string(e.what()).find("x_min"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("joint"), std::string::npos) << e.what();
  }
  EXPECT_NO_THROW(ff::scene::load_scene(scene, {"joint[1].edge=\"u=1\""}));
  EXPECT_NO_THROW(ff::scene::load_scene(scene, {"joint[1].edge=\"end_angle\""}));
}
