#pragma once
/// \file shell_static_simulation.h
/// Nonlinear statics of a shell model: load control (Newton with cut-backs) or arc-length path
/// following, one Frame per converged step (Frame::time and load_factor = lambda), probes of
/// node displacements against the load, and the metrics a scene asks for.

#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <tuple>
#include <vector>

#include "core/model/simulation.h"
#include "core/shell/shell_model.h"
#include "core/solve/static_arclength.h"
#include "core/solve/static_newton.h"

namespace ff::shell {

/// A scalar probe: direction . u(node) for a displacement, direction . (sum of the reactions
/// over `nodes`) for a reaction (global direction, unit or not), the nodal value of the stress
/// field `field` (a name of stress_fields, shell_stress.h) at `node` for a stress.
struct ShellProbe {
  enum class Quantity { displacement, reaction, stress };
  std::string name, label;
  int node = -1;
  Vec3 direction = Vec3::UnitZ();
  Quantity quantity = Quantity::displacement;
  std::vector<int> nodes;  ///< reaction: the nodes summed
  std::string field;       ///< stress: the field read
};

/// A metric of the load path (summary.json "metrics").
struct ShellMetric {
  /// linear_buckling_load: the first critical load of a linear buckling analysis of the same
  /// structure and loads about the reference state (shell_eigen.md), computed when the run starts
  /// (not while the scene is read: `check` solves nothing), to put beside the first limit load the
  /// path finds
  enum class Kind { at_load, final_value, first_limit_load, at_first_limit, min_load_after_limit, max_abs,
                    linear_buckling_load };
  std::string name;
  Kind kind = Kind::final_value;
  std::string probe;       ///< probe name (unused for the load-only kinds)
  double load = 0.0;       ///< at_load: the load where the probe is read (interpolated along the path)
  /// linear_buckling_load: its value (NaN when the analysis found none, or before the run started)
  double computed = std::numeric_limits<double>::quiet_NaN();
  std::string computed_why = "the linear buckling analysis runs when the run starts";  ///< why there is none
};

struct ShellStaticSettings {
  /// linear: one solve K(q0) du = lambda_end f_ref at the reference state (shell_model.md §L);
  /// otherwise load control, or arc length when arc_length is set
  bool linear = false;
  bool arc_length = false;
  LoadControlSettings load_control;
  ArcLengthSettings arc;
  double load_scale = 1.0;        ///< load = lambda * load_scale (the scene's reference load)
  std::string load_label = "load", load_unit;
  std::vector<ShellProbe> probes;
  std::vector<ShellMetric> metrics;
  /// With a linear_buckling_load metric: the buckling analysis the run starts with, which sets
  /// the critical load (in the scene's load units) or why there is none. The scene layer makes it
  /// (a ShellEigenSimulation of the structure as the scene built it), so that the two analyses
  /// need not know each other.
  std::function<void(double& critical_load, std::string& why)> linear_buckling;
  /// every stress field (shell_stress.h) of the structure in every frame, after displacement and
  /// strain (a scene's output.stresses, or a stress field it colours or probes)
  bool record_stresses = false;
  /// the recovered-stress error indicator field in every frame and its summary at the end
  /// (error_indicator.h; the scene's output.error_bar)
  bool record_error_indicator = false;
  std::string monitor_probe;      ///< arc length: probe whose |value| ends the run at displacement_limit
  double displacement_limit = std::numeric_limits<double>::infinity();
};

class ShellStaticSimulation final : public Simulation {
 public:
  ShellStaticSimulation(ShellModelSpec spec, ShellStaticSettings settings, RunInfo info);
  ~ShellStaticSimulation() override;
  const RunInfo& info() const override { return info_; }
  double end_time() const override;  ///< lambda at the end
  std::string end_description() const override;  ///< the load range, not a time
  std::string start() override;
  double time() const override { return lambda_; }
  StepDone step(double h) override;  ///< one converged step of the path (h is not used: the solver sizes it)
  Frame frame() const override;
  Metrics metrics() const override;
  std::vector<std::string> answer_metrics() const override;
  std::optional<FieldErrorEstimate> field_error_estimate() const override;
  std::vector<std::pair<std::string, std::array<double, 3>>> metric_points() const override;
  std::vector<std::pair<std::string, std::string>> metrics_unreached() const override;
  SolverTotals totals() const override { return totals_; }
  std::vector<EffectStat> effect_stats() const override { return model_->effect_stats(); }
  void set_element_threads(int count, const std::atomic<bool>* busy) override {
    model_->set_threads({count, busy});
  }
  const ShellModel& model() const { return *model_; }

 private:
  double probe_value(std::size_t k) const;  // probe k of settings_.probes
  /// every metric of the scene in its order: its value (NaN when it has none) and why it has none
  std::vector<std::tuple<std::string, double, std::string>> evaluate_metrics() const;
  std::string unreached_reason(const ShellMetric& metric, int limit_sample) const;
  void record();  // load and probes of the current state into the path history
  StepDone linear_step();  // the whole linear analysis, as the run's only step
  void predict_linear_buckling();  // the linear_buckling_load metrics' one buckling analysis
  bool buckling_predicted_ = false;
  std::unique_ptr<ShellModel> model_;
  ShellStaticSettings settings_;
  RunInfo info_;
  SolverTotals totals_;
  std::unique_ptr<LoadControlPath> load_control_;  // one of the two, by settings_.arc_length
  std::unique_ptr<ArcLengthPath> arc_length_;
  double lambda_ = 0.0;
  std::vector<double> loads_;                 // load per step
  std::vector<std::vector<double>> values_;   // [probe][step]
  std::vector<std::size_t> probe_field_;      // [probe]: a stress probe's field in stress_fields(), npos: none
};

}  // namespace ff::shell
