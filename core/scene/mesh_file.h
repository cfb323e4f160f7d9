#pragma once
/// \file mesh_file.h
/// How `mesh.generator = "file"` reaches a mesh reader. Core reads no mesh files (no assimp in
/// core/); the app installs its importer (app/io/mesh_import.h, ff::io::install_mesh_file_reader)
/// before loading scenes, and a program that installs none gets a located scene error instead.

#include <functional>
#include <string>

#include "core/mesh/shell_mesh.h"

namespace ff::scene {

/// Reads the quad mesh at `path` into `out`; on failure returns false and sets *error to a
/// complete sentence naming the file.
using MeshFileReader = std::function<bool(const std::string& path, mesh::ShellMesh& out, std::string* error)>;

/// Installs the reader used by every later scene load (process-wide; call once at start-up,
/// before any thread loads scenes). An empty function uninstalls it.
void set_mesh_file_reader(MeshFileReader reader);
/// The installed reader; empty when none is.
const MeshFileReader& mesh_file_reader();

}  // namespace ff::scene
