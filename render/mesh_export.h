#pragma once
/// \file mesh_export.h
/// The deformed mesh of a frame as VTK XML files for ParaView and similar tools (no GL needed,
/// no VTK types here). One .vtu (unstructured grid) per frame and a .pvd collection that gives
/// each file its time.
///
/// What a .vtu holds:
///  - points: Frame::points, the current world positions p_W (the run's length unit);
///  - cells: the mesh's lines (VTK_LINE), triangles (VTK_TRIANGLE) and quads (VTK_QUAD), in
///    that order, with the point indices of RunInfo::mesh;
///  - point data: one scalar array per RunInfo::fields entry, named by the field's name (the
///    first is the active scalars); "displacement_xyz" = points - mesh.reference_points and
///    "elastic_displacement_xyz" = points - base_points (3-component vectors; the second only
///    when the frame has base_points);
///  - field data: "TimeValue" (the frame time, ParaView shows it), "step", "load_factor", and
///    the string array "field_units" with one "name: label [unit]" entry per field.

#include <string>
#include <utility>
#include <vector>

#include "core/frame/frame.h"

namespace ff::render {

/// What a .vtu may carry besides the frame: 3-component point-data vectors (e.g. a mode's
/// displacement "mode_2") and numeric field-data arrays (e.g. the modes' frequencies).
struct VtuExtras {
  std::vector<std::pair<std::string, std::vector<double>>> point_vectors;  ///< name, 3 values per point
  std::vector<std::pair<std::string, std::vector<double>>> field_arrays;   ///< name, values
};

/// Writes `frame` of the run `info` as a VTK XML unstructured grid (binary, appended,
/// zlib-compressed), with `extras`. Returns false and fills *error on size mismatches (points,
/// base_points, fields, extra vectors against the mesh) or when the file cannot be written.
bool write_vtu(const std::string& path, const RunInfo& info, const Frame& frame, std::string* error,
               const VtuExtras& extras = {});

/// One entry of a .pvd collection: a time and a file name relative to the .pvd.
struct PvdEntry {
  double time = 0.0;
  std::string file;
};

/// Writes a ParaView collection (.pvd) listing `entries` in order. Returns false and fills
/// *error when the file cannot be written.
bool write_pvd(const std::string& path, const std::vector<PvdEntry>& entries, std::string* error);

}  // namespace ff::render
