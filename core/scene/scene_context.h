#pragma once
/// \file scene_context.h
/// What building a scene may need from the program around it: a mesh file reader, the memory a
/// run may use, the stop flag and progress of a long set-up. The caller of load_scene fills it
/// (the app: ff::io::scene_context(), app/io/mesh_import.h); core keeps no global of its own.

#include <string>
#include <vector>

#include "core/model/setup_monitor.h"
#include "core/scene/mesh_file.h"

namespace ff::scene {

struct MeshQualityReport;

/// What building a scene may need from the program around it (passed in, never global).
struct SceneContext {
  MeshFileReader mesh_reader;  ///< reads generator = "file" meshes; empty: such scenes are refused
  /// Memory a run may use [bytes] (the machine's, or a process/container limit); a scene whose
  /// estimated peak exceeds it is refused at its mesh keys. 0: unknown, nothing is refused.
  double memory_limit_bytes = 0.0;
  /// Long set-up (a large mesh, the hub-beam's matrices) polls its stop flag and reports progress
  /// through it; a model that builds later (at its start()) keeps a copy. Empty: never stopped.
  SetupMonitor setup;
  /// Where a shell structure's builder leaves its mesh quality report (mesh_quality_report.h);
  /// load_scene points it at LoadedScene::mesh_quality. nullptr: the report is not kept.
  MeshQualityReport* mesh_quality = nullptr;
  /// Where a builder leaves its warnings: input it accepts but that is likely a mistake (ply angles
  /// that look like radians), each a located Issue::to_string() line; load_scene points it at
  /// LoadedScene::warnings. nullptr: warnings are not kept.
  std::vector<std::string>* warnings = nullptr;
};

}  // namespace ff::scene
