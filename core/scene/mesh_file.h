#pragma once
/// \file mesh_file.h
/// How `mesh.generator = "file"` reaches a mesh reader. Core reads no mesh files (no assimp in
/// core/): the caller of load_scene passes a reader in its SceneContext (scene_context.h; the app
/// passes its assimp importer, app/io/mesh_import.h, ff::io::scene_context()); a scene that needs
/// a mesh file and got no reader is refused with a located error.

#include <functional>
#include <string>
#include <vector>

#include "core/mesh/shell_mesh.h"

namespace ff::scene {

/// What a scene asks of its mesh file (the part.* keys of generator = "file").
struct MeshFileRequest {
  std::string path;             ///< resolved against the scene file's folder
  double weld_tolerance = 0.0;  ///< part.weld_tolerance: join vertices closer than this (0: none)
  /// part.triangles: "refuse", "split" (each triangle into three quads) or "recombine" (Gmsh)
  std::string triangles = "split";
  double crease_angle_deg = 30.0;  ///< part.crease_angle: averaged directors fold across sharper edges
  std::string group;               ///< part.group: only this surface group of the file ("" = all)
  double mesh_size = 0.0;          ///< part.mesh_size: CAD and .geo files, the largest element (0 = the file's)
  std::vector<std::string> local_size_groups;  ///< part.local_size_groups
  std::vector<double> local_sizes;             ///< part.local_sizes, one per group above
  double time_limit_seconds = 300.0;           ///< part.mesh_time_limit: Gmsh is stopped after this
  /// The most nodes a run of this scene can hold within the memory limit (the scene's memory
  /// estimate; 0: no bound). A CAD or .geo part whose estimated mesh has more is refused before
  /// Gmsh meshes it.
  double most_nodes = 0.0;
  /// part.keep_faces_apart: faces that touch stay apart (CAD faces are not joined, and a surface
  /// touching itself without being joined is accepted instead of refused)
  bool keep_faces_apart = false;
  /// part.mesh_pattern: "mapped" (four-sided CAD faces as structured grids, the others free) or
  /// "free" (every face Frontal-Delaunay with Blossom recombination)
  std::string mesh_pattern = "mapped";
  bool operator==(const MeshFileRequest&) const = default;
};

/// Why a mesh file was not read: a complete sentence naming the file, and the scene key at fault
/// ("" = part.file itself; e.g. "part.weld_tolerance", "part.group" when that request could not
/// be met).
struct MeshFileError {
  std::string message;
  std::string key;
};

/// Reads the mesh of `request` into `out` (quads, named groups in out.groups, what was done in
/// the patch description); on failure returns false and fills *error. What the user must hear of
/// a mesh that was read (most of a piece turned, a local size not reached) goes into *warnings,
/// one sentence each naming the file (when warnings is not null).
using MeshFileReader = std::function<bool(const MeshFileRequest& request, mesh::ShellMesh& out, MeshFileError* error,
                                          std::vector<std::string>* warnings)>;

}  // namespace ff::scene
