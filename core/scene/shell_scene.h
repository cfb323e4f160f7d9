#pragma once
/// Scene keys and model building for model = "shell", analysis = "static" (CB shell statics).
#include <memory>
#include <string>
#include <vector>

#include "core/model/simulation.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"
#include "core/scene/shell_structure_scene.h"

namespace ff::scene {

const Schema& shell_static_schema();
/// Builds the simulation; throws SceneError located at the offending key (empty node sets,
/// impossible restraints, bad reference columns ...).
std::unique_ptr<Simulation> build_shell_static(const Document& d, const std::string& path, const SceneContext& ctx);

}  // namespace ff::scene
