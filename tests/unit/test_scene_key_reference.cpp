// The scene-key reference (docs/reference/scene-keys.md) is generated from the schema; this keeps
// the two from drifting.
#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

#include "core/scene/scene.h"

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
