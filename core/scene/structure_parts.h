#pragma once
/// \file structure_parts.h
/// The structure of a shell scene, whatever the analysis: its [[material]] tables (one form for
/// every part: elastic constants, isotropic or orthotropic, thickness, shear factor, drilling
/// factor, density), its [[layup]] tables (laminated sections: plies of materials, each with its
/// thickness and angle, core/shell/laminate.md), its [[part]] tables (each a generator's or a
/// file's mesh, mesh_generator_keys.h, made of a material or a layup, with the direction its ply
/// angles are measured from) and the [[junction]] tables that make parts share the nodes where
/// their edges coincide. A single part without junctions is its own mesh unchanged, so a one-part
/// scene gives exactly the mesh it always did.

#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"
#include "core/scene/scene_context.h"
#include "core/scene/schema.h"
#include "core/shell/cb_shell.h"

namespace ff::scene {

/// Declares [[material]], [[layup]], [[part]] (mesh_generator_keys.h) and [[junction]].
void declare_structure_keys(Schema& s);

/// A section a part can be made of: a [[material]] with its thickness (isotropic: plies null;
/// orthotropic, or with strengths: one ply at angle 0), or a [[layup]] (its plies).
struct StructureMaterial {
  std::string name;
  shell::ShellSection section;
  double drilling_factor = 1e-3;
  double density = 0.0;  ///< 0 when the scene gives none (a static analysis needs none)
  /// the [[layup]] entry it comes from; -1: the [[material]] entry of the same index
  int layup = -1;
  /// a layup: the first [[material]] among its plies without a density (-1: every ply has one);
  /// its density is then not the section's, and an analysis that needs one refuses it there
  int ply_without_density = -1;
};

struct StructurePart {
  std::string name;
  mesh::ShellMesh mesh;  ///< the part alone, its own node numbers
  int material = 0;      ///< index into Structure::materials
  bool from_file = false;
  int first_node = 0;    ///< where its nodes went in Structure::joined (-1 for a node shared earlier: node_map)
  std::vector<int> node_map;  ///< its node i is joined node node_map[i]
  /// per quad of `mesh`: the world direction its ply angles are measured from (part.fibre_reference)
  std::vector<Eigen::Vector3d> reference_direction;
};

struct Structure {
  /// the [[material]] entries (index k = entry k), then the [[layup]] entries (index
  /// materials_in_file + l = layup entry l); a material only used as a ply is here unused
  std::vector<StructureMaterial> materials;
  std::size_t materials_in_file = 0;
  std::vector<StructurePart> parts;
  /// every part in one mesh, the nodes of each junction shared (fold nodes where the joined
  /// parts' directors differ); patches named as the parts' own
  mesh::ShellMesh joined;
  std::vector<int> quad_part;  ///< per quad of `joined`
  /// per quad of `joined`: its part's reference_direction; empty when no part is laminated and
  /// none gives part.fibre_reference or part.fibre_vector (each element then measures from its own
  /// xi direction, exactly as before layups existed)
  std::vector<Eigen::Vector3d> quad_reference_direction;
  bool has_junctions = false;
  /// index of the part called `name`, or -1
  int find(const std::string& name) const;
  /// the first quad of part p in `joined` (parts' quads are consecutive, in part order)
  int first_quad(int p) const;
};

/// Estimated nodes of the structure before any mesh is built (generator counts; a file part is
/// read through the context's reader when one is given, else counts 0), the count key that makes
/// it large and the part it belongs to. For the memory check of `check` and `run`.
struct StructureSize {
  long long nodes = 0;
  std::string key = "part.generator";
  int part = 0;
};
StructureSize structure_size(const Document& d, const std::string& scene_path, const SceneContext& ctx);
/// Peak memory [bytes] of a run on the structure (shell::estimated_peak_bytes at structure_size's
/// nodes, every node with 6 DoFs under the drilling effect); 0 when nothing can be counted.
double estimated_structure_bytes(const Document& d, const std::string& scene_path, const SceneContext& ctx);

/// Builds every material, layup and part and joins the parts; located SceneErrors for a material
/// or layup no part names, a part naming no material, two parts of one name, a junction whose
/// parts share no node or whose directors face opposite sides, and the material and layup checks
/// of docs/reference (an unstable orthotropic material, a ply of zero thickness, a fibre
/// reference parallel to an element's normal ...). A cylinder or cap thicker than its radius is
/// refused at the material's thickness (a layup's ply_thicknesses). Ply angles that look like
/// radians are accepted with a warning left in ctx.warnings.
Structure read_structure(const Document& d, const std::string& scene_path, const SceneContext& ctx);

/// An issue at the key that sets section `section`'s thickness (an index into
/// Structure::materials): material.thickness of a [[material]], layup.ply_thicknesses of a layup.
Issue thickness_issue(const Document& d, const Structure& s, int section, const std::string& message);
/// Refuses part p when its section has no density: `message` at its material's density (the
/// line of its table when it has none); for a layup, at the first ply material without a density
/// (a layup whose plies have densities only in part has no section density either).
void require_density(const Document& d, const Structure& s, std::size_t p, const std::string& message);
/// An issue at the density key of section `section` (its material's, or a layup's first ply
/// material's; the line of the table when not given).
Issue density_issue(const Document& d, const Structure& s, int section, const std::string& message);

/// How each file part was read (format, what became of triangles, directors, named groups), as
/// run settings: ("mesh_import", text) for a one-part structure, ("mesh_import_<part>", text)
/// per file part otherwise. `check` prints them and results.h5 keeps them.
std::vector<std::pair<std::string, std::string>> mesh_import_settings(const Structure& s);

/// The sections of a joined structure for the static model (ShellModelSpec::sections,
/// drilling_factors, quad_section); empty quad_section when one material covers every part (the
/// scene's only section). Layups are sections too.
void structure_sections(const Structure& s, std::vector<shell::ShellSection>& sections,
                        std::vector<double>& drilling_factors, std::vector<int>& quad_section);

}  // namespace ff::scene
