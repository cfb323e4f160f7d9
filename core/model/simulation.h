#pragma once
/// \file simulation.h
/// What the app's worker thread drives: a model plus its integrator, publishing Frames.
/// Implementations own all solver state; consumers only ever see copies (Frames).

#include <array>
#include <atomic>
#include <functional>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "core/frame/frame.h"

namespace ff {

using Metrics = std::vector<std::pair<std::string, double>>;

/// The value of metric `name`, or nothing when the run did not produce it.
inline std::optional<double> find_metric(const Metrics& m, const std::string& name) {
  for (const auto& [k, v] : m)
    if (k == name) return v;
  return std::nullopt;
}

/// What one effect (elastic, inertia, gravity, joints ...) cost: evaluations and seconds spent.
/// Where the mesh is too coarse, at the end of a run (core/shell/error_indicator.md): the
/// recovered-stress estimate of the energy-norm error, over the whole structure and where its
/// largest share is.
struct FieldErrorEstimate {
  double relative_energy_error = 0.0;  ///< (Z8)
  int elements = 0;
  std::array<double, 3> worst_at{};    ///< reference centroid of the element with the largest share
  double worst_indicator = 0.0;        ///< that element's i_e (Z9) (the RMS of i_e is relative_energy_error)
  /// the fewest elements that carry half of the squared error, as a fraction of all: small when the
  /// error is concentrated (refine there), about 1/2 when it is spread evenly (refine everywhere)
  double half_error_fraction = 0.0;
};

/// An effect that runs fused inside another effect's kernel (hr, ans, drilling inside the elastic
/// shell element; the terms of the hub-beam's dense equations of motion) has no time of its own:
/// `included_in` names the effect whose seconds contain it and `seconds` is NaN (JSON null).
/// Timing the fused parts apart would need clocks inside the element loop; `flexframe bench`
/// measures what switching them off saves instead.
struct EffectStat {
  std::string effect;
  long long evaluations = 0;  ///< element (or model) evaluations in which the effect's terms ran
  double seconds = 0.0;
  std::string included_in;    ///< empty: `seconds` is this effect's own measured time
};

struct SolverTotals {
  long long steps = 0;
  long long newton_iterations = 0;
  long long jacobian_updates = 0;
  long long cutbacks = -1;  ///< steps shortened after a rejected attempt (statics); -1: not counted
};

/// What one step of a model did, as the run loop (run_loop.h) sees it.
struct StepDone {
  bool accepted = false;  ///< a new converged state exists (the loop logs it and may publish it)
  StepStats stats;        ///< of this step alone (dt: its time step, or load increment in statics)
  bool finished = false;  ///< the run ends here: with `status` and `reason`
  RunStatus status = RunStatus::completed;
  std::string reason;     ///< empty when completed
  std::vector<PathEvent> events;  ///< events of the whole run, given with the last step
  /// attempts not accepted, in order, before this step's accepted one (or all of this call's
  /// when none was accepted): rows of the convergence log with converged = false
  std::vector<StepRecord> rejected;
};

/// The value of a live edit, already typed: core/scene reads the text and validates it against
/// the key's declaration in the scene schema (scene::validate_live), so a model gets the
/// alternative its key is declared as (a number as double, a list of numbers as
/// vector<double>, ...) and never parses text itself.
using LiveValue = std::variant<double, long long, bool, std::string, std::vector<double>, std::vector<std::string>>;

/// A model with its integrator, advanced one step at a time. RunLoop (core/model/run_loop.h)
/// drives every Simulation the same way: it owns the stop flag, the split of a step at a
/// [[timeline]] change, the output cadence, the step log and the outcome; a model only knows how
/// to start, take one step, and describe its current state. Implementations own all solver state;
/// consumers only ever see copies (Frames).
class Simulation {
 public:
  virtual ~Simulation() = default;
  virtual const RunInfo& info() const = 0;
  virtual double end_time() const = 0;  ///< for progress and ETA
  /// Where the run ends, for `flexframe check`, e.g. "ends at t = 2 s".
  virtual std::string end_description() const;

  /// Builds what a run needs beyond what `check` validates (the hub-beam's dense matrices), so
  /// that a caller can time it apart from the run; start() does it when nobody did. "" or why it
  /// cannot (set-up interrupted by the stop flag it was given, or a numerical failure).
  virtual std::string prepare() { return ""; }

  // ---- stepping (called by RunLoop, on one thread) ----
  /// Prepares the initial state (consistent accelerations ...): "" or why it cannot start.
  virtual std::string start() = 0;
  /// Newton statistics of that preparation (the initial frame's stats).
  virtual StepStats start_stats() const { return {}; }
  /// How a start() that gave a reason ended: failed by default; diverged where its Newton
  /// iteration (a static start) did not converge or went non-finite.
  virtual RunStatus start_failure_status() const { return RunStatus::failed; }
  /// Time (or load factor, in statics) of the current state.
  virtual double time() const = 0;
  /// The regular step of a time-stepping model (the loop keeps later steps on its grid when a
  /// timeline change splits one); infinity for a model that sizes its own steps (statics).
  virtual double nominal_step() const { return std::numeric_limits<double>::infinity(); }
  /// Time of the first planned [[timeline]] parameter change later than t (infinity: none).
  virtual double next_change(double t) const { return std::numeric_limits<double>::infinity(); }
  /// Applies the planned changes due at t and any pending live change; true when anything
  /// changed (the loop then calls restart()).
  virtual bool apply_changes(double t) { return false; }
  /// Restarts the integrator from the current state after a change: "" or why it cannot.
  virtual std::string restart() { return ""; }
  /// One step of length h (time models; a self-sizing model takes its own), from the current state.
  virtual StepDone step(double h) = 0;
  /// The current state as a Frame (the loop sets step, stats and step_log).
  virtual Frame frame() const = 0;
  /// Publish every n-th step (the others are logged); the last state is always published.
  virtual int output_every() const { return 1; }
  /// A frame published every n-th step carries the log of every step since the previous one.
  virtual bool logs_skipped_steps() const { return false; }
  /// Called with every frame the loop publishes (e.g. for metrics read off published states).
  virtual void on_publish(const Frame& frame) { (void)frame; }

  /// Metrics of what was computed so far (name -> number), e.g. after the run.
  virtual Metrics metrics() const = 0;
  /// The metrics the scene asks for that have no value, each with why (e.g. a load the path
  /// never reached): summary.json keeps them as null under "metrics" and says why under
  /// "metrics_unreached", and run warns, instead of leaving them out.
  virtual std::vector<std::pair<std::string, std::string>> metrics_unreached() const { return {}; }
  /// The metrics that are answers of the discretized physics (probe readings, frequencies, loads),
  /// which a coarser mesh or a longer time step changes: these get error bars
  /// (core/model/error_bars.md). The others (Newton counts, wall time, drifts, constraint
  /// violations) describe the solver and get none.
  virtual std::vector<std::string> answer_metrics() const { return {}; }
  /// Answers of the physics that no error bar can follow yet, each with why: the console and
  /// summary.json say it beside the value instead of printing it like a solver count.
  virtual std::vector<std::pair<std::string, std::string>> answers_without_bar() const { return {}; }
  /// The field error indicator at the run's last state, for models that record it (a shell
  /// structure with output.error_bar on); empty otherwise.
  virtual std::optional<FieldErrorEstimate> field_error_estimate() const { return std::nullopt; }
  /// Where each answer metric read at one node reads (reference coordinates): a coarser twin whose
  /// probe picked another node compares another point, which the error bars must say
  /// (core/model/error_bars.md §6). Metrics read elsewhere (sums, modes, the load) are absent.
  virtual std::vector<std::pair<std::string, std::array<double, 3>>> metric_points() const { return {}; }
  /// The time-step error of each answer metric of a time-stepping run as its integrator's local
  /// error estimate says it (core/solve/generalized_alpha.md §9): the local errors of the steps
  /// accumulated up to where the metric was read, in the metric's unit (absolute). Metrics the
  /// estimate cannot follow (stress readings, arcs) are absent; empty for models without one.
  virtual std::vector<std::pair<std::string, double>> local_time_errors() const { return {}; }
  /// The modes an eigen-analysis (scene.analysis = "modal" or "buckling") found, after the run;
  /// null for analyses that compute none.
  virtual const ModeSet* modes() const { return nullptr; }
  virtual SolverTotals totals() const = 0;
  /// Effects that were evaluated, with their counts and times (summary.json "effect_stats");
  /// empty where a model does not count them.
  virtual std::vector<EffectStat> effect_stats() const { return {}; }
  /// Threads of the model's element loops from now on: `count` (0 = OMP_NUM_THREADS when set,
  /// else the cores this process may run on), one fewer while *busy_with_other_work (the frame
  /// renderer; null: never). Passed down to the loops (core/assembly/element_threads.h), never
  /// kept per thread. Models without element loops ignore it.
  virtual void set_element_threads(int count, const std::atomic<bool>* busy_with_other_work) {
    (void)count, (void)busy_with_other_work;
  }
  /// A parameter change while the run goes on (the GUI's live edits), made between steps on the
  /// solver's own thread; it takes effect at the start of the next step, exactly as a [[timeline]]
  /// change at that time would. `key` is one the scene schema declares live and `value` has been
  /// validated against it (scene::change_live does both). Returns "" when accepted, otherwise
  /// why not, e.g. a state the value cannot apply to (the caller then rebuilds the model instead).
  virtual std::string change_live(const std::string& key, const LiveValue& value) {
    (void)value;
    return "'" + key + "' cannot change while the model runs";
  }

  /// The whole run with RunLoop: publishes the initial state and the steps by the output cadence,
  /// until the end, a divergence, or `stop` becoming true. Never throws for numerical trouble:
  /// that is the outcome.
  RunOutcome run(const std::function<void(Frame&&)>& publish, const std::atomic<bool>& stop);
};

}  // namespace ff
