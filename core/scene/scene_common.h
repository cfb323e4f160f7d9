#pragma once
/// Keys and reading shared by every model's scene schema.
#include <string>
#include <vector>

#include "core/frame/frame.h"
#include "core/scene/scene.h"

namespace ff::scene {

/// [scene]: name, description, model, and the model's effects list.
void declare_scene_table(Schema& s, const std::string& effects_doc, std::vector<std::string> effects);
/// [output]: frames, cadence, size, deformation scale, colour field, plots (and camera keys if asked).
void declare_output_keys(Schema& s, std::vector<std::string> color_fields, bool camera_keys);
/// OutputSettings from a document declared with declare_output_keys.
OutputSettings read_output(const Document& d, bool camera_keys);
/// Scene name, path, text and every effective setting into a RunInfo.
void describe_run(const Document& d, const std::string& path, RunInfo& info);

}  // namespace ff::scene
