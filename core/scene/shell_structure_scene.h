#pragma once
/// What every analysis of a shell structure at rest reads the same way (static, modal, buckling):
/// the structure, its supports and loads, its probes; and the analyses scene.analysis names.
#include <string>
#include <vector>

#include "core/model/simulation.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"
#include "core/scene/structure_parts.h"
#include "core/shell/shell_model.h"
#include "core/shell/shell_static_simulation.h"

namespace ff::scene {

/// The analyses of model = "shell" (scene.analysis), in every one of its schemas, and what it says.
const std::vector<std::string>& shell_analyses();
extern const char* const kShellAnalysisDoc;

/// The keys every analysis of a shell structure at rest shares (static, modal, buckling): the
/// scene table, the structure, mesh quality, gravity, [[bc]], [[load]], [[probe]].
void declare_shell_structure_scene_keys(Schema& s);
/// What those keys build: the model's spec (mesh, sections, restraints, loads, gravity), the
/// structure it came from (materials, densities), the probes and the run's description.
struct ShellStructureInput {
  shell::ShellModelSpec spec;
  Structure structure;
  std::vector<shell::ShellProbe> probes;
  RunInfo info;
};
/// Reads them (SceneError at the offending key). `loads_needed_by`: the key whose value makes the
/// analysis apply the loads ("scene.analysis", "modal.about"), at which a scene with no [[load]]
/// is refused, and a scene whose loads and prescribed displacements are all zero, or whose loads
/// the supports take whole (refuse_loads_on_held_dofs), is refused at the load; "" when the
/// analysis applies no loads.
ShellStructureInput read_shell_structure_input(const Document& d, const std::string& path, const SceneContext& ctx,
                                               const std::string& loads_needed_by);

}  // namespace ff::scene
