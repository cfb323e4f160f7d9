#pragma once
/// \file mesh_file.h
/// How `mesh.generator = "file"` reaches a mesh reader. Core reads no mesh files (no assimp in
/// core/): the caller of load_scene passes a reader in its SceneContext (scene_context.h; the app
/// passes its assimp importer, app/io/mesh_import.h, ff::io::scene_context()); a scene that needs
/// a mesh file and got no reader is refused with a located error.

#include <functional>
#include <string>

#include "core/mesh/shell_mesh.h"

namespace ff::scene {

/// What a scene asks of its mesh file.
struct MeshFileRequest {
  std::string path;             ///< resolved against the scene file's folder
  double weld_tolerance = 0.0;  ///< mesh.weld_tolerance: join vertices closer than this (0: none)
};

/// Why a mesh file was not read: a complete sentence naming the file, and the scene key at fault
/// ("" = mesh.file itself; "mesh.weld_tolerance" when that request could not be met).
struct MeshFileError {
  std::string message;
  std::string key;
};

/// Reads the quad mesh of `request` into `out`; on failure returns false and fills *error.
using MeshFileReader = std::function<bool(const MeshFileRequest& request, mesh::ShellMesh& out, MeshFileError* error)>;

}  // namespace ff::scene
