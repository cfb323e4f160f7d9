#include "core/scene/scene_selections.h"

#include <algorithm>

#include "core/scene/node_selection.h"
#include "core/scene/scene.h"
#include "core/scene/shell_dynamic_scene.h"
#include "core/scene/shell_scene.h"
#include "core/scene/structure_parts.h"

namespace ff::scene {

namespace {

std::string count_of(std::size_t n, const char* one, const char* many) {
  return std::to_string(n) + " " + (n == 1 ? one : many);
}

// entries of `table`; 0 where the analysis has no such table (joints and arcs: dynamics only)
std::size_t entries(const Document& d, const std::string& table) { return d.declares_array(table) ? d.count(table) : 0; }

bool declares_key(const Document& d, const std::string& array, const std::string& key) {
  const std::vector<std::string> keys = d.element_key_paths(array);
  return std::find(keys.begin(), keys.end(), key) != keys.end();
}

// "bc[0] clamped", "bc[2] fix ux, uz (global)"
std::string bc_label(const Document& d, std::size_t i) {
  const std::string type = d.string("bc.type", i);
  std::string label = "bc[" + std::to_string(i) + "] " + type;
  if (type == "fix" || type == "displacement") {
    const std::vector<std::string> dofs = d.strings("bc.fix", i);
    for (std::size_t k = 0; k < dofs.size(); ++k) label += (k == 0 ? " " : ", ") + dofs[k];
    if (declares_key(d, "bc", "bc.frame") && d.string("bc.frame", i) != "global")
      label += " (" + d.string("bc.frame", i) + ")";
  }
  return label;
}

}  // namespace

std::optional<SceneSelections> scene_selections(const std::string& path, const std::vector<std::string>& overrides,
                                                const SceneContext& ctx) {
  return scene_selections_of_text(read_scene_text(path), path, overrides, ctx);
}

std::optional<SceneSelections> scene_selections_of_text(const std::string& text, const std::string& path,
                                                        const std::vector<std::string>& overrides, const SceneContext& ctx) {
  const Schema& schema = schema_for_text(text);
  if (&schema != &shell_static_schema() && &schema != &shell_dynamic_schema()) return std::nullopt;
  const Document d = validate(schema, text, path, overrides);
  Structure structure = read_structure(d, path, ctx);

  SceneSelections out;
  out.scene_name = d.string("scene.name");
  for (const StructurePart& part : structure.parts) out.part_names.push_back(part.name);
  out.quad_part = structure.quad_part;
  out.mesh = std::move(structure.joined);
  const mesh::ShellMesh& m = out.mesh;

  auto add = [&](const std::string& table, std::size_t i, std::string label, std::vector<int> nodes) {
    EntrySelection e;
    e.table = table;
    e.index = i;
    e.label = std::move(label);
    std::sort(nodes.begin(), nodes.end());
    e.extent = count_of(nodes.size(), "node", "nodes");
    e.nodes = std::move(nodes);
    out.entries.push_back(std::move(e));
    return &out.entries.back();
  };
  for (std::size_t i = 0; i < entries(d, "bc"); ++i) add("bc", i, bc_label(d, i), select_nodes(d, m, "bc", i));
  for (std::size_t i = 0; i < entries(d, "load"); ++i) {
    const std::string type = d.string("load.type", i);
    std::vector<int> ids = select_nodes(d, m, "load", i);
    EntrySelection* e = add("load", i, "load[" + std::to_string(i) + "] " + type, ids);
    if (type == "pressure" || type == "surface") {  // the quads the model loads (a surface group's own)
      e->quads = selected_quads(d, m, "load", i, ids);
      std::vector<int> corners;
      for (int q : e->quads) corners.insert(corners.end(), m.quads[q].begin(), m.quads[q].end());
      std::sort(corners.begin(), corners.end());
      corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
      e->extent = count_of(e->quads.size(), "quad", "quads") + " of " + count_of(corners.size(), "node", "nodes");
      e->nodes = std::move(corners);
    }
  }
  const bool reaction_probes = declares_key(d, "probe", "probe.quantity");
  for (std::size_t i = 0; i < entries(d, "probe"); ++i) {
    const std::vector<int> ids = select_nodes(d, m, "probe", i);
    const std::string label = "probe[" + std::to_string(i) + "] " + d.string("probe.name", i);
    if (reaction_probes && d.string("probe.quantity", i) == "reaction") {
      EntrySelection* e = add("probe", i, label + " (reaction)", ids);
      e->extent = "summed over " + e->extent;
      continue;
    }
    // a displacement or stress probe reads the first node the selector returns (shell_boundary.cpp,
    // read_probes); a stress probe's label names its field
    const bool stress = reaction_probes && d.string("probe.quantity", i) == "stress";
    EntrySelection* e = add("probe", i, stress ? label + " (" + d.string("probe.field", i) + ")" : label, {ids.front()});
    e->extent = "node " + std::to_string(ids.front());
    if (ids.size() > 1) e->extent += " (the first of " + std::to_string(ids.size()) + " selected)";
  }
  for (std::size_t i = 0; i < entries(d, "joint"); ++i) {
    const std::string other = d.string("joint.other", i);
    add("joint", i,
        "joint[" + std::to_string(i) + "] " + d.string("joint.type", i) + " to " +
            (other.empty() ? std::string("ground") : "'" + other + "'"),
        select_nodes(d, m, "joint", i));
  }
  for (std::size_t i = 0; i < entries(d, "arc"); ++i)
    add("arc", i, "arc[" + std::to_string(i) + "] " + d.string("arc.name", i), select_nodes(d, m, "arc", i));
  return out;
}

}  // namespace ff::scene
