#pragma once
/// \file mesh_generator_keys.h
/// The [[part]] tables of shell scenes: which generator builds each part's mid-surface, its
/// dimensions as scene keys, and the mesh they give (core/mesh/generators.h). Every function
/// takes the part's index i in the [[part]] array. The key docs are
/// the scene-key reference (docs/reference/scene-keys.md), so they state where each generator places its surface,
/// its patches and the names of their edges (for select = "patch_edge").
///
/// Bad input is a located SceneError at the exact key: a dimension the generator needs and the
/// scene does not give, a key that does not belong to the chosen generator, inconsistent ranges.

#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"
#include "core/scene/schema.h"

namespace ff::scene {

/// Declares the [[part]] array and its keys (name, material, generator, element counts,
/// dimensions, file).
void declare_part_keys(Schema& s);

/// The dimensions generator `generator` cannot do without (part.radius for a cylinder, ...), as
/// key names inside [[part]]; empty for "file" (it needs part.file) and unknown names.
std::vector<std::string> generator_required_keys(const std::string& generator);

/// The element-count keys generator `generator` reads (of n1, n2, n3), as key names inside [[part]];
/// empty for "file" and unknown names.
std::vector<std::string> generator_count_keys(const std::string& generator);

/// True when part.generator = "file" (the caller reads part.file); checks first that no
/// generator dimension is given with it.
bool mesh_from_file(const Document& d, std::size_t i);

/// Refuses a cylinder, cut cylinder or spherical cap at least as thick (`thickness`, set by the key
/// `thickness_key`, entry `thickness_index` of its array: a material's thickness or a layup's ply
/// thicknesses) as its part.radius, naming both keys; other generators have no radius to compare with.
void check_thickness_against_radius(const Document& d, std::size_t i, double thickness, const std::string& thickness_key,
                                    std::size_t thickness_index);

/// What a generator's u and v grid directions are on its surface, in words ("u around the arc,
/// from edge start_angle to end_angle; v along the axis, from bottom to top" for a cylinder), for
/// messages that ask the scene to choose one (part.fibre_reference); "" for "file" and unknown
/// names.
std::string generator_grid_directions(const std::string& generator);

/// The mesh of a parametric generator (part.generator != "file"), built from part i's keys.
mesh::ShellMesh generate_mesh(const Document& d, std::size_t i);

/// The size of the mesh generate_mesh(d) would build, counted from the keys without building it.
struct GeneratedMeshSize {
  long long nodes = 0;  ///< exactly generate_mesh(d).node_count() (for keys the generator accepts)
  /// the count key that makes the mesh large: of part.n1, n2, n3 (those the generator reads and the
  /// scene gives), the one whose reduction to 1 would shrink it most; "part.generator" when none is given
  std::string key;
};
GeneratedMeshSize generated_mesh_size(const Document& d, std::size_t i);

}  // namespace ff::scene
