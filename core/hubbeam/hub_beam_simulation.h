#pragma once
/// \file hub_beam_simulation.h
/// The hub-beam system integrated by Newmark, publishing Frames and computing the metrics
/// the paper reports (hub_beam.md; docs/validation/hub-beam.md).

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "core/hubbeam/hub_beam_system.h"
#include "core/model/simulation.h"
#include "core/solve/newmark.h"

namespace ff::hubbeam {

struct HubBeamRunSettings {
  double dt = 0.05;        ///< time step [s]
  double t_end = 10.0;     ///< end time [s]
  NewmarkSettings newmark;
  /// [[timeline]] torque_scale: (time, factor on the hub torque from then on), ascending in time.
  /// The step containing a time is split there, so the change happens exactly at it.
  std::vector<std::pair<double, double>> torque_scale_changes;
};

/// Metrics from a sampled history (free functions so tests can check them on known signals).
/// Mean of y over t >= t0 (trapezoidal).
double time_mean_after(const std::vector<double>& t, const std::vector<double>& y, double t0);
/// Dominant frequency of y over t >= t0 from mean-crossings (linear interpolation) [Hz]; NaN if < 3 crossings.
double crossing_frequency(const std::vector<double>& t, const std::vector<double>& y, double t0);
/// Linear interpolation of y at time tq; NaN outside the samples.
double sample_at(const std::vector<double>& t, const std::vector<double>& y, double tq);

/// Largest |rate| on [0, h] of the cubic Hermite interpolant through (v0, a0), (v1, a1) (eq. 30).
double peak_rate(double v0, double a0, double v1, double a1, double h);

/// Builds the system (its dense matrices) when the run starts, polling the monitor it is given.
using HubBeamSystemBuilder = std::function<std::unique_ptr<HubBeamSystem>(const SetupMonitor& monitor)>;

class HubBeamSimulation final : public Simulation {
 public:
  /// The system is built by `build` in start(), not here: `check` (which never starts a run) only
  /// validates, and a run's set-up shows progress and stops on `monitor`'s stop flag.
  HubBeamSimulation(HubBeamSystemBuilder build, SetupMonitor monitor, const HubBeamParams& params,
                    const HubBeamEffects& effects, HubBeamRunSettings settings, RunInfo info);
  ~HubBeamSimulation() override;
  const RunInfo& info() const override { return info_; }
  double end_time() const override { return settings_.t_end; }
  std::string prepare() override;
  std::string start() override;
  StepStats start_stats() const override { return start_stats_; }
  double time() const override { return state_.t; }
  double nominal_step() const override { return settings_.dt; }
  double next_change(double t) const override;
  bool apply_changes(double t) override;
  std::string restart() override;
  StepDone step(double h) override;
  Frame frame() const override { return current_; }
  Metrics metrics() const override;
  std::vector<std::string> answer_metrics() const override;
  SolverTotals totals() const override { return totals_; }
  std::vector<EffectStat> effect_stats() const override { return sys_ ? sys_->effect_stats() : std::vector<EffectStat>{}; }
  /// The built system (after start()); null before.
  const HubBeamSystem* system() const { return sys_.get(); }
  /// Live: "torque.amplitude" (tau0 [N m]; the run goes on with the torque scaled to it).
  std::string change_live(const std::string& key, const LiveValue& value) override;

 private:
  void record();  // the current state as current_, and its probes into the history
  HubBeamSystemBuilder build_;
  SetupMonitor monitor_;
  HubBeamParams params_;
  std::unique_ptr<HubBeamSystem> sys_;
  HubBeamRunSettings settings_;
  RunInfo info_;
  SolverTotals totals_;
  std::unique_ptr<NewmarkIntegrator> integrator_;
  NewmarkState state_;
  StepStats start_stats_;
  std::size_t next_change_ = 0;              // first torque_scale change not yet applied
  std::optional<double> live_torque_scale_;  // a live change waiting for the next step
  Frame current_;
  std::vector<double> t_, angle_deg_, tip_v_, tip_u_, energy_, momentum_;
};

}  // namespace ff::hubbeam
