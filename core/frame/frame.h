#pragma once
/// \file frame.h
/// The plain values that travel from the solver to every consumer (HDF5 store, renderer, GUI).
/// No pointers into solver state; copyable; no dependencies beyond the standard library.
/// Units are SI unless a scene says otherwise; positions are in the world frame W.

#include <cstdint>
#include <string>
#include <vector>

namespace ff {

/// A named scalar quantity with its unit, e.g. {"hub_angle", "deg", "hub angle"}.
struct Quantity {
  std::string name;   ///< machine name, also the HDF5 data set name
  std::string unit;   ///< unit for axis labels, e.g. "m", "deg", "rad/s", "" for none
  std::string label;  ///< human label for plots and legends
};

/// Geometry that stays constant for a run: what is drawn, in the reference configuration.
struct FrameMesh {
  std::vector<double> reference_points;  ///< 3*n world coordinates p_WP of the n drawn points
  std::vector<std::int32_t> lines;       ///< 2*k point indices: line segments
  std::vector<std::int32_t> triangles;   ///< 3*k point indices
  std::vector<std::int32_t> quads;       ///< 4*k point indices
  std::size_t point_count() const { return reference_points.size() / 3; }
};

/// Newton statistics of the step that produced a frame.
struct StepStats {
  double dt = 0.0;                 ///< step size used (time for dynamics, load for statics)
  std::int32_t iterations = 0;     ///< Newton iterations in this step
  std::int32_t jacobian_updates = 0;  ///< iteration-matrix factorizations in this step
  double residual_norm = 0.0;      ///< final residual norm
  double increment_norm = 0.0;     ///< final increment norm
  bool converged = true;
};

/// One solver step of the convergence log (MBDyn-style: one line per step).
struct StepRecord {
  std::int64_t step = 0;  ///< solver step number (1 = the first step)
  double time = 0.0;      ///< time (or load factor) at the end of the step
  StepStats stats;        ///< of this step alone
};

/// Reference data a plot overlays as markers: y(x) where x and y name probes of this run
/// (e.g. x = "load", y = "disp_outward"), with where the numbers come from.
struct ReferenceSeries {
  std::string x_probe, y_probe;
  std::string label;                ///< legend, e.g. "Sze et al. 2004 (ABAQUS S4R)"
  std::vector<double> x, y;
};

/// Constant description of a run, published once before the first frame.
struct RunInfo {
  std::string scene_name;                 ///< e.g. "hub_beam_efg_tau1"
  std::string scene_path;                 ///< path the scene was read from
  std::string scene_text;                 ///< full scene file text (results are self-contained)
  std::vector<std::string> effects;       ///< effects the model evaluates, e.g. {"inertia", ...}
  std::vector<std::pair<std::string, std::string>> settings;  ///< solver/model settings, key -> value
  std::string time_unit = "s";            ///< unit of Frame::time
  FrameMesh mesh;
  std::vector<Quantity> probes;           ///< scalar probes, in the order of Frame::probes
  std::vector<Quantity> fields;           ///< per-point fields, in the order of Frame::fields
  std::string plot_x_probe;               ///< probe on the plots' x axis; "" = time
  std::vector<ReferenceSeries> references;  ///< reference curves overlaid on the plots
};

/// One published state of the model.
struct Frame {
  std::int64_t step = 0;          ///< solver step that produced it (0 = initial state)
  double time = 0.0;              ///< simulated time (pseudo-time for statics)
  double load_factor = 0.0;       ///< load factor lambda (statics); 0 where meaningless
  std::vector<double> points;     ///< 3*n current world positions of the mesh points
  std::vector<double> base_points;  ///< 3*n positions of the undeformed body carried by its
                                    ///< rigid motion (points - base_points = elastic deformation)
  std::vector<double> probes;     ///< values in the order of RunInfo::probes
  std::vector<std::vector<double>> fields;  ///< per-point values in the order of RunInfo::fields
  StepStats stats;
  /// Every solver step since the previous frame, this frame's step last, for models that
  /// publish every n-th step (stats then sums their iterations and updates). Empty when the
  /// frame's own stats are its only step.
  std::vector<StepRecord> step_log;
};

/// One eigen-pair of a modal or a linear buckling analysis, as consumers see it (issue 36).
struct Mode {
  std::int32_t number = 0;   ///< 1-based, in increasing order of `value`
  double value = 0.0;        ///< natural frequency in Hz (modal) or load multiplier (buckling)
  double eigenvalue = 0.0;   ///< what the eigen-solver returned: omega^2 in rad^2/s^2, or the multiplier
  bool rigid_body = false;   ///< a zero frequency: a rigid-body mode of a free part or a mechanism
  /// 3*n displacements of RunInfo::mesh's drawn points for the mode at unit amplitude (its
  /// largest nodal translation is 1 in the scene's length unit), about ModeSet's base state
  std::vector<double> displacement;
};
/// The result of an eigen-analysis: its modes about one state of the structure. The state itself
/// is the run's last published Frame (the reference, or the preloaded state the modes are about).
struct ModeSet {
  std::string analysis;      ///< "modal" or "buckling"
  std::string value_name;    ///< "frequency" or "load_multiplier" (HDF5 / JSON name)
  std::string value_unit;    ///< "Hz" or "" (a multiplier of the scene's loads)
  std::string value_label;   ///< for tables and plots, e.g. "natural frequency"
  std::string about;         ///< the state, in words, e.g. "reference state" or "preloaded to lambda = 1"
  std::vector<Mode> modes;
};

/// How a run ended. `incomplete`: it stopped early by design (a step budget ran out) before its end.
enum class RunStatus { completed, incomplete, diverged, interrupted, failed };

inline const char* to_string(RunStatus s) {
  switch (s) {
    case RunStatus::completed: return "completed";
    case RunStatus::incomplete: return "incomplete";
    case RunStatus::diverged: return "diverged";
    case RunStatus::interrupted: return "interrupted";
    case RunStatus::failed: return "failed";
  }
  return "failed";
}

/// Something the solution path did on the way, e.g. a limit point of a static load path.
struct PathEvent {
  std::string kind;           ///< "limit_point", "bifurcation", "turn_back", "unloaded", "loop", ..."
  std::int64_t step = 0;      ///< the converged step (frame step) after which it was seen
  double load_factor = 0.0;   ///< load factor (or time) there
  std::string detail;         ///< one sentence
};

/// Final word of a run: status, why, and where it stopped.
struct RunOutcome {
  RunStatus status = RunStatus::completed;
  /// why it ended; when completed, empty unless the path did something a reader must know
  /// (statics: returns to the unloaded state, loops)
  std::string reason;
  double stop_time = 0.0;    ///< simulated time of the last converged frame
  std::int64_t steps = 0;    ///< converged steps
  std::int64_t cutbacks = -1;  ///< steps shortened after a rejected attempt (statics); -1: not counted
  double wall_time_s = 0.0;
  std::vector<PathEvent> events;  ///< in path order; empty where a model reports none
  /// attempts made after the last converged step and not accepted (the step the run died on):
  /// rows of the convergence log with converged = false that belong to no published frame
  std::vector<StepRecord> trailing_attempts;
};

}  // namespace ff
