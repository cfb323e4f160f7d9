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
model = "shell"
analysis = "static"
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
  EXPECT_NE(e.find("static.toml:6:"), std::string::npos) << e;
  EXPECT_NE(e.find("'mesh' was renamed to 'part'"), std::string::npos) << e;
  EXPECT_NE(e.find("expected an array of tables [[material]]"), std::string::npos) << e;
}

TEST(OldVocabulary, DynamicShellTableSplitsIntoPartAndMaterialKeyByKey) {
  const std::string e = refusal("dynamic", R"([scene]
name = "old_dynamic"
model = "shell"
analysis = "dynamic"
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
  EXPECT_NE(e.find("dynamic.toml:17:"), std::string::npos) << e;  // the body line
}

// The two shell models of before are one structure with two analyses now.
TEST(OldVocabulary, OldShellModelNamesSayHowTheyAreWrittenNow) {
  for (const std::string analysis : {"static", "dynamic"}) {
    const std::string e = refusal("model_" + analysis, "[scene]\nname = \"old\"\nmodel = \"shell_" + analysis +
                                                           "\"\neffects = [\"elastic\"]\n");
    EXPECT_NE(e.find("model_" + analysis + ".toml:3:"), std::string::npos) << e;
    EXPECT_NE(e.find("'shell_" + analysis + "' was renamed to model = \"shell\" with analysis = \"" + analysis + "\""),
              std::string::npos)
        << e;
  }
  // the analysis is required: no silent choice between them
  const std::string e = refusal("no_analysis", "[scene]\nname = \"x\"\nmodel = \"shell\"\neffects = [\"elastic\"]\n");
  EXPECT_NE(e.find("scene.analysis"), std::string::npos) << e;
}

}  // namespace
