#pragma once
/// \file shell_boundary.h
/// Supports ([[bc]]), loads ([[load]]) and probes ([[probe]]) of a shell scene (both analyses): their
/// schema keys and their translation into the model's spec (restraints in global, cylindrical or
/// nodal axes, symmetry planes of any normal, prescribed displacements, point and line loads,
/// pressures), with errors located at the scene entry that caused them.
#include <string>
#include <vector>

#include "core/scene/schema.h"
#include "core/scene/structure_parts.h"
#include "core/shell/shell_model.h"
#include "core/shell/shell_static_simulation.h"
#include "core/shell/shell_stress.h"

namespace ff::scene {

/// Declares [[bc]] (type, fix, frame, axis, axis_point, displacement and the selector keys).
void declare_bc_keys(Schema& s);
/// Declares [[load]] (type, total, per_length, pressure, follower and the selector keys).
void declare_load_keys(Schema& s);
/// Declares [[probe]] (name, label, quantity, direction, field and the selector keys).
void declare_probe_keys(Schema& s);
/// The stress fields every shell structure has (an isotropic one's: no ply fields), for the key
/// reference of output.color_field.
std::vector<std::string> stress_field_names();
/// Declares probe.field, the stress field a probe of quantity "stress" reads (both analyses).
void declare_probe_field_key(Schema& s);
/// Whether [[probe]] entry i reads a stress (probe.quantity = "stress"); refuses probe.field
/// without that quantity, and the quantity without probe.field or with probe.direction, and a
/// displacement or reaction probe without probe.direction or with a zero one.
bool probe_reads_stress(const Document& d, std::size_t i);
/// Whether a shell run records its stress fields: output.stresses, or a colour field other than
/// `fixed_fields` and "none", or a stress probe.
bool stresses_wanted(const Document& d, const std::vector<std::string>& fixed_fields);
/// Refuses, at probe.field, a stress probe whose field is not one of `fields` (the built
/// structure's; the ply fields depend on its layup), naming those it has.
void refuse_unknown_probe_fields(const Document& d, const std::vector<shell::StressField>& fields);

/// Restraints, symmetry planes and prescribed displacements of every [[bc]] into `spec`
/// (each tagged with its entry index as `source`). Needs spec.mesh. Throws SceneError.
void read_bcs(const Document& d, shell::ShellModelSpec& spec);
/// Entry i of [[load]] (point forces and moments, line, surface and pressure loads), added to
/// spec.loads / spec.pressures; each entry apart, so that a caller knows what each one applies
/// (the dynamic model gives each its own time history).
void read_load(const Document& d, std::size_t i, shell::ShellModelSpec& spec);
/// Probes of every [[probe]].
std::vector<shell::ShellProbe> read_probes(const Document& d, const mesh::ShellMesh& m);

/// One direction a support holds at a node (world components): its translation, or with
/// `rotation` its rotation, along `direction` is held at zero, or moved by a prescribed
/// displacement (`prescribed`); `entry` names the scene entry that holds it ("bc[2]", "joint[0]").
struct HeldDirection {
  int node = -1;
  Eigen::Vector3d direction = Eigen::Vector3d::UnitZ();
  bool rotation = false;
  bool prescribed = false;
  std::string entry;
};
/// The directions the [[bc]] entries read into `spec` (read_bcs) hold: restraints, prescribed
/// displacements, and a symmetry plane's normal translation and in-plane rotations.
std::vector<HeldDirection> held_directions(const shell::ShellModelSpec& spec);

/// The loads one [[load]] entry put on the structure, as read_load read them.
struct EntryLoads {
  std::size_t entry = 0;
  std::vector<shell::NodalLoad> nodal;
  std::vector<shell::PressureLoad> pressures;  ///< quads of the mesh given to refuse_loads_on_held_dofs
};
/// Refuses, at its amount key (load.total, load.per_length, load.pressure, load.per_area), a
/// non-zero [[load]] entry that does no work: at every node it loads, its force lies in the
/// translations the supports hold or prescribe there and its moment in the rotations they hold,
/// so that the supports take all of it and the structure never feels it (a run would report its
/// undisturbed state as completed). The message names the supports. A load the supports hold only
/// in part is accepted without a word: the share at held nodes goes into the reactions. A
/// follower load counts as held only where the node's whole translation (rotation) is held, since
/// it turns with the node. Pressures are taken as their reference nodal forces on `m`.
void refuse_loads_on_held_dofs(const Document& d, const mesh::ShellMesh& m, const std::vector<HeldDirection>& held,
                               const std::vector<EntryLoads>& loads);
/// Warnings (ctx.warnings, at probe.direction) for a displacement probe whose direction the
/// supports hold at its node (it records 0 throughout; a prescribed direction is not warned
/// about: it records the prescribed motion), and a reaction probe whose direction no support holds
/// at any of its nodes (it records only the residual, about 0). A reaction probe on a support, and
/// a displacement probe on a partly held node along a free direction, are what they should be.
/// `reaction_probes`: the analysis has them (the warning then points to one).
void warn_probes_on_held_dofs(const Document& d, const mesh::ShellMesh& m, const std::vector<HeldDirection>& held,
                              bool reaction_probes, std::vector<std::string>* warnings);

/// The scene issue for an error the model constructor raised about the spec read from `d`
/// (an element's fault at its part's material or generator).
Issue located(const Document& d, const shell::ShellSpecError& e, const Structure& structure);

/// Nodal forces equivalent to a uniform force per unit length q along the mesh edges joining the
/// nodes `ids` (consistent lumping: q L / 2 to each end of an edge of length L). Empty `why`
/// on success; otherwise why the nodes do not form a line (no edge between them, or a whole quad
/// selected).
std::vector<std::pair<int, Eigen::Vector3d>> line_load_forces(const mesh::ShellMesh& m, const std::vector<int>& ids,
                                                              const Eigen::Vector3d& q, std::string& why);

/// Consistent nodal forces of a force per unit reference area t (global components) on the quads
/// `quads` (core/shell/shell_model.md P5), summed per node.
std::vector<std::pair<int, Eigen::Vector3d>> surface_load_forces(const mesh::ShellMesh& m, const std::vector<int>& quads,
                                                                 const Eigen::Vector3d& t);

}  // namespace ff::scene
