#pragma once
/// Scene keys and model building for model = "shell", analysis = "modal" (natural frequencies and
/// modes) and analysis = "buckling" (linear buckling loads and modes) of a CB shell structure
/// (core/shell/shell_eigen.md).
#include <memory>
#include <string>

#include "core/model/simulation.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"

namespace ff::scene {

const Schema& shell_modal_schema();
const Schema& shell_buckling_schema();
/// The estimated peak memory [bytes] of a modal or buckling run (the registry's estimate): the
/// structure's and the Lanczos iteration's (ff::lanczos_peak_bytes) on every node's DoFs; 0 when
/// the structure cannot be counted.
double estimated_eigen_bytes(const Document& d, const std::string& path, const SceneContext& ctx);
/// Build the simulations; throw SceneError located at the offending key.
std::unique_ptr<Simulation> build_shell_modal(const Document& d, const std::string& path, const SceneContext& ctx);
std::unique_ptr<Simulation> build_shell_buckling(const Document& d, const std::string& path, const SceneContext& ctx);

}  // namespace ff::scene
