#pragma once
/// \file simulation.h
/// What the app's worker thread drives: a model plus its integrator, publishing Frames.
/// Implementations own all solver state; consumers only ever see copies (Frames).

#include <atomic>
#include <functional>
#include <optional>
#include <string>
#include <utility>
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
};

class Simulation {
 public:
  virtual ~Simulation() = default;
  virtual const RunInfo& info() const = 0;
  /// Runs until the end time, a divergence, or `stop` becoming true. Publishes the initial state
  /// and every converged step. Never throws for numerical trouble: that is the outcome.
  virtual RunOutcome run(const std::function<void(Frame&&)>& publish, const std::atomic<bool>& stop) = 0;
  /// Metrics of what was computed so far (name -> number), e.g. after run() returns.
  virtual Metrics metrics() const = 0;
  virtual SolverTotals totals() const = 0;
  virtual double end_time() const = 0;  ///< for progress and ETA
  /// Effects that were evaluated, with their counts and times (summary.json "effect_stats");
  /// empty where a model does not count them.
  virtual std::vector<EffectStat> effect_stats() const { return {}; }
  /// A parameter change while the run goes on (the GUI's live edits). Call it from inside run()'s
  /// publish callback, i.e. between steps on the solver's own thread; it takes effect at the start
  /// of the next step, exactly as a [[timeline]] change at that time would. Returns "" when
  /// accepted, otherwise why not (the caller then rebuilds the model instead).
  virtual std::string change_live(const std::string& key, const std::string& value) {
    (void)value;
    return "'" + key + "' cannot change while the model runs";
  }
};

}  // namespace ff
