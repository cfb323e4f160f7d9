#pragma once
/// \file shell_dynamic_simulation.h
/// Dynamics of a multibody system of CB shells, rigid bodies and joints with the Lie-group
/// generalized-α (core/solve/generalized_alpha.md): one Frame every `output_every` steps,
/// displacement and arc probes, energy, and the counters NOI/NOU of the shell paper (Zhang, Liu,
/// Zhang & Liu 2022, Tables 3-4).

#include <limits>
#include <chrono>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/model/simulation.h"
#include "core/shell/multibody_model.h"
#include "core/solve/generalized_alpha.h"

namespace ff::shell {

/// direction . u(node): a displacement component of one node (model-wide id); with a `field`
/// (a name of stress_fields, shell_stress.h) the nodal value of that stress field instead.
struct DynamicProbe {
  std::string name, label;
  int node = -1;
  Vec3 direction = Vec3::UnitZ();
  std::string field;  ///< "" : a displacement probe
};

/// A curve through ordered nodes (e.g. arc AC): its relative change of chord |x_last − x_first|
/// (the "deformation rate" of the shell paper's example 5.6) and of polyline length (membrane strain).
struct DynamicArc {
  std::string name;
  std::vector<int> nodes;
};

struct DynamicMetric {
  /// mean: the time average over the run (trapezoid rule over the recorded steps)
  enum class Kind { min, max, max_abs, final_value, mean };
  std::string name;
  Kind kind = Kind::final_value;
  std::string probe;
};

struct ShellDynamicSettings {
  GeneralizedAlphaSettings integrator;
  /// start from the static equilibrium under the loads and gravity at t = 0 (generalized_alpha.md
  /// (G11)), not from the undeformed reference
  bool static_start = false;
  double dt = 1e-3;
  double end_time = 1.0;
  int output_every = 1;  ///< publish every n-th step (and the last)
  double count_until = std::numeric_limits<double>::infinity();  ///< NOI/NOU window (the shell paper: first 1 s)
  std::vector<DynamicProbe> probes;
  std::vector<DynamicArc> arcs;
  std::vector<DynamicMetric> metrics;
  /// every stress field (shell_stress.h) of the shells in every published frame, after
  /// displacement and strain (a scene's output.stresses, or a stress field it colours or probes)
  bool record_stresses = false;
  /// the recovered-stress error indicator field in every frame and its summary at the end
  /// (error_indicator.h; the scene's output.error_bar)
  bool record_error_indicator = false;
  /// [[timeline]] gravity: (time, g from then on), ascending in time. The step containing a time
  /// is split there, so the change happens exactly at it.
  std::vector<std::pair<double, Vec3>> gravity_changes;
};

class ShellDynamicSimulation final : public Simulation {
 public:
  ShellDynamicSimulation(MultibodySpec spec, ShellDynamicSettings settings, RunInfo info);
  const RunInfo& info() const override { return info_; }
  double end_time() const override { return settings_.end_time; }
  std::string start() override;
  RunStatus start_failure_status() const override {
    return static_start_diverged_ ? RunStatus::diverged : RunStatus::failed;
  }
  double time() const override { return integrator_->time(); }
  double nominal_step() const override { return settings_.dt; }
  double next_change(double t) const override;
  bool apply_changes(double t) override;
  std::string restart() override { return integrator_->restart(); }
  StepDone step(double h) override;
  Frame frame() const override;
  int output_every() const override { return settings_.output_every; }
  bool logs_skipped_steps() const override { return true; }
  void on_publish(const Frame& frame) override;
  Metrics metrics() const override;
  std::vector<std::string> answer_metrics() const override;
  std::optional<FieldErrorEstimate> field_error_estimate() const override;
  std::vector<std::pair<std::string, std::array<double, 3>>> metric_points() const override;
  std::vector<std::pair<std::string, double>> local_time_errors() const override;
  std::vector<std::pair<std::string, std::string>> answers_without_bar() const override;
  std::vector<std::pair<std::string, std::string>> metrics_unreached() const override;
  SolverTotals totals() const override { return totals_; }
  std::vector<EffectStat> effect_stats() const override;
  void set_element_threads(int count, const std::atomic<bool>* busy) override {
    model_->set_threads({count, busy});
  }
  /// Live: "gravity.g" (a list [gx, gy, gz] in m/s²; needs the gravity effect).
  std::string change_live(const std::string& key, const LiveValue& value) override;
  const MultibodyModel& model() const { return *model_; }
  /// Largest |Φ| seen after a converged step (constraint violation), in length units.
  double max_constraint_violation() const { return max_violation_; }

 private:
  void record();                             // probes of the current state into the history
  void accumulate_local_error();             // the step's local error into each displacement probe's sum (G14)
  std::vector<double> probe_values() const;  // probes in RunInfo order
  int history_index(const std::string& name) const;  // a probe's or arc's row in values_, -1: none
  std::unique_ptr<MultibodyModel> model_;
  std::optional<Vec3> live_gravity_;  // a live change waiting for the next step
  std::size_t next_change_ = 0;       // first gravity change not yet applied
  std::vector<LoadSwitch> load_switches_;  // where a load's history jumps or bends (a step lands on each)
  std::size_t next_switch_ = 0;            // first of them not yet passed
  std::unique_ptr<GeneralizedAlpha> integrator_;
  ShellDynamicSettings settings_;
  RunInfo info_;
  int static_start_corrections_ = 0;
  bool static_start_diverged_ = false;
  double load_changed_at() const;
  SolverTotals totals_;
  std::vector<double> arc_chord0_, arc_length0_;
  std::vector<double> times_;
  std::vector<std::vector<double>> values_;  // [probe][recorded step]
  // a displacement probe's accumulated local time-step error |d · R e| (generalized_alpha.md (G14)):
  // the running sum per probe, its value at every recorded step, and the step's error vector
  std::vector<double> time_error_sum_;
  std::vector<std::vector<double>> time_error_values_;  // [probe][recorded step]
  Eigen::VectorXd local_error_;
  std::vector<std::size_t> probe_field_;     // [probe]: a stress probe's field in stress_fields(), npos: none
  long long window_noi_ = 0, window_nou_ = 0;
  std::chrono::steady_clock::time_point wall0_;
  double wall_ = 0.0, simulated_ = 0.0, energy0_ = 0.0, max_energy_growth_ = 0.0, max_violation_ = 0.0;
  double max_moving_energy_ = 0.0;  // largest kinetic + strain energy published: energy_growth_max_rel's scale
};

}  // namespace ff::shell
