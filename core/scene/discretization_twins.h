#pragma once
/// \file discretization_twins.h
/// Which coarser twins of a scene measure its discretization error (core/model/error_bars.md §5):
/// the same scene with extra --set overrides, so that a twin is built by load_scene exactly as the
/// run was and differs only in its mesh or its time step.

#include <string>
#include <vector>

namespace ff::scene {

/// One twin: the run's scene with `overrides` added after the run's own.
struct TwinPlan {
  /// "mesh" (coarser mesh, the run's time step: statics, eigen, and dynamics with the local time
  /// estimate), "time" (the run's mesh at twice its time step),
  /// "mesh_at_2dt" (coarser mesh at twice the time step: the mesh estimate of a dynamic run, (R8));
  /// with three levels also "mesh_coarser" (halved twice), "time_coarser" (4 dt) and
  /// "mesh_coarser_at_2dt"
  std::string name;
  std::vector<std::string> overrides;
  std::string description;  ///< what differs from the run, e.g. "part[0].n1 = 8 (15), part[0].n2 = 8 (15)"
  /// a mesh twin's h_twin / h_run where the counts give it exactly (generator parts only: the
  /// geometric mean of n / n_twin over the counts halved); 0: measured from element counts (R5)
  double mesh_ratio = 0.0;
};

struct TwinPlans {
  std::vector<TwinPlan> twins;  ///< in the order to run them
  /// sources that get no twin, each a sentence saying why and what would give one
  /// ("no mesh estimate: part[1].file is a fixed mesh (...)")
  std::vector<std::string> missing;
  bool dynamic = false;  ///< a time-stepping run (time and mesh_at_2dt twins)
  /// the time source is the run's own accumulated local error (error_bars.md (R9)), no time twin:
  /// a shell structure in dynamics with two levels; its mesh twin then runs at the run's step
  bool local_time = false;
  bool on = true;        ///< the scene's output.error_bar (--error-bar overrides it)
  int levels = 2;        ///< levels per source: the run and one twin, or two (the observed order)
};

/// How TwinPlans::missing begins the sentence of a third mesh level that was not made: it removes
/// no source (the two levels remain), so the console says it once, not beside every metric.
inline constexpr const char* kNoThirdMeshLevel = "no third mesh level (two only): ";

/// The twins of the scene at `path` with the run's `overrides`, for `levels` = 2 or 3 levels per
/// source (the run counts as one; 0: the scene's output.error_bar_levels, whose auto is 3 for static and eigen
/// runs and 2 for runs in time). Throws SceneError when the scene does not validate (the run
/// would have refused it first).
TwinPlans discretization_twins(const std::string& path, const std::vector<std::string>& overrides, int levels = 2);


}  // namespace ff::scene
