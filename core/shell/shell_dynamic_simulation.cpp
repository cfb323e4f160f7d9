#include "core/shell/shell_dynamic_simulation.h"

#include "core/frame/text.h"
#include "core/solve/static_common.h"  // fmt

#include <algorithm>
#include <chrono>
#include <cmath>

namespace ff::shell {

namespace {

// The recorded step a metric reads its non-empty history at: the last one (final; a mean ends
// there), or the first where the history is least, largest, or largest in magnitude
std::size_t read_step(DynamicMetric::Kind kind, const std::vector<double>& v) {
  switch (kind) {
    case DynamicMetric::Kind::min: return std::min_element(v.begin(), v.end()) - v.begin();
    case DynamicMetric::Kind::max: return std::max_element(v.begin(), v.end()) - v.begin();
    case DynamicMetric::Kind::max_abs:
      return std::max_element(v.begin(), v.end(), [](double a, double b) { return std::abs(a) < std::abs(b); }) -
             v.begin();
    default: return v.size() - 1;
  }
}
double chord(const MultibodyModel& m, const DynamicArc& a) {
  return (m.poses()[a.nodes.back()].p - m.poses()[a.nodes.front()].p).norm();
}
// SI units of a stress field (shell_stress.h names): resultants per unit length, the failure
// index a pure number, stresses in pascal
std::string stress_unit(const std::string& field) {
  if (field.rfind("tsai_wu", 0) == 0 || field.find("_tsai_wu") != std::string::npos) return "";
  if (field[0] == 'N' || field[0] == 'Q') return "N/m";
  if (field[0] == 'M') return "N";  // N m per m
  return "Pa";
}
double polyline(const MultibodyModel& m, const DynamicArc& a) {
  double l = 0.0;
  for (std::size_t k = 1; k < a.nodes.size(); ++k) l += (m.poses()[a.nodes[k]].p - m.poses()[a.nodes[k - 1]].p).norm();
  return l;
}
}  // namespace

ShellDynamicSimulation::ShellDynamicSimulation(MultibodySpec spec, ShellDynamicSettings settings, RunInfo info)
    : settings_(std::move(settings)), info_(std::move(info)) {
  model_ = std::make_unique<MultibodyModel>(std::move(spec));
  integrator_ = std::make_unique<GeneralizedAlpha>(*model_, settings_.integrator);
  load_switches_ = model_->load_switches();
  // drawn mesh: every shell body's quads (model-wide node ids), rigid-body nodes as points
  info_.time_unit = "s";
  info_.mesh = {};
  for (int I = 0; I < model_->node_count(); ++I) {
    const Vec3& x = model_->reference_pose(I).p;
    info_.mesh.reference_points.insert(info_.mesh.reference_points.end(), {x.x(), x.y(), x.z()});
  }
  for (std::size_t b = 0; b < model_->spec().shells.size(); ++b) {
    const int off = model_->shell_node_offset(static_cast<int>(b));
    for (const auto& q : model_->spec().shells[b].mesh.quads)
      for (int c = 0; c < 4; ++c) info_.mesh.quads.push_back(off + q[c]);
  }
  // a stress probe reads its field by number; the scene refuses a name the structure lacks
  const std::vector<StressField> stresses = stress_fields(model_->stress_layout());
  for (const DynamicProbe& p : settings_.probes) {
    std::size_t field = std::string::npos;
    for (std::size_t k = 0; k < stresses.size() && !p.field.empty(); ++k)
      if (stresses[k].name == p.field) field = k;
    probe_field_.push_back(field);
    info_.probes.push_back({p.name, p.field.empty() ? "m" : stress_unit(p.field), p.label});
  }
  for (const DynamicArc& a : settings_.arcs) {
    if (a.nodes.size() < 2) throw std::invalid_argument("arc '" + a.name + "' needs at least two nodes");
    info_.probes.push_back({"arc_rate_" + a.name, "", "relative chord change of arc " + a.name});
    info_.probes.push_back({"arc_strain_" + a.name, "", "relative length change of arc " + a.name});
    arc_chord0_.push_back(chord(*model_, a));
    arc_length0_.push_back(polyline(*model_, a));
  }
  info_.probes.push_back({"kinetic_energy", "J", "kinetic energy"});
  info_.probes.push_back({"strain_energy", "J", "strain energy"});
  info_.probes.push_back({"total_energy", "J", "kinetic + strain + gravity potential + dead-load potential energy"});
  info_.fields = {{"displacement", "m", "displacement magnitude"}, {"strain", "", "largest principal surface strain"}};
  if (settings_.record_stresses)
    for (const StressField& f : stresses) info_.fields.push_back({f.name, stress_unit(f.name), f.description});
  if (settings_.record_error_indicator) info_.fields.push_back({kErrorIndicatorField, "", kErrorIndicatorDescription});
  values_.resize(settings_.probes.size() + 2 * settings_.arcs.size());
  time_error_sum_.assign(settings_.probes.size(), 0.0);
  time_error_values_.resize(settings_.probes.size());
}

std::vector<double> ShellDynamicSimulation::probe_values() const {
  std::vector<double> v;
  v.reserve(values_.size());
  for (std::size_t k = 0; k < settings_.probes.size(); ++k) {
    const DynamicProbe& p = settings_.probes[k];
    if (p.field.empty()) v.push_back(p.direction.dot(model_->node_displacement(p.node)));
    else v.push_back(probe_field_[k] == std::string::npos ? std::numeric_limits<double>::quiet_NaN()
                                                          : model_->nodal_stress(p.node, probe_field_[k]));
  }
  for (std::size_t k = 0; k < settings_.arcs.size(); ++k) {
    v.push_back(chord(*model_, settings_.arcs[k]) / arc_chord0_[k] - 1.0);
    v.push_back(polyline(*model_, settings_.arcs[k]) / arc_length0_[k] - 1.0);
  }
  return v;
}

Frame ShellDynamicSimulation::frame() const {
  Frame f;
  f.time = integrator_->time();
  const int nn = model_->node_count();
  f.points.reserve(3 * nn);
  f.base_points.reserve(3 * nn);
  f.fields.assign(1, std::vector<double>(nn));
  f.fields.push_back(model_->nodal_surface_strain());
  if (settings_.record_stresses)
    for (std::vector<double>& values : model_->nodal_stress_fields()) f.fields.push_back(std::move(values));
  if (settings_.record_error_indicator) f.fields.push_back(model_->error_indicator().nodal);
  for (int I = 0; I < nn; ++I) {
    const Vec3& x = model_->poses()[I].p;
    const Vec3& X = model_->reference_pose(I).p;
    f.points.insert(f.points.end(), {x.x(), x.y(), x.z()});
    f.base_points.insert(f.base_points.end(), {X.x(), X.y(), X.z()});
    f.fields[0][I] = (x - X).norm();
  }
  f.probes = probe_values();
  const MotionSummary e = model_->summary(integrator_->velocity(), integrator_->time());
  f.probes.insert(f.probes.end(), {e.kinetic, e.strain, e.total()});
  return f;
}

void ShellDynamicSimulation::record() {
  times_.push_back(integrator_->time());
  const std::vector<double> v = probe_values();
  for (std::size_t k = 0; k < v.size(); ++k) values_[k].push_back(v[k]);
  for (std::size_t k = 0; k < time_error_sum_.size(); ++k) time_error_values_[k].push_back(time_error_sum_[k]);
  max_violation_ = std::max(max_violation_, model_->constraint_violation());
}

void ShellDynamicSimulation::on_publish(const Frame& f) {
  // probes end with kinetic, strain and total energy (frame())
  const std::size_t n = f.probes.size();
  max_energy_growth_ = std::max(max_energy_growth_, f.probes[n - 1] - energy0_);
  max_moving_energy_ = std::max(max_moving_energy_, f.probes[n - 3] + f.probes[n - 2]);
}

std::string ShellDynamicSimulation::start() {
  wall0_ = std::chrono::steady_clock::now();
  apply_changes(0.0);  // [[timeline]] gravity at t = 0
  if (settings_.static_start) {  // a static preload first (generalized_alpha.md (G11))
    const std::string why = integrator_->find_static_equilibrium(0.0, static_start_corrections_);
    // its Newton iteration did not converge (or went non-finite under an absurd load): diverged
    static_start_diverged_ = !why.empty();
    if (!why.empty()) return "the static equilibrium at t = 0 (solver.initial_state): " + why;
  }
  const std::string why = integrator_->initialize(0.0, Eigen::VectorXd::Zero(model_->size()));
  if (!why.empty()) return why;
  record();
  energy0_ = model_->summary(integrator_->velocity(), 0.0).total();
  return "";
}

// the next [[timeline]] gravity change or load switch (a step lands on each)
double ShellDynamicSimulation::next_change(double t) const {
  double next = std::numeric_limits<double>::infinity();
  for (std::size_t k = next_change_; k < settings_.gravity_changes.size(); ++k)
    if (settings_.gravity_changes[k].first > t) {
      next = settings_.gravity_changes[k].first;
      break;
    }
  for (std::size_t k = next_switch_; k < load_switches_.size(); ++k)
    if (load_switches_[k].time > t) return std::min(next, load_switches_[k].time);
  return next;
}

// [[timeline]] gravity changes due at (or within round-off of) the time t, a live edit, and a
// load's jump (cb_shell_dynamics.md §8: the step that ends at t already has the load of t⁺, the
// restart gives the accelerations that go with it)
bool ShellDynamicSimulation::apply_changes(double t) {
  bool changed = false;
  while (next_switch_ < load_switches_.size() && load_switches_[next_switch_].time <= t + 1e-9 * settings_.dt)
    changed = load_switches_[next_switch_++].jump || changed;
  while (next_change_ < settings_.gravity_changes.size() &&
         settings_.gravity_changes[next_change_].first <= t + 1e-9 * settings_.dt)
    model_->set_gravity(settings_.gravity_changes[next_change_++].second), changed = true;
  if (live_gravity_) {  // a live edit (change_live) made since the last step
    model_->set_gravity(*live_gravity_);
    live_gravity_.reset();
    changed = true;
  }
  return changed;
}

StepDone ShellDynamicSimulation::step(double h) {
  StepDone d;
  const double t0 = integrator_->time();
  const StepReport rep = integrator_->step(h);
  if (t0 < settings_.count_until - 1e-9 * settings_.dt)
    window_noi_ += rep.iterations, window_nou_ += rep.matrix_updates;
  totals_.newton_iterations = integrator_->total_iterations();
  totals_.jacobian_updates = integrator_->total_updates();
  simulated_ = integrator_->time();
  wall_ = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall0_).count();
  if (!rep.converged) {
    d.finished = true;
    d.status = RunStatus::diverged;
    d.reason = rep.failure;
    return d;
  }
  ++totals_.steps;
  accumulate_local_error();
  record();
  d.accepted = true;
  d.stats = rep.stats(h);
  return d;
}

std::vector<EffectStat> ShellDynamicSimulation::effect_stats() const { return model_->effect_stats(); }

std::optional<FieldErrorEstimate> ShellDynamicSimulation::field_error_estimate() const {
  if (!settings_.record_error_indicator) return std::nullopt;
  return model_->field_error_estimate();
}

std::vector<std::pair<std::string, std::array<double, 3>>> ShellDynamicSimulation::metric_points() const {
  std::vector<std::pair<std::string, std::array<double, 3>>> out;
  for (const DynamicMetric& mt : settings_.metrics)
    for (const DynamicProbe& p : settings_.probes)
      if (p.name == mt.probe && p.node >= 0) {
        const Vec3& x = model_->reference_pose(p.node).p;
        out.push_back({mt.name, {x.x(), x.y(), x.z()}});
      }
  return out;
}

// A displacement probe reads d · (x_I − X_I); the step's local error e (generalized_alpha.md (G12))
// moves node I by R_I e_trans to first order (X = X_n exp(h Δq) on SE(3), (G3)), so the probe by
// d · R_I e_trans, whose magnitude adds up over the steps (G14). Stress probes are left out: their
// reading is no linear function of the nodes' motion.
void ShellDynamicSimulation::accumulate_local_error() {
  integrator_->take_local_error(local_error_);
  for (std::size_t k = 0; k < settings_.probes.size(); ++k) {
    const DynamicProbe& p = settings_.probes[k];
    if (!p.field.empty() || p.node < 0) continue;
    Vec3 e = Vec3::Zero();
    for (int c = 0; c < 3; ++c)
      if (const int q = model_->equation(p.node, c); q >= 0) e[c] = local_error_[q];
    time_error_sum_[k] += std::abs(p.direction.dot(model_->poses()[p.node].R * e));
  }
}

std::vector<std::pair<std::string, double>> ShellDynamicSimulation::local_time_errors() const {
  std::vector<std::pair<std::string, double>> out;
  for (const DynamicMetric& mt : settings_.metrics) {
    const int k = history_index(mt.probe);  // a displacement probe: (G14) follows those only
    if (k < 0 || k >= static_cast<int>(settings_.probes.size()) || !settings_.probes[k].field.empty() ||
        settings_.probes[k].node < 0)
      continue;
    const std::vector<double>& v = values_[k];
    const std::vector<double>& e = time_error_values_[k];
    if (v.empty() || e.size() != v.size()) continue;
    // the sum up to the step the metric was read at (G15); a mean reads every step: their mean
    double x = e[read_step(mt.kind, v)];
    if (mt.kind == DynamicMetric::Kind::mean) {
      x = 0;
      for (double y : e) x += y;
      x /= static_cast<double>(e.size());
    }
    out.emplace_back(mt.name, x);
  }
  return out;
}

std::vector<std::string> ShellDynamicSimulation::answer_metrics() const {
  std::vector<std::string> out;  // the [[metric]]s read probes; the rest count the solver's work
  for (const DynamicMetric& mt : settings_.metrics) out.push_back(mt.name);
  return out;
}

// Each arc's largest changes over the run: measured on the main job (docs/validation/error-bars.md,
// "The main job's mesh bars and its arcs"), neither a coarser twin nor the integrator's local error
// bounds the largest length change (a difference of nearly equal lengths read at one of many
// vibration peaks: 1/8 to 130 times its error); the chord-rate maxima stay beside them unbarred.
std::vector<std::pair<std::string, std::string>> ShellDynamicSimulation::answers_without_bar() const {
  std::vector<std::pair<std::string, std::string>> out;
  const std::string why = "the largest change of an arc over its vibrations has no error estimate yet "
                          "(docs/validation/error-bars.md)";
  for (const DynamicArc& a : settings_.arcs) {
    out.emplace_back("arc_rate_max_" + a.name, why);
    out.emplace_back("arc_strain_max_" + a.name, why);
  }
  return out;
}

// a probe's or arc's row in values_ by its name in RunInfo; -1 when there is none
int ShellDynamicSimulation::history_index(const std::string& name) const {
  for (std::size_t k = 0; k < settings_.probes.size(); ++k)
    if (settings_.probes[k].name == name) return static_cast<int>(k);
  for (std::size_t k = 0; k < settings_.arcs.size(); ++k) {
    if ("arc_rate_" + settings_.arcs[k].name == name) return static_cast<int>(settings_.probes.size() + 2 * k);
    if ("arc_strain_" + settings_.arcs[k].name == name) return static_cast<int>(settings_.probes.size() + 2 * k + 1);
  }
  return -1;
}

Metrics ShellDynamicSimulation::metrics() const {
  Metrics m;
  for (const DynamicMetric& mt : settings_.metrics) {
    const int k = history_index(mt.probe);
    if (k < 0 || values_[k].empty()) continue;
    const std::vector<double>& v = values_[k];
    double x = v[read_step(mt.kind, v)];
    if (mt.kind == DynamicMetric::Kind::max_abs) x = std::abs(x);
    if (mt.kind == DynamicMetric::Kind::mean && v.size() == times_.size() && times_.size() > 1 &&
        times_.back() > times_.front()) {
      double area = 0;
      for (std::size_t i = 1; i < v.size(); ++i) area += 0.5 * (v[i] + v[i - 1]) * (times_[i] - times_[i - 1]);
      x = area / (times_.back() - times_.front());
    }
    m.emplace_back(mt.name, x);
  }
  for (std::size_t k = 0; k < settings_.arcs.size(); ++k) {  // largest |relative change| of each arc
    double rate = 0, strain = 0;
    for (double y : values_[settings_.probes.size() + 2 * k]) rate = std::max(rate, std::abs(y));
    for (double y : values_[settings_.probes.size() + 2 * k + 1]) strain = std::max(strain, std::abs(y));
    m.emplace_back("arc_rate_max_" + settings_.arcs[k].name, rate);
    m.emplace_back("arc_strain_max_" + settings_.arcs[k].name, strain);
  }
  if (settings_.static_start)  // Newton corrections of the static preload, apart from the steps' NOI
    m.emplace_back("static_start_corrections", static_cast<double>(static_start_corrections_));
  m.emplace_back("NOI", static_cast<double>(integrator_->total_iterations()));
  m.emplace_back("NOU", static_cast<double>(integrator_->total_updates()));
  if (std::isfinite(settings_.count_until)) {
    m.emplace_back("NOI_window", static_cast<double>(window_noi_));
    m.emplace_back("NOU_window", static_cast<double>(window_nou_));
  }
  m.emplace_back("fallback_steps", static_cast<double>(integrator_->total_fallbacks()));
  if (simulated_ > 0) m.emplace_back("wall_per_sim_second", wall_ / simulated_);
  m.emplace_back("constraint_violation_max", max_violation_);
  // relative to the largest kinetic + strain energy of the run, which does not depend on where the
  // gravity potential is zero (the total energy does: a plate released at z = 0 starts at 0 J)
  if (load_changed_at() < 0)
    m.emplace_back("energy_growth_max_rel", max_energy_growth_ / std::max(max_moving_energy_, 1e-300));
  return m;
}

// the first time after the start at which a load's history jumps or bends, or -1: from then on
// the loads do work and the total energy is not conserved, so its growth measures nothing
double ShellDynamicSimulation::load_changed_at() const {
  for (const LoadSwitch& s : load_switches_)
    if (s.time > 0.0) return s.time;
  return -1.0;
}

std::vector<std::pair<std::string, std::string>> ShellDynamicSimulation::metrics_unreached() const {
  std::vector<std::pair<std::string, std::string>> out;
  if (const double t = load_changed_at(); t >= 0)
    out.emplace_back("energy_growth_max_rel", "a load changed during the run (first at t = " + significant(t) +
                                                  " s): it did work on the structure, so the total energy is "
                                                  "not conserved and its growth measures nothing");
  return out;
}

std::string ShellDynamicSimulation::change_live(const std::string& key, const LiveValue& value) {
  if (key != "gravity.g") return "'" + key + "' cannot change while the model runs (live: gravity.g)";
  if (!model_->spec().gravity) return "gravity.g changes live only when the scene has the gravity effect";
  // the scene schema has checked the value (three finite numbers); this only guards the type
  const auto* g = std::get_if<std::vector<double>>(&value);
  if (!g || g->size() != 3) return "gravity.g takes a list of 3 numbers";
  live_gravity_ = Vec3((*g)[0], (*g)[1], (*g)[2]);
  return "";
}

}  // namespace ff::shell
