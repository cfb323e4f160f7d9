// Issue 31 moved the shell scenes to one structure vocabulary ([[part]], [[material]], selections
// by patch). A scene in the old words is refused at each old key's line with where it went,
// never with a bare "unknown key" and never silently.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>

#include "core/scene/scene.h"

namespace {

std::string refusal(const std::string& name, const std::string& text) {
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out/old_vocabulary";
  std::filesystem::create_directories(dir);
  const std::string path = dir + "/" + name + ".toml";
  std::ofstream(path) << text;
  try {
    ff::scene::load_scene(path, {});
  } catch (const ff::scene::SceneError& e) {
    return e.what();
  }
  return "";
}

TEST(OldVocabulary, StaticMeshAndMaterialTablesSayWhereTheyWent) {
  const std::string e = refusal("static", R"([scene]
name = "old_static"
model = "shell_static"
effects = ["elastic"]
[mesh]
generator = "rectangular_plate"
length = 1.0
width = 1.0
[material]
youngs_modulus = 1.0
thickness = 0.1
[[probe]]
name = "w"
direction = [0.0, 0.0, 1.0]
[solver]
)");
  EXPECT_NE(e.find("static.toml:5:"), std::string::npos) << e;
  EXPECT_NE(e.find("'mesh' was renamed to 'part'"), std::string::npos) << e;
  EXPECT_NE(e.find("expected an array of tables [[material]]"), std::string::npos) << e;
}

TEST(OldVocabulary, DynamicShellTableSplitsIntoPartAndMaterialKeyByKey) {
  const std::string e = refusal("dynamic", R"([scene]
name = "old_dynamic"
model = "shell_dynamic"
effects = ["elastic", "inertia", "joints"]
[solver]
dt = 1e-3
end = 0.01
[[shell]]
name = "plate"
generator = "rectangular_plate"
youngs_modulus = 1e9
density = 1000.0
phi_start = 0.0
[[joint]]
type = "simple_support"
body = "plate"
select = "patch_edge"
)");
  EXPECT_NE(e.find("'shell[0].name' was renamed to 'part.name'"), std::string::npos) << e;
  EXPECT_NE(e.find("'shell[0].youngs_modulus' was renamed to 'material.youngs_modulus'"), std::string::npos) << e;
  EXPECT_NE(e.find("'shell[0].density' was renamed to 'material.density'"), std::string::npos) << e;
  EXPECT_NE(e.find("'shell[0].phi_start' was renamed to 'part.start_angle'"), std::string::npos) << e;
  EXPECT_NE(e.find("'joint[0].body' was renamed to 'joint.patch'"), std::string::npos) << e;
  EXPECT_NE(e.find("dynamic.toml:16:"), std::string::npos) << e;  // the body line
}

}  // namespace
