#include "core/scene/shell_structure_scene.h"

#include <algorithm>
#include <limits>

#include "core/scene/mesh_quality_report.h"
#include "core/scene/scene_common.h"
#include "core/scene/shell_boundary.h"

namespace ff::scene {

const std::vector<std::string>& shell_analyses() {
  static const std::vector<std::string> a = {"static", "dynamic", "modal", "buckling"};
  return a;
}
const char* const kShellAnalysisDoc =
    "what is computed over the structure: static (equilibrium: linear, load control or arc length), dynamic "
    "(motion in time), modal (natural frequencies and mode shapes) or buckling (linear buckling loads and modes); "
    "the scene's other keys are that analysis's";

void declare_shell_structure_scene_keys(Schema& s) {
    declare_scene_table(s,
                        "effects to simulate: elastic (required), hr (assumed membrane stress), ans (assumed "
                        "transverse shear), drilling (6 DoF per node, Fox-Simo penalty), gravity (the self-weight "
                        "of every part, density x thickness x g per unit area, times the load factor)",
                        {"elastic", "hr", "ans", "drilling", "gravity"});
    s.choice("scene.analysis", kShellAnalysisDoc, shell_analyses(), std::nullopt);
    declare_structure_keys(s);
    declare_mesh_quality_keys(s);
    s.table("gravity", "uniform gravity (effect gravity): in a static analysis the parts' self-weight, a dead load "
                       "times the load factor")
        .number_list("gravity.g", "acceleration of gravity [m/s^2]; each component within [-1e100, 1e100]",
                     std::vector<double>{0, 0, -9.81}, Range::closed(-1e100, 1e100), 3, 3);
    declare_bc_keys(s);
    declare_load_keys(s);
    declare_probe_keys(s);
}

ShellStructureInput read_shell_structure_input(const Document& d, const std::string& path, const SceneContext& ctx,
                                               const std::string& loads_needed_by) {
  const bool require_loads = !loads_needed_by.empty();
  using namespace ff::shell;
  const std::vector<std::string> fx = d.strings("scene.effects");
  auto has = [&](const char* e) { return std::find(fx.begin(), fx.end(), e) != fx.end(); };
  ShellStructureInput in;
  ShellModelSpec& spec = in.spec;
  // the parts' node counts from their keys (exact, nothing built): a structure that cannot fit is
  // refused at the count key that makes it large before seconds go into generating it
  const StructureSize size = structure_size(d, path, ctx);
  refuse_oversized(d, ctx, static_cast<int>(std::min<long long>(size.nodes, std::numeric_limits<int>::max())),
                   has("drilling") ? 1.0 : 0.0, size.key, size.part);
  ctx.setup.poll("generating the mesh", 0.0);
  in.structure = read_structure(d, path, ctx);
  Structure& structure = in.structure;
  report_mesh_quality(d, structure, ctx);  // refuses inverted or degenerate quads; warnings for poor ones
  spec.mesh = std::move(structure.joined);
  {
    int six = 0;
    for (std::uint8_t f : spec.mesh.fold) six += f != 0;
    const double six_fraction = has("drilling") ? 1.0 : spec.mesh.node_count() > 0 ? double(six) / spec.mesh.node_count() : 0.0;
    refuse_oversized(d, ctx, spec.mesh.node_count(), six_fraction, size.key, size.part);
  }
  // the first part's section (the first [[material]] may be only a ply of a layup)
  const StructureMaterial& first = structure.materials[structure.parts.front().material];
  spec.section = first.section;
  structure_sections(structure, spec.sections, spec.drilling_factors, spec.quad_section);
  spec.quad_reference_direction = structure.quad_reference_direction;
  spec.options.hr = has("hr");
  spec.options.ans = has("ans");
  spec.options.drilling = has("drilling");
  spec.options.drilling_factor = first.drilling_factor;
  const mesh::ShellMesh& m = spec.mesh;

  read_bcs(d, spec);
  const std::vector<HeldDirection> held = held_directions(spec);
  std::vector<EntryLoads> entry_loads;
  for (std::size_t i = 0; i < d.count("load"); ++i) {
    const std::size_t loads_before = spec.loads.size(), pressures_before = spec.pressures.size();
    read_load(d, i, spec);
    entry_loads.push_back({i, {spec.loads.begin() + static_cast<std::ptrdiff_t>(loads_before), spec.loads.end()},
                           {spec.pressures.begin() + static_cast<std::ptrdiff_t>(pressures_before), spec.pressures.end()}});
  }
  // loads the supports take whole do nothing where they are applied (modal about the reference
  // state applies none: its [[load]] entries are warned about as a whole)
  if (require_loads) refuse_loads_on_held_dofs(d, spec.mesh, held, entry_loads);
  warn_probes_on_held_dofs(d, spec.mesh, held, true, ctx.warnings);
  // gravity: each part's self-weight rho h g per unit area of its reference mid-surface, as
  // consistent nodal forces of a dead surface load (shell_model.md (P5)), times the load factor
  if (d.table_present("gravity") && !has("gravity"))
    throw SceneError({d.issue("gravity.g", "the scene gives [gravity] but scene.effects lacks gravity")});
  if (has("gravity")) {
    const Eigen::Vector3d g(d.numbers("gravity.g")[0], d.numbers("gravity.g")[1], d.numbers("gravity.g")[2]);
    for (std::size_t p = 0; p < structure.parts.size(); ++p) {
      const StructureMaterial& material = structure.materials[structure.parts[p].material];
      require_density(d, structure, p,
                      "the effect gravity weighs every part: give material.density for part '" + structure.parts[p].name + "'");
      std::vector<int> quads;
      for (int q = 0; q < static_cast<int>(structure.quad_part.size()); ++q)
        if (structure.quad_part[q] == static_cast<int>(p)) quads.push_back(q);
      for (const auto& [node, f] : surface_load_forces(spec.mesh, quads, material.density * material.section.thickness * g))
        spec.loads.push_back({node, f, Vec3::Zero(), false});
    }
  }
  // A zero [[load]] or a zero prescribed displacement is accepted (a load switched off with
  // --set, a displacement that holds its DoFs), alike; but a path needs something non-zero to follow.
  const bool loaded =
      std::any_of(spec.loads.begin(), spec.loads.end(),
                  [](const NodalLoad& l) { return !l.force.isZero(0.0) || !l.moment.isZero(0.0); }) ||
      std::any_of(spec.pressures.begin(), spec.pressures.end(), [](const PressureLoad& p) { return p.pressure != 0.0; }) ||
      std::any_of(spec.directions.begin(), spec.directions.end(), [](const DirectionRestraint& r) { return r.value != 0.0; });
  if (!loaded && require_loads) {
    if (d.count("load") == 0)
      throw SceneError({d.issue(loads_needed_by, loads_needed_by + " = \"" + d.string(loads_needed_by) +
                                                     "\" follows the scene's loads, but nothing loads the shell: give "
                                                     "a [[load]] or a [[bc]] of type = \"displacement\"")});
    const std::string type = d.string("load.type", 0);
    const std::string amount = type == "force" || type == "moment" ? "load.total"
                               : type == "line"                    ? "load.per_length"
                               : type == "pressure"                ? "load.pressure"
                                                                   : "load.per_area";
    throw SceneError({d.issue(amount, 0, "every [[load]] is zero and no [[bc]] prescribes a non-zero displacement, so "
                                         "nothing loads the shell and the path has nothing to follow")});
  }
  in.probes = read_probes(d, m);
  describe_run(d, path, in.info);
  // how an imported mesh was read (vertices welded or not, where the directors came from)
  for (auto& setting : mesh_import_settings(structure)) in.info.settings.push_back(std::move(setting));
  in.info.effects = fx;
  return in;
}

}  // namespace ff::scene
