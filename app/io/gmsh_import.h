#pragma once
/// \file gmsh_import.h
/// Meshes through the Gmsh library: .msh files (formats 2 and 4) read as they are, and CAD parts
/// (STEP, IGES, BREP) or Gmsh .geo scripts meshed into quads, into core's ImportedSurface
/// (core/mesh/imported_surface.h) with every physical group as a named group.
///
/// Every Gmsh call runs in a child process (fork), for three reasons measured or read in Gmsh 4.8:
/// - a crash in Gmsh (the quad mesher, Mesh.Algorithm = 8, segfaults on a simple cylindrical
///   roof; malformed files reach asserts) must not take the run with it: the child's death is
///   reported with its signal;
/// - a mesher that runs long is bounded: the child is killed at the time limit, or when the
///   stop flag (a signal) is set;
/// - a .geo script is a program (it can Save files, run System commands, read files and the
///   environment): the child runs under a seccomp filter that refuses every write, create,
///   delete, rename, exec and socket call, so a scene from a stranger cannot touch anything
///   outside its output folder; with an empty environment (GetEnv reads ""); and, where the
///   kernel has Landlock (Linux 5.13+), reading only the file's folder and below and the loaded
///   libraries' folders (else a note says what is not confined). Its memory is limited to the
///   machine's limit (setrlimit), so a huge mesh fails in the child.
/// The child dies with its parent (PR_SET_PDEATHSIG), and sends the mesh back through a pipe;
/// nothing is written to disk. Before it starts, the parent refuses what is not a regular file
/// or is larger than the memory limit (core/frame/input_file.h), and a .msh file whose $Nodes or
/// $Elements header claims more than its bytes hold or the memory limit allows; geometry whose
/// estimated mesh (area over size squared) exceeds request.most_nodes is refused before meshing.

#include <atomic>
#include <string>
#include <utility>
#include <vector>

#include "core/mesh/imported_surface.h"

namespace ff::io {

struct GmshMeshRequest {
  std::string path;
  /// CAD or .geo: generate a 2D mesh (recombined into quads). A .msh file is read as it is.
  bool mesh_geometry = false;
  /// the largest element size (Mesh.MeshSizeMax); 0 = the file's own sizes (a .geo's)
  double mesh_size = 0.0;
  /// a smaller size at the points of a named physical group (name, size)
  std::vector<std::pair<std::string, double>> group_sizes;
  /// CAD: faces that touch without sharing an edge are joined first (OpenCASCADE's fragment of
  /// every face against the others; the physical groups found again on the new entities)
  bool join_touching_faces = true;
  /// geometry with mesh_size: faces bounded by four curves meshed as mapped (structured) grids,
  /// unless something is embedded in them or a local size touches them (part.mesh_pattern)
  bool mapped_faces = true;
  /// a mesh file's triangles joined into quads by Gmsh's recombination (Blossom)
  bool recombine_triangles = false;
  double time_limit_seconds = 300.0;
  double memory_limit_bytes = 0.0;  ///< 0: no limit
  /// geometry: the most nodes its mesh may have (0: no bound); an estimate above it (the surfaces'
  /// area over the element size squared, before meshing) is refused
  double most_nodes = 0.0;
  const std::atomic<bool>* stop = nullptr;
};

/// True for the extensions Gmsh reads here: .msh, .step/.stp, .iges/.igs, .brep/.brp, .geo.
bool gmsh_reads(const std::string& path);
/// True when the file is geometry to be meshed (not .msh).
bool gmsh_is_geometry(const std::string& path);

/// Reads or meshes `request.path` into `out`. False with a complete sentence naming the file and
/// the entity or group at fault in *error: unreadable file, Gmsh error (with its last message),
/// no surface, volume or second-order elements, an empty or unnamed-group problem, a crash (the
/// signal), the time limit, a stop, or memory.
bool read_with_gmsh(const GmshMeshRequest& request, ff::mesh::ImportedSurface& out, std::string* error);

}  // namespace ff::io
