#pragma once
/// \file mesh_import.h
/// Shell meshes from files (assimp: OBJ, PLY, STL, glTF ...) into core's ff::mesh::ShellMesh,
/// and plain OBJ / PLY writers for the same meshes. This header does not include assimp.
///
/// What the importer guarantees about `out` (see core/mesh/shell_mesh.h):
/// - quads exactly as in the file (no triangulation, no recombination); a file with any
///   triangle, n-gon, point or line is refused, naming the file and the counts. STL and glTF 2.0
///   can only store triangles, so in practice quad meshes come from OBJ or PLY;
/// - vertices as the file writes them: two vertices at the same place stay two nodes (a slit
///   stays open) unless options.weld_tolerance > 0 joins those closer than it; vertices used by
///   no face dropped; node order is the order of first use by the faces. OBJ is read by its
///   v / vn / f records (assimp copies a vertex per face corner, which loses vertex identity
///   and line numbers); PLY and the rest through assimp with ValidateDataStructure (STL, glTF:
///   identical corners joined, as those files keep no vertex identity); node transforms applied;
/// - every vertex finite and within 1e150; every index in range; PLY files whose header never
///   ends are refused before assimp sees them (its reader would loop at end of file);
/// - orientation from the file's winding (a face counter-clockwise seen from its front);
///   inconsistent winding between neighbouring faces is refused unless options.reorient;
///   with file normals, a quad wound against its normals is refused (or flipped with reorient);
/// - directors: the file's normals (OBJ vn, PLY nx/ny/nz) when every face corner has one; a
///   node whose corner normals differ by more than 1e-5 rad is a fold node (6 DoF, a director
///   per corner). Without normals: area-weighted average of the adjacent quad normals. The
///   patch description says which. Frames from options.frame_reference; one unstructured
///   patch named after the file stem;
/// - validate(out) passes, or the import fails with its summary.

#include <atomic>
#include <string>
#include <vector>

#include "core/mesh/imported_surface.h"
#include "core/mesh/shell_mesh.h"
#include "core/scene/scene_context.h"

namespace ff::io {

struct MeshImportOptions {
  /// flip quads to agree with their neighbours (breadth-first from the first face of every
  /// connected piece) instead of refusing an inconsistently wound file
  bool reorient = false;
  /// reference direction for the nodal frames' e1 (see ff::mesh::frame_from_normal)
  Eigen::Vector3d frame_reference = Eigen::Vector3d::UnitX();
  /// join vertices closer than this length (0: keep every file vertex, so slits stay open)
  double weld_tolerance = 0.0;
  /// memory the import may use [bytes] (0: unknown). Before anything is read, the element counts a
  /// PLY header declares (an OBJ's, counted from its records when its size could hold too many)
  /// are checked against the file's size and this limit; a file that cannot hold what it declares,
  /// or whose elements would not fit, is refused without allocating for them.
  double memory_limit_bytes = 0.0;
  /// triangles: refused (the default here), or split into quads with core's conversion
  /// (core/mesh/imported_surface.h; then directors are averaged and the file's normals unused)
  ff::mesh::TriangleHandling triangles = ff::mesh::TriangleHandling::refuse;
  double crease_angle_deg = 30.0;  ///< for a split mesh's averaged directors
};

/// Reads `path` into `out`. Returns false and sets *error (a complete sentence naming the file)
/// when the file is missing or unreadable, holds non-quad faces, is inconsistently oriented or
/// non-manifold, or fails ff::mesh::validate. `out` is untouched on failure.
/// With file normals, a normal tilted from its quad's own normal at that corner by more than 5
/// deg beyond the turn of the file's normals across that quad, or by more than 60 deg, is
/// refused (face, corner, node and angle named); the patch description records the largest tilt. *weld_tolerance_at_fault (when given) says that options.weld_tolerance, not the file,
/// is what was refused.
/// *warnings (when given) receives what the user must hear of a mesh that was read (a piece of
/// which a quarter or more was turned to agree with the rest).
bool import_shell_mesh(const std::string& path, ff::mesh::ShellMesh& out, std::string* error,
                       const MeshImportOptions& options = {}, bool* weld_tolerance_at_fault = nullptr,
                       std::vector<std::string>* warnings = nullptr);

/// What the app passes to every scene load: import_shell_mesh (default options, the machine's memory
/// limit) as the reader for scenes with mesh.generator = "file" (core/scene/mesh_file.h), and the
/// memory limit. With `stop`, long set-up polls it (a signal ends it within a fraction of a second)
/// and says what it is doing on stderr once it has taken more than a second.
ff::scene::SceneContext scene_context(const std::atomic<bool>* stop = nullptr);

/// Reads the mesh a scene part asks for (core/scene/mesh_file.h), whatever its format: .msh and CAD
/// (STEP, IGES, BREP, .geo) through Gmsh (gmsh_import.h), Abaqus .inp, OBJ/PLY/STL through
/// import_shell_mesh; triangles as the request says; named groups kept. A surface that touches
/// itself without being joined there (ff::mesh::find_unjoined_contacts: faces side by side with a
/// row of nodes each, a stiffener's foot not joined to its face) is refused at part.file unless
/// request.keep_faces_apart. On failure, error says why and which part.* key is at fault. What
/// the user must hear of a mesh that was read goes into *warnings (a piece of which a quarter or
/// more was turned to agree with the rest, a named group meshed far coarser than its local size).
bool read_mesh_file(const ff::scene::MeshFileRequest& request, ff::mesh::ShellMesh& out, ff::scene::MeshFileError& error,
                    double memory_limit_bytes = 0.0, const std::atomic<bool>* stop = nullptr,
                    std::vector<std::string>* warnings = nullptr);

/// Writes points and quads as Wavefront OBJ (1-based "f a b c d", 17 significant digits); with
/// `normals`, every quad corner's director as a vn record ("f a//i b//j ...").
bool write_shell_mesh_obj(const std::string& path, const ff::mesh::ShellMesh& mesh, std::string* error,
                          bool normals = false);
/// Writes points and quads as ASCII PLY (double coordinates, "4 a b c d" faces); with `normals`,
/// the node directors as nx ny nz (fold nodes keep only their first director: use OBJ for those).
bool write_shell_mesh_ply(const std::string& path, const ff::mesh::ShellMesh& mesh, std::string* error,
                          bool normals = false);

}  // namespace ff::io
