#include "core/hubbeam/hub_beam_simulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>
#include <stdexcept>

namespace ff::hubbeam {

double time_mean_after(const std::vector<double>& t, const std::vector<double>& y, double t0) {
  double area = 0.0, span = 0.0;
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (t[i - 1] < t0 - 1e-12) continue;
    const double h = t[i] - t[i - 1];
    area += 0.5 * h * (y[i] + y[i - 1]);
    span += h;
  }
  return span > 0 ? area / span : std::numeric_limits<double>::quiet_NaN();
}

double crossing_frequency(const std::vector<double>& t, const std::vector<double>& y, double t0) {
  const double mean = time_mean_after(t, y, t0);
  std::vector<double> crossings;
  for (std::size_t i = 1; i < t.size(); ++i) {
    if (t[i - 1] < t0 - 1e-12) continue;
    const double a = y[i - 1] - mean, b = y[i] - mean;
    if ((a < 0 && b >= 0) || (a > 0 && b <= 0)) crossings.push_back(t[i - 1] + (t[i] - t[i - 1]) * a / (a - b));
  }
  if (crossings.size() < 3) return std::numeric_limits<double>::quiet_NaN();
  // consecutive crossings are half a period apart
  return 0.5 * (crossings.size() - 1) / (crossings.back() - crossings.front());
}

double sample_at(const std::vector<double>& t, const std::vector<double>& y, double tq) {
  for (std::size_t i = 1; i < t.size(); ++i)
    if (t[i - 1] <= tq + 1e-12 && tq <= t[i] + 1e-12) {
      const double h = t[i] - t[i - 1];
      return h > 0 ? y[i - 1] + (y[i] - y[i - 1]) * (tq - t[i - 1]) / h : y[i];
    }
  return std::numeric_limits<double>::quiet_NaN();
}

double peak_rate(double v0, double a0, double v1, double a1, double h) {
  double peak = std::max(std::abs(v0), std::abs(v1));
  for (int k = 1; k < 32; ++k) {
    const double s = k / 32.0, s2 = s * s, s3 = s2 * s;
    const double v = (2 * s3 - 3 * s2 + 1) * v0 + (s3 - 2 * s2 + s) * h * a0 + (-2 * s3 + 3 * s2) * v1 +
                     (s3 - s2) * h * a1;
    peak = std::max(peak, std::abs(v));
  }
  return peak;
}

HubBeamSimulation::HubBeamSimulation(HubBeamSystemBuilder build, SetupMonitor monitor, const HubBeamParams& params,
                                     const HubBeamEffects& effects, HubBeamRunSettings settings, RunInfo info)
    : build_(std::move(build)), monitor_(std::move(monitor)), params_(params), settings_(settings), info_(std::move(info)) {
  info_.mesh = hub_beam_drawing(params.hub_radius, params.length);
  info_.probes = hub_beam_probes();
  info_.fields = hub_beam_fields();
  info_.effects = effects.names();
  info_.time_unit = "s";
}

HubBeamSimulation::~HubBeamSimulation() = default;

void HubBeamSimulation::record() {
  current_ = Frame{};
  sys_->fill_frame(state_.x, state_.v, state_.t, current_);
  t_.push_back(state_.t);
  angle_deg_.push_back(current_.probes[0]);
  tip_v_.push_back(current_.probes[2]);
  tip_u_.push_back(current_.probes[3]);
  energy_.push_back(current_.probes[5]);
  momentum_.push_back(current_.probes[6]);
}

std::string HubBeamSimulation::prepare() {
  if (sys_) return "";
  try {
    sys_ = build_(monitor_);
  } catch (const SetupInterrupted& e) {
    return e.what();
  } catch (const std::invalid_argument& e) {  // e.g. an EFG moment matrix singular at a quadrature point
    return std::string("model set-up: ") + e.what();
  }
  return "";
}

std::string HubBeamSimulation::start() {
  if (std::string why = prepare(); !why.empty()) return why;
  integrator_ = std::make_unique<NewmarkIntegrator>(*sys_, settings_.newmark);
  const int n = sys_->size();
  state_.x = Eigen::VectorXd::Zero(n);
  state_.v = Eigen::VectorXd::Zero(n);
  state_.a = Eigen::VectorXd::Zero(n);
  apply_changes(0.0);  // [[timeline]] changes at t = 0 set the starting torque
  const StepReport init = integrator_->initialize(state_);
  if (!init.converged) return init.failure;
  start_stats_ = init.stats(0.0);
  record();
  return "";
}

double HubBeamSimulation::next_change(double t) const {
  for (std::size_t k = next_change_; k < settings_.torque_scale_changes.size(); ++k)
    if (settings_.torque_scale_changes[k].first > t) return settings_.torque_scale_changes[k].first;
  return std::numeric_limits<double>::infinity();
}

// [[timeline]] torque_scale changes due at (or within round-off of) the time t, and a live edit
bool HubBeamSimulation::apply_changes(double t) {
  if (!sys_) return false;  // start() applies the changes at t = 0 once the system is built
  const auto& changes = settings_.torque_scale_changes;
  bool changed = false;
  while (next_change_ < changes.size() && changes[next_change_].first <= t + 1e-9 * settings_.dt)
    sys_->set_torque_scale(changes[next_change_++].second), changed = true;
  if (live_torque_scale_) {  // a live edit (change_live) made since the last step
    sys_->set_torque_scale(*live_torque_scale_);
    live_torque_scale_.reset();
    changed = true;
  }
  return changed;
}

// the torque jumps: accelerations that balance the new torque, so the step after the change
// carries none of the old one (Newmark's update mixes the accelerations at both ends of a step)
std::string HubBeamSimulation::restart() {
  const StepReport re = integrator_->initialize(state_);
  return re.converged ? "" : re.failure;
}

StepDone HubBeamSimulation::step(double h) {
  StepDone d;
  const double t_before = state_.t, prev_v = state_.v[0], prev_a = state_.a[0];
  const StepReport rep = integrator_->step(state_, h);
  totals_.newton_iterations += rep.iterations;
  totals_.jacobian_updates += rep.matrix_updates;
  if (!rep.converged) {
    std::ostringstream msg;
    msg << "diverged in the step from t = " << t_before << " s to " << t_before + h << " s: " << rep.failure;
    d.finished = true;
    d.status = RunStatus::diverged;
    d.reason = msg.str();
    return d;
  }
  ++totals_.steps;
  record();
  d.accepted = true;
  d.stats = rep.stats(h);
  // eq. (30): the hub rate along the step's cubic Hermite interpolant, against the critical speed
  const double peak = peak_rate(prev_v, prev_a, state_.v[0], state_.a[0], h);
  if (peak > sys_->critical_speed()) {
    std::ostringstream msg;
    msg << "diverged in the step from t = " << t_before << " s to " << state_.t << " s: the hub rate reached " << peak
        << " rad/s, above this model's critical speed " << sys_->critical_speed()
        << " rad/s where the effective bending stiffness K2 + w^2 (D1 - M2) loses definiteness "
           "(zero-order model without dynamic stiffening); its response grows without bound";
    d.finished = true;
    d.status = RunStatus::diverged;
    d.reason = msg.str();
  }
  return d;
}

std::vector<std::string> HubBeamSimulation::answer_metrics() const {
  // the motion's numbers; the drifts measure the integrator and the inertia is an input
  return {"hub_angle_mean_after_T_deg", "tip_frequency_hz", "tip_transverse_at_2s_m", "tip_axial_max_m",
          "tip_transverse_max_m",       "modal_frequency_hz"};
}

Metrics HubBeamSimulation::metrics() const {
  Metrics m;
  if (!sys_) return m;  // set-up did not finish: nothing was computed
  const double T = params_.torque_period;
  auto add = [&](const char* name, double v) {
    if (std::isfinite(v)) m.emplace_back(name, v);
  };
  add("hub_angle_mean_after_T_deg", time_mean_after(t_, angle_deg_, T));
  add("tip_frequency_hz", crossing_frequency(t_, tip_v_, T));
  add("tip_transverse_at_2s_m", sample_at(t_, tip_v_, 2.0));
  double umax = 0.0, vmax = 0.0;
  for (double u : tip_u_) umax = std::max(umax, std::abs(u));
  for (double v : tip_v_) vmax = std::max(vmax, std::abs(v));
  if (!tip_u_.empty()) add("tip_axial_max_m", umax);
  if (!tip_v_.empty()) add("tip_transverse_max_m", vmax);
  // drifts over the torque-free part, where energy and angular momentum are conserved (eq. 14):
  // (max - min) after T, relative to the mean energy after T and to the peak |momentum| of the run
  // (the torque of the hub-beam paper, Xie & Jian 2017, has zero impulse, so the momentum after T
  // is ~0 and cannot be the scale)
  auto spread_after_T = [&](const std::vector<double>& y) {
    double lo = 1e300, hi = -1e300;
    for (std::size_t i = 0; i < t_.size(); ++i)
      if (t_[i] >= T - 1e-12) lo = std::min(lo, y[i]), hi = std::max(hi, y[i]);
    return hi >= lo ? hi - lo : std::numeric_limits<double>::quiet_NaN();
  };
  double p_peak = 0.0;
  for (double p : momentum_) p_peak = std::max(p_peak, std::abs(p));
  const double e_mean = time_mean_after(t_, energy_, T);
  add("energy_drift_rel", std::abs(e_mean) > 0 ? spread_after_T(energy_) / std::abs(e_mean) : NAN);
  add("angular_momentum_drift_rel", p_peak > 0 ? spread_after_T(momentum_) / p_peak : NAN);
  const ModalResult modal = sys_->modal_analysis();
  if (modal.frequencies_hz.size() > 1) add("modal_frequency_hz", modal.frequencies_hz[1]);
  add("beam_inertia_kg_m2", sys_->matrices().jb);
  return m;
}

std::string HubBeamSimulation::change_live(const std::string& key, const LiveValue& value) {
  if (key != "torque.amplitude") return "'" + key + "' cannot change while the model runs (live: torque.amplitude)";
  // the scene schema has checked the value (a finite number >= 0); this only guards the type
  const double* tau0 = std::get_if<double>(&value);
  if (!tau0) return "torque.amplitude takes a number";
  const double base = params_.torque_amplitude;
  if (base == 0.0) return "the scene's torque amplitude is 0, so it cannot be scaled live";
  live_torque_scale_ = *tau0 / base;
  return "";
}

}  // namespace ff::hubbeam
