#pragma once
/// \file mesh_import.h
/// Shell meshes from files (assimp: OBJ, PLY, STL, glTF ...) into core's ff::mesh::ShellMesh,
/// and plain OBJ / PLY writers for the same meshes. This header does not include assimp.
///
/// What the importer guarantees about `out` (see core/mesh/shell_mesh.h):
/// - quads exactly as in the file (no triangulation, no recombination); a file with any
///   triangle, n-gon, point or line is refused, naming the file and the counts. STL and glTF 2.0
///   can only store triangles, so in practice quad meshes come from OBJ or PLY;
/// - node transforms of the file applied (glTF/OBJ groups), coincident vertices joined
///   (distance <= 1e-9 x bounding-box diagonal), vertices used by no face dropped; node order
///   is the order of first use by the faces;
/// - orientation from the file's winding (a face counter-clockwise seen from its front);
///   inconsistent winding between neighbouring faces is refused unless options.reorient;
/// - normals = area-weighted average of the adjacent quad normals; frames from
///   options.frame_reference; one unstructured patch named after the file stem;
/// - validate(out) passes, or the import fails with its summary.

#include <string>

#include "core/mesh/shell_mesh.h"
#include "core/scene/mesh_file.h"

namespace ff::io {

struct MeshImportOptions {
  /// flip quads to agree with their neighbours (breadth-first from the first face of every
  /// connected piece) instead of refusing an inconsistently wound file
  bool reorient = false;
  /// reference direction for the nodal frames' e1 (see ff::mesh::frame_from_normal)
  Eigen::Vector3d frame_reference = Eigen::Vector3d::UnitX();
};

/// Reads `path` into `out`. Returns false and sets *error (a complete sentence naming the file)
/// when the file is missing or unreadable, holds non-quad faces, is inconsistently oriented or
/// non-manifold, or fails ff::mesh::validate. `out` is untouched on failure.
bool import_shell_mesh(const std::string& path, ff::mesh::ShellMesh& out, std::string* error,
                       const MeshImportOptions& options = {});

/// What the app passes to every scene load: import_shell_mesh (default options) as the reader for
/// scenes with mesh.generator = "file" (core/scene/mesh_file.h).
ff::scene::SceneContext scene_context();

/// Writes points and quads as Wavefront OBJ (1-based "f a b c d", 17 significant digits).
bool write_shell_mesh_obj(const std::string& path, const ff::mesh::ShellMesh& mesh, std::string* error);
/// Writes points and quads as ASCII PLY (double coordinates, "4 a b c d" faces).
bool write_shell_mesh_ply(const std::string& path, const ff::mesh::ShellMesh& mesh, std::string* error);

}  // namespace ff::io
