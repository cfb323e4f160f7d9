#pragma once
/// \file frame_export.h
/// The deformed mesh of one frame as a glTF 2.0 or OBJ file, written through assimp's exporter
/// (this header does not include assimp). For VTK XML (.vtu/.pvd) see render/mesh_export.h.
///
/// What a file holds: one mesh per cell kind present ("surfaces", "lines"), each with the
/// frame's points its cells use as vertices (Frame::points, world coordinates p_W, in point
/// order; a mesh of quads over all points has vertex i = point i) and
///  - the triangles, and each quad as two triangles (a, b, c) and (a, c, d): glTF has no quads;
///  - the line segments as line primitives (glTF mode LINES; OBJ "l").
/// Every vertex carries its point index as texture coordinate u (v = 0; glTF TEXCOORD_0,
/// OBJ "vt"): it maps vertices back to results.h5 and keeps coincident points (the node pairs
/// of a hinge) apart, which assimp's exporters would otherwise join into one vertex.
/// With a colour field the vertices carry colours from the frames' blue - grey - red map over
/// the given range (glTF COLOR_0). glTF is y-up: the root node rotates the scene's z-up world
/// by -90° about x so viewers show it upright; the vertex coordinates themselves are p_W.

#include <array>
#include <string>
#include <vector>

#include "core/frame/frame.h"

namespace ff::io {

enum class MeshFileFormat {
  gltf_binary,  ///< .glb, one self-contained file (assimp format id "glb2")
  obj,          ///< .obj with a .mtl beside it (assimp format id "obj")
};

/// File extension without the dot: "glb", "obj".
const char* extension(MeshFileFormat format);

/// Writes `frame` of the run `info` to `path`. color_field: index into info.fields, or -1 for
/// no vertex colours; range: field values mapped to the ends of the colour map. Returns false
/// and sets *error on size mismatches or when assimp cannot write the file. `files`, when given,
/// receives every file written (an OBJ's .mtl beside it too), each opened without following a
/// link (core/frame/output_file.h).
bool write_frame_mesh(const std::string& path, MeshFileFormat format, const RunInfo& info, const Frame& frame,
                      int color_field, std::array<double, 2> range, std::string* error,
                      std::vector<std::string>* files = nullptr);

}  // namespace ff::io
