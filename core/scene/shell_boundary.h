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
/// displacement or reaction probe without probe.direction.
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
/// Point forces and moments, line, surface and pressure loads of every [[load]] into `spec`.
void read_loads(const Document& d, shell::ShellModelSpec& spec);
/// Entry i of [[load]] alone, added to spec.loads / spec.pressures (the dynamic model reads each
/// entry with its own time history).
void read_load(const Document& d, std::size_t i, shell::ShellModelSpec& spec);
/// Probes of every [[probe]].
std::vector<shell::ShellProbe> read_probes(const Document& d, const mesh::ShellMesh& m);

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
