#pragma once
/// Scene keys and model building for model = "shell", analysis = "dynamic" (CB shells, rigid bodies and joints
/// in motion with the Lie-group generalized-alpha).
#include <memory>
#include <string>

#include "core/model/simulation.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"

namespace ff::scene {

const Schema& shell_dynamic_schema();
/// Builds the simulation; throws SceneError located at the offending key.
std::unique_ptr<Simulation> build_shell_dynamic(const Document& d, const std::string& path, const SceneContext& ctx);

}  // namespace ff::scene
