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

namespace ff::scene {

/// Declares [[bc]] (type, fix, frame, axis, axis_point, displacement and the selector keys).
void declare_bc_keys(Schema& s);
/// Declares [[load]] (type, total, per_length, pressure, follower and the selector keys).
void declare_load_keys(Schema& s);
/// Declares [[probe]] (name, label, quantity, direction and the selector keys).
void declare_probe_keys(Schema& s);

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
