#pragma once
/// Scene keys and model building for model = "shell", analysis = "dynamic" (CB shells, rigid bodies and joints
/// in motion with the Lie-group generalized-alpha).
#include <memory>
#include <string>
#include <vector>

#include "core/model/simulation.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"
#include "core/scene/structure_parts.h"
#include "core/shell/multibody_model.h"

namespace ff::scene {

const Schema& shell_dynamic_schema();
/// Builds the simulation; throws SceneError located at the offending key.
/// Declares [[rigid]] and [[joint]] (the dynamic analysis's, and a modal analysis's of a jointed structure).
void declare_multibody_keys(Schema& s);
/// The multibody structure of a document: shell bodies from the parts, rigid bodies, joints,
/// supports, gravity and (with `with_loads`) the loads on their time histories; `load_entry`,
/// `pressure_entry` give each spec load's [[load]] entry. `joints_need_effect`: refuse [[joint]]
/// entries without the effect 'joints' (dynamics; a modal analysis honours them always).
struct MultibodyInput {
  shell::MultibodySpec spec;
  Structure structure;
  std::vector<std::size_t> load_entry, pressure_entry;
};
MultibodyInput read_multibody_input(const Document& d, const std::string& path, const SceneContext& ctx, bool with_loads,
                                    bool joints_need_effect);
std::unique_ptr<Simulation> build_shell_dynamic(const Document& d, const std::string& path, const SceneContext& ctx);

}  // namespace ff::scene
