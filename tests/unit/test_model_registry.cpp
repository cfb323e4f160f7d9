// The model registry (core/scene/scene.h, model_kinds()): one entry per model picks its schema,
// builder and end key; a model name that is none is refused at scene.model with the models there
// are, instead of being validated against another model's schema.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "core/scene/scene.h"

using namespace ff::scene;

TEST(ModelRegistry, EveryModelHasItsSchemaAndBundledScenesLoad) {
  ASSERT_GE(model_kinds().size(), 3u);
  for (const ModelKind& k : model_kinds()) {
    EXPECT_EQ(find_model(k.name, k.analysis), &k);
    EXPECT_NE(k.schema().markdown_reference().find(k.end_key), std::string::npos) << k.name;
    // a model of several analyses declares scene.analysis, and only such a model does
    EXPECT_EQ(k.schema().find_key("scene.analysis") != nullptr, !k.analysis.empty()) << k.name;
  }
  // one shell structure, two analyses over it (issue 31)
  ASSERT_NE(find_model("shell", "static"), nullptr);
  ASSERT_NE(find_model("shell", "dynamic"), nullptr);
  EXPECT_EQ(find_model("shell"), nullptr);
  EXPECT_EQ(find_model("shell_statik"), nullptr);
}

// The schemas are declared below the registry (core/scene/scene_common.cpp, model_names()); every
// model's scene.model must still offer exactly the registry's models, in its order.
TEST(ModelRegistry, EverySchemaOffersTheRegistrysModels) {
  std::vector<std::string> names;  // each model once, however many analyses it has
  for (const ModelKind& k : model_kinds())
    if (names.empty() || names.back() != k.name) names.push_back(k.name);
  for (const ModelKind& k : model_kinds()) {
    const Schema::KeySpec* model = k.schema().find_key("scene.model");
    ASSERT_NE(model, nullptr) << k.name;
    EXPECT_EQ(model->choices, names) << k.name;
  }
}

TEST(ModelRegistry, AnUnknownModelIsRefusedAtItsLine) {
  const std::string path = std::string(FF_BINARY_DIR) + "/test_out/unknown_model.toml";
  std::filesystem::create_directories(std::string(FF_BINARY_DIR) + "/test_out");
  std::ofstream(path) << "[scene]\nname = \"x\"\nmodel = \"shell_statik\"\neffects = [\"elastic\"]\n";
  try {
    load_scene(path);
    ADD_FAILURE() << "an unknown model was accepted";
  } catch (const SceneError& e) {
    ASSERT_EQ(e.issues.size(), 1u) << e.what();  // one clear issue, not another model's missing tables
    EXPECT_EQ(e.issues[0].key, "scene.model");
    EXPECT_EQ(e.issues[0].line, 3);
    for (const ModelKind& k : model_kinds()) { EXPECT_NE(e.issues[0].message.find(k.name), std::string::npos); }
  }
}
