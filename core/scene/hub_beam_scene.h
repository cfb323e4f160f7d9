#pragma once
/// Scene keys and model building for model = "hub_beam" (a rotating hub with a flexible beam,
/// EFG or FEM, core/hubbeam/).
#include <memory>
#include <string>

#include "core/model/simulation.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"

namespace ff::scene {

const Schema& hub_beam_schema();
/// Builds the simulation (its dense matrices are built when the run starts); throws SceneError
/// located at the offending key (a missing effect, a product of inputs outside double precision,
/// an EFG support too small for its basis, unstable Newmark parameters ...).
std::unique_ptr<Simulation> build_hub_beam(const Document& d, const std::string& path, const SceneContext& ctx);
/// The estimated peak memory [bytes] of a run, from the node count and the axial effect.
double estimated_hub_beam_bytes(const Document& d, const std::string& path, const SceneContext& ctx);

}  // namespace ff::scene
