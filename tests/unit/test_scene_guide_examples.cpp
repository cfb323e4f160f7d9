// The scene guide's examples stay valid (docs/guide/writing-a-scene.md): every ```toml block that
// is a whole scene (it has a [scene] table) is read and built as `flexframe check` does, and every
// other block (a fragment: a [[part]], a [[bc]], a [[joint]] ...) is validated against the schema
// of the analysis it is written for, appended to the guide's first whole scene of that analysis
// (fragments before "## The dynamic path" to the static one, those after it to the dynamic one).
// A key renamed or removed in the code, or a block that no longer builds, fails here with the
// block's first line and the scene error.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/scene/scene.h"
#include "core/scene/shell_dynamic_scene.h"
#include "core/scene/shell_scene.h"

namespace {

struct Block {
  std::string text;
  std::size_t offset = 0;  // where it starts in the guide
  bool whole_scene = false;
  bool dynamic_part = false;  // after "## The dynamic path"
};

std::string guide_text() {
  std::ifstream in(std::string(FF_SOURCE_DIR) + "/docs/guide/writing-a-scene.md");
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// the ```toml blocks, with the indentation of their fence (a block inside a list item) removed
std::vector<Block> toml_blocks(const std::string& guide) {
  std::vector<Block> out;
  const std::size_t dynamic_path = guide.find("\n## The dynamic path");
  std::istringstream lines(guide);
  std::string line, indent;
  std::size_t offset = 0;
  bool inside = false;
  Block b;
  while (std::getline(lines, line)) {
    const std::size_t here = offset;
    offset += line.size() + 1;
    const std::size_t first = line.find_first_not_of(' ');
    const std::string trimmed = first == std::string::npos ? "" : line.substr(first);
    if (!inside && trimmed == "```toml") {
      inside = true, indent = line.substr(0, first), b = Block{}, b.offset = here;
      b.dynamic_part = dynamic_path != std::string::npos && here > dynamic_path;
    } else if (inside && trimmed == "```") {
      inside = false;
      out.push_back(b);
    } else if (inside) {
      const std::string body = line.compare(0, indent.size(), indent) == 0 ? line.substr(indent.size()) : line;
      if (body == "[scene]") b.whole_scene = true;
      b.text += body + "\n";
    }
  }
  return out;
}

std::string first_line(const Block& b) { return b.text.substr(0, b.text.find('\n')); }

std::string write_scene(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::temp_directory_path() / ("ff_guide_examples_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const auto path = dir / (name + ".toml");
  std::ofstream(path) << text;
  return path.string();
}

TEST(SceneGuide, EveryWholeExampleBuilds) {
  const std::vector<Block> blocks = toml_blocks(guide_text());
  int whole = 0, dynamic = 0;
  for (std::size_t k = 0; k < blocks.size(); ++k) {
    if (!blocks[k].whole_scene) continue;
    ++whole, dynamic += blocks[k].dynamic_part;
    const std::string path = write_scene("whole_" + std::to_string(k), blocks[k].text);
    try {
      const ff::scene::LoadedScene s = ff::scene::load_scene(path);
      EXPECT_TRUE(s.simulation != nullptr) << "block at offset " << blocks[k].offset;
    } catch (const ff::scene::SceneError& e) {
      ADD_FAILURE() << "the guide's scene at offset " << blocks[k].offset << " does not build: " << e.what();
    }
  }
  // the static first scene, the swinging plate and the step-loaded strip at least
  EXPECT_GE(whole, 3);
  EXPECT_GE(dynamic, 2);
  EXPECT_GE(whole - dynamic, 1);
}

TEST(SceneGuide, EveryFragmentIsValidInItsAnalysis) {
  const std::vector<Block> blocks = toml_blocks(guide_text());
  const Block *static_host = nullptr, *dynamic_host = nullptr;
  for (const Block& b : blocks)
    if (b.whole_scene) {
      if (!b.dynamic_part && !static_host) static_host = &b;
      if (b.dynamic_part && !dynamic_host) dynamic_host = &b;
    }
  ASSERT_TRUE(static_host && dynamic_host) << "the guide needs a whole static and a whole dynamic scene";
  int fragments = 0;
  for (const Block& b : blocks) {
    if (b.whole_scene) continue;
    ++fragments;
    const Block& host = b.dynamic_part ? *dynamic_host : *static_host;
    const ff::scene::Schema& schema =
        b.dynamic_part ? ff::scene::shell_dynamic_schema() : ff::scene::shell_static_schema();
    try {
      ff::scene::validate(schema, host.text + "\n" + b.text, "guide fragment");
    } catch (const ff::scene::SceneError& e) {
      ADD_FAILURE() << "the guide's fragment at offset " << b.offset << " (" << first_line(b)
                    << ") is not valid in a " << (b.dynamic_part ? "dynamic" : "static") << " scene: " << e.what();
    }
  }
  EXPECT_GE(fragments, 5);
}

// The verification tests that run a guide example find it by its marker.
TEST(SceneGuide, NamedExamplesAreMarked) {
  const std::string guide = guide_text();
  for (const char* name : {"cantilever_linear", "swinging_plate", "cantilever_step_load"}) {
    const std::size_t m = guide.find(std::string("<!-- guide-example: ") + name + " -->");
    ASSERT_NE(m, std::string::npos) << name;
    const std::size_t b = guide.find("```toml\n", m), e = guide.find("\n```", b + 1);
    ASSERT_NE(e, std::string::npos) << name;
    const std::string block = guide.substr(b, e - b);
    EXPECT_NE(block.find(std::string("name = \"") + name + "\""), std::string::npos) << name;
  }
}

}  // namespace
