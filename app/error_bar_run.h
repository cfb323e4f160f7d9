#pragma once
/// \file error_bar_run.h
/// Every run's metrics with their discretization error: the scene's coarser twins
/// (core/scene/discretization_twins.h) are solved after the run, and their metrics turned into an
/// estimate and a bar per metric (core/model/error_bars.{h,md}); the console line, summary.json
/// "error_bars" and the cost as a share of the run come from here.

#include <array>
#include <atomic>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "core/model/error_bars.h"
#include "app/plots.h"
#include "core/model/simulation.h"

namespace ff::app {

/// One twin as it ran.
struct TwinRun {
  std::string name;         ///< "mesh", "time", "mesh_at_2dt" (discretization_twins.h)
  std::string description;  ///< what differs from the run
  RunStatus status = RunStatus::failed;
  std::string reason;       ///< why it did not complete; also a twin that could not be built
  double wall_s = 0.0;
  int elements = 0;         ///< quads of its mesh
  Metrics metrics;
  std::map<std::string, int> events;  ///< path events by kind (statics)
  std::vector<std::pair<std::string, std::array<double, 3>>> points;  ///< Simulation::metric_points
  std::optional<ModeSet> modes;  ///< an eigen-analysis twin's modes (paired with the run's by MAC)
  /// its refinement ratio to the run itself ((R5); 2 for a time twin), when it completed on the
  /// run's path; 0 when it is not directly below the run (mesh_at_2dt, *_coarser) or cannot stand
  /// beside it. The plots' error band (richardson_bands) is drawn from such a twin.
  double ratio = 0.0;
  /// why it cannot stand beside the run (it did not complete, or its path differs in kind from the
  /// run's, error_bars.md §6); "" when it can. Set once the twins have run.
  std::string problem;
  /// a completed twin whose path differs in kind (another count of limit points, bifurcations,
  /// turn-backs): the run warns and records it as an event
  bool path_differs() const { return status == RunStatus::completed && !problem.empty(); }
  /// a third level's twin (mesh_coarser, time_coarser, ...): its failure drops only its own level
  bool third_level() const { return name.find("_coarser") != std::string::npos; }
  /// the plan's h_twin / h_run for a generator-only mesh twin (TwinPlan::mesh_ratio); 0 otherwise
  double planned_ratio = 0.0;
  RunInfo info;          ///< its probes (for plots beside the run's)
  PlotHistory history;   ///< its probes at every frame it published (plots, results.h5)
};

struct ErrorBarReport {
  bool on = false;              ///< asked for (--error-bar, output.error_bar)
  int levels = 2;               ///< levels per source (the run and one or two twins)
  bool local_time = false;      ///< the time source is the integrator's local error (R9), no time twin
  std::string not_estimated;    ///< why no twin ran although asked ("" when they ran)
  std::vector<TwinRun> twins;
  std::vector<std::string> missing;  ///< sources without a twin, and why
  std::vector<MetricError> metrics;  ///< one per answer metric the run has
  double twins_wall_s = 0.0;
  double run_wall_s = 0.0;      ///< the run's set-up (reading, meshing) and solve
  bool interrupted = false;     ///< the stop flag ended a twin
  /// the twins' wall time over the run's (the cost of the bars, as a share of the run)
  double cost_share() const { return run_wall_s > 0 ? twins_wall_s / run_wall_s : 0.0; }
  const MetricError* find(const std::string& metric) const;
};

/// Runs the twins of the scene at `scene_path` (with the run's `overrides`) and estimates the
/// error of each of `run`'s answer metrics. `run_elements`: quads of the run's mesh (0 when it has
/// none); `outcome`: the run's, whose events the twins' paths are compared with; `setup_wall_s`:
/// what building the run's model took (reading and meshing its parts), which the twins pay again,
/// so that the cost share compares like with like; `levels`: 2 (one twin per source, formal
/// order), 3 (two twins per source, observed order) or 0 (the scene's output.error_bar_levels). A twin that cannot
/// be built or does not complete flags the metrics instead of failing the run; the stop flag ends
/// a twin (interrupted). `field_error`: the run's field indicator, which a mesh no twin can
/// coarsen (a fixed mesh file) reports beside its "no mesh estimate".
ErrorBarReport estimate_error_bars(const std::string& scene_path, const std::vector<std::string>& overrides,
                                   const Simulation& run, const RunOutcome& outcome, double setup_wall_s,
                                   int run_elements, int levels, const std::optional<FieldErrorEstimate>& field_error,
                                   const std::atomic<bool>& stop);

/// What `check` says the bars will cost before the run: the twins a run of the scene would solve,
/// what each changes and its expected share of the run, and the sources without a twin.
std::string error_bar_plan_text(const std::string& scene_path, const std::vector<std::string>& overrides);

/// The console's text after the metric's value, e.g. "± 0.0031 (0.7 %: mesh 0.6 %, time 0.1 %)",
/// or "(no bar: <flag>)"; "" for a metric without an estimate.
std::string error_bar_text(const MetricError& m);

/// summary.json "error_bars": per metric its value, estimate, extrapolated value, bar, sources
/// (levels, ratio, order, safety factor), flags and what is missing; the twins and the cost.
nlohmann::ordered_json error_bars_json(const ErrorBarReport& report);

/// summary.json "field_error" (and results.h5's attribute of that name): the recovered-stress
/// estimate of where the mesh is too coarse (core/shell/error_indicator.md).
nlohmann::ordered_json field_error_json(const FieldErrorEstimate& e);
/// The console's line of it, e.g. "field error (recovered stresses): 3.1 % in the energy norm; half of
/// it in 4 % of the elements, the most at (0.98, 0.05, 0): refine there (plots/error_indicator.png)".
std::string field_error_text(const FieldErrorEstimate& e, bool picture);

}  // namespace ff::app
