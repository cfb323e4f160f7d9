#include "core/shell/shell_static_simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/frame/text.h"
#include "core/solve/sparse_solver.h"
#include "core/solve/static_common.h"

namespace ff::shell {

ShellStaticSimulation::ShellStaticSimulation(ShellModelSpec spec, ShellStaticSettings settings, RunInfo info)
    : settings_(std::move(settings)), info_(std::move(info)) {
  model_ = std::make_unique<ShellModel>(std::move(spec));
  const mesh::ShellMesh& m = model_->spec().mesh;
  if (model_->snapped_directors() > 0)  // directors moved into symmetry planes they nearly contained
    info_.settings.emplace_back("symmetry_directors_moved",
                                std::to_string(model_->snapped_directors()) + " nodes, largest by " +
                                    std::to_string(model_->largest_director_snap() * 180.0 / std::acos(-1.0)) + " deg");
  info_.time_unit = "";
  info_.mesh.reference_points.clear();
  for (const Vec3& p : m.points) info_.mesh.reference_points.insert(info_.mesh.reference_points.end(), {p.x(), p.y(), p.z()});
  for (const auto& q : m.quads) info_.mesh.quads.insert(info_.mesh.quads.end(), q.begin(), q.end());
  info_.probes = {{"lambda", "", "load factor"}, {"load", settings_.load_unit, settings_.load_label}};
  for (const ShellProbe& p : settings_.probes) info_.probes.push_back({p.name, "", p.label});
  info_.fields = {{"displacement", "", "displacement magnitude"}, {"strain", "", "largest principal surface strain"}};
  const std::vector<StressField> stresses = stress_fields(model_->stress_layout());
  if (settings_.record_stresses)
    for (const StressField& f : stresses) info_.fields.push_back({f.name, "", f.description});
  if (settings_.record_error_indicator) info_.fields.push_back({kErrorIndicatorField, "", kErrorIndicatorDescription});
  // a stress probe reads its field by number; the scene refuses a name the structure lacks
  for (const ShellProbe& p : settings_.probes) {
    std::size_t field = std::string::npos;
    for (std::size_t k = 0; k < stresses.size() && p.quantity == ShellProbe::Quantity::stress; ++k)
      if (stresses[k].name == p.field) field = k;
    probe_field_.push_back(field);
  }
  info_.plot_x_probe = "load";
  values_.resize(settings_.probes.size());
}

double ShellStaticSimulation::end_time() const {
  return settings_.arc_length && !settings_.linear ? settings_.arc.lambda_max : settings_.load_control.lambda_end;
}

std::string ShellStaticSimulation::end_description() const {
  const double end = end_time();
  if (settings_.linear)
    return "linear analysis at load factor λ = " + significant(end) + " (solver.end; " + settings_.load_label + " = λ × " +
           significant(settings_.load_scale) + (settings_.load_unit.empty() ? "" : " " + settings_.load_unit) + ")";
  std::string s = "load factor λ from 0 to " + significant(end) + " (solver.end; " + settings_.load_label + " = λ × " +
                  significant(settings_.load_scale) + (settings_.load_unit.empty() ? "" : " " + settings_.load_unit) + ")";
  if (settings_.arc_length) {
    if (std::isfinite(settings_.arc.lambda_min))
      s += ", path kept within λ ≥ " + significant(settings_.arc.lambda_min) + " (solver.min_load_factor)";
    if (settings_.arc.stop_at_first_limit_point) s += ", or until its first limit point";
  }
  return s;
}

double ShellStaticSimulation::probe_value(std::size_t k) const {
  const ShellProbe& p = settings_.probes[k];
  if (p.quantity == ShellProbe::Quantity::displacement) return p.direction.dot(model_->node_displacement(p.node));
  if (p.quantity == ShellProbe::Quantity::stress)
    return probe_field_[k] == std::string::npos ? std::numeric_limits<double>::quiet_NaN()
                                                : model_->nodal_stress(p.node, probe_field_[k]);
  Vec3 total = Vec3::Zero();
  for (int I : p.nodes) total += model_->node_reaction(I);
  return p.direction.dot(total);
}

ShellStaticSimulation::~ShellStaticSimulation() = default;

Frame ShellStaticSimulation::frame() const {
  Frame f;
  f.time = lambda_;
  f.load_factor = lambda_;
  const auto& poses = model_->poses();
  const auto& ref = model_->spec().mesh.points;
  f.points.reserve(3 * poses.size());
  f.fields.assign(1, std::vector<double>(poses.size()));
  f.fields.push_back(model_->nodal_surface_strain());
  if (settings_.record_stresses)
    for (std::vector<double>& values : model_->nodal_stress_fields()) f.fields.push_back(std::move(values));
  if (settings_.record_error_indicator) f.fields.push_back(model_->error_indicator().nodal);
  for (std::size_t i = 0; i < poses.size(); ++i) {
    f.points.insert(f.points.end(), {poses[i].p.x(), poses[i].p.y(), poses[i].p.z()});
    f.base_points.insert(f.base_points.end(), {ref[i].x(), ref[i].y(), ref[i].z()});
    f.fields[0][i] = (poses[i].p - ref[i]).norm();
  }
  f.probes = {lambda_, lambda_ * settings_.load_scale};
  for (std::size_t k = 0; k < settings_.probes.size(); ++k) f.probes.push_back(probe_value(k));
  return f;
}

void ShellStaticSimulation::record() {
  loads_.push_back(lambda_ * settings_.load_scale);
  for (std::size_t k = 0; k < settings_.probes.size(); ++k) values_[k].push_back(probe_value(k));
}

// [[metric]] kind = "linear_buckling_load": one linear buckling analysis of this structure under
// this scene's loads about the reference state (the first multiplier, shell_eigen.md), computed
// once, when the run first starts (a scene being read or checked solves nothing); its value is the
// critical load in the scene's load units, beside the path's limit load. The structure is the one
// the path starts from (imperfections included).
void ShellStaticSimulation::predict_linear_buckling() {
  if (buckling_predicted_ || !settings_.linear_buckling) return;
  buckling_predicted_ = true;
  double value = std::numeric_limits<double>::quiet_NaN();
  std::string why;
  settings_.linear_buckling(value, why);
  if (why.empty() && !std::isfinite(value)) why = "the linear buckling analysis found no positive multiplier";
  for (ShellMetric& m : settings_.metrics)
    if (m.kind == ShellMetric::Kind::linear_buckling_load) {
      m.computed = value;
      m.computed_why = why.empty() ? "" : "linear buckling about the reference state: " + why;
    }
}

std::string ShellStaticSimulation::start() {
  predict_linear_buckling();
  lambda_ = 0.0;
  record();
  if (settings_.linear) return "";
  if (settings_.arc_length) {
    for (std::size_t k = 0; k < settings_.probes.size(); ++k)
      if (settings_.probes[k].name == settings_.monitor_probe) {
        settings_.arc.monitor = [this, k] { return probe_value(k); };
        settings_.arc.displacement_limit = settings_.displacement_limit;
      }
    arc_length_ = std::make_unique<ArcLengthPath>(*model_, settings_.arc);
    arc_length_->start();  // a run that ends at once reports it at the first step
  } else {
    load_control_ = std::make_unique<LoadControlPath>(*model_, settings_.load_control);
  }
  return "";
}

StepDone ShellStaticSimulation::linear_step() {
  // shell_model.md (L1): r(q0) + K(q0) du = lambda f_ref, one factorization at the reference state
  StepDone d;
  d.finished = true;
  const double lambda = settings_.load_control.lambda_end;
  Eigen::VectorXd r, f_ref, du;
  SparseMatrixD K;
  SparseLinearSolver solver(settings_.load_control.convergence.linear_backend);
  const TangentInParts parts(*model_, solver);  // over ranks each rank assembles and hands over its part
  model_->evaluate(0.0, r, &K, &f_ref);
  LinearStatus status = solver.factorize(K);
  if (status) status = solver.solve(lambda * f_ref - r, du);
  if (!status) {
    d.status = RunStatus::diverged;
    d.reason = "the linear analysis could not solve K du = f at the reference state: " + status.message +
               (status.code == LinearStatus::Code::singular
                    ? " (a mechanism: some part of the structure is not held against rigid motion)"
                    : "");
    return d;
  }
  model_->update(du);
  model_->apply_prescribed(lambda);
  lambda_ = lambda;
  model_->evaluate(lambda_, r, nullptr, nullptr);  // the reactions of the displaced state (L2)
  totals_.steps = 1;
  totals_.newton_iterations = 1;
  totals_.jacobian_updates = 1;
  totals_.cutbacks = 0;  // one solve: nothing to cut back
  record();
  d.accepted = true;
  d.stats = {lambda, 1, 1, 0.0, du.norm(), true};
  d.status = RunStatus::completed;
  return d;
}

StepDone ShellStaticSimulation::step(double) {
  if (settings_.linear) return linear_step();
  StepDone d;
  const bool accepted = arc_length_ ? !arc_length_->finished() && arc_length_->advance() : load_control_->advance();
  const StaticResult& r = arc_length_ ? arc_length_->result() : load_control_->result();
  totals_.newton_iterations = r.iterations;
  totals_.cutbacks = r.cutbacks;
  // every attempt is in the record (static_solvers.md §4.5): the rejected ones as rows that did not converge
  for (const StaticAttempt& a : arc_length_ ? arc_length_->rejected() : load_control_->rejected())
    d.rejected.push_back(
        {a.step, a.lambda, {a.dlambda, a.iterations, a.factorizations, a.residual_norm, a.increment_norm, false}});
  if (accepted) {
    const StaticStepInfo& st = arc_length_ ? arc_length_->last_step() : load_control_->last_step();
    lambda_ = st.lambda;
    ++totals_.steps;
    record();
    d.accepted = true;
    d.stats = {st.dlambda, st.iterations, st.factorizations, st.residual_norm, st.increment_norm, true};
  }
  if (arc_length_ ? arc_length_->finished() : load_control_->finished()) {
    totals_.jacobian_updates = r.factorizations;
    d.finished = true;
    d.status = r.status == StaticStatus::completed     ? RunStatus::completed
               : r.status == StaticStatus::incomplete  ? RunStatus::incomplete
               : r.status == StaticStatus::interrupted ? RunStatus::interrupted
                                                       : RunStatus::diverged;
    // a completed path that returned to the unloaded state or looped says so (r.notes), and one
    // that stopped at its first limit point, as asked, says where
    d.reason = r.status == StaticStatus::completed && r.stop != StaticStop::limit_point ? r.notes : r.reason;
    for (const StaticEvent& e : r.events) d.events.push_back({std::string(to_string(e.kind)), e.step, e.lambda, e.detail});
  }
  return d;
}

namespace {
// the limit point between path samples i-1, i, i+1: parabola through the loads over the path
// parameter t = -1, 0, 1, its vertex t*, and y read from the parabola through y at the same t*
double vertex(const std::vector<double>& load, int i, const std::vector<double>& y) {
  const double a = 0.5 * (load[i - 1] + load[i + 1]) - load[i], b = 0.5 * (load[i + 1] - load[i - 1]);
  const double t = a < 0 ? std::clamp(-b / (2 * a), -1.0, 1.0) : 0.0;
  const double ay = 0.5 * (y[i - 1] + y[i + 1]) - y[i], by = 0.5 * (y[i + 1] - y[i - 1]);
  return y[i] + by * t + ay * t * t;
}
}  // namespace

std::optional<FieldErrorEstimate> ShellStaticSimulation::field_error_estimate() const {
  if (!settings_.record_error_indicator) return std::nullopt;
  return model_->field_error_estimate();
}

std::vector<std::pair<std::string, std::array<double, 3>>> ShellStaticSimulation::metric_points() const {
  std::vector<std::pair<std::string, std::array<double, 3>>> out;
  for (const ShellMetric& mt : settings_.metrics)
    for (const ShellProbe& p : settings_.probes)
      if (p.name == mt.probe && p.quantity != ShellProbe::Quantity::reaction && p.node >= 0) {
        const Vec3& x = model_->spec().mesh.points[p.node];
        out.push_back({mt.name, {x.x(), x.y(), x.z()}});
      }
  return out;
}

std::vector<std::string> ShellStaticSimulation::answer_metrics() const {
  std::vector<std::string> out;  // every [[metric]] reads the path of the discretized structure
  for (const ShellMetric& mt : settings_.metrics) out.push_back(mt.name);
  return out;
}

Metrics ShellStaticSimulation::metrics() const {
  Metrics m;
  for (const auto& [name, value, why] : evaluate_metrics())
    if (std::isfinite(value)) m.emplace_back(name, value);
  return m;
}

std::vector<std::pair<std::string, std::string>> ShellStaticSimulation::metrics_unreached() const {
  std::vector<std::pair<std::string, std::string>> out;
  for (const auto& [name, value, why] : evaluate_metrics())
    if (!std::isfinite(value)) out.emplace_back(name, why);
  return out;
}

std::vector<std::tuple<std::string, double, std::string>> ShellStaticSimulation::evaluate_metrics() const {
  std::vector<std::tuple<std::string, double, std::string>> m;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // first local maximum of the load along the path
  int limit = -1;
  for (std::size_t i = 1; i + 1 < loads_.size(); ++i)
    if (loads_[i] > loads_[i - 1] && loads_[i] >= loads_[i + 1]) {
      limit = static_cast<int>(i);
      break;
    }
  auto probe_index = [&](const std::string& name) {
    for (std::size_t k = 0; k < settings_.probes.size(); ++k)
      if (settings_.probes[k].name == name) return static_cast<int>(k);
    return -1;
  };
  for (const ShellMetric& mt : settings_.metrics) {
    const int k = probe_index(mt.probe);
    double v = nan;
    switch (mt.kind) {
      case ShellMetric::Kind::at_load:
        // first crossing of the requested load along the path, linear in between
        // first crossing of the requested load along the path; quadratic through a third sample on
        // the same monotone stretch of the load (long arc-length steps), else linear
        for (std::size_t i = 1; k >= 0 && i < loads_.size(); ++i)
          if ((loads_[i - 1] - mt.load) * (loads_[i] - mt.load) <= 0 && loads_[i] != loads_[i - 1]) {
            const double t = (mt.load - loads_[i - 1]) / (loads_[i] - loads_[i - 1]);
            v = values_[k][i - 1] + t * (values_[k][i] - values_[k][i - 1]);
            const double dir = loads_[i] - loads_[i - 1];
            for (const std::size_t j : {i + 1, i - 2}) {
              if (j >= loads_.size() || (j == i - 2 && i < 2)) continue;
              const std::size_t a = std::min(j, i - 1), c = std::max(j, i);  // a < b < c along the path
              const std::size_t b = a + 1;
              if (!((loads_[b] - loads_[a]) * dir > 0 && (loads_[c] - loads_[b]) * dir > 0)) continue;
              const double x = mt.load, xa = loads_[a], xb = loads_[b], xc = loads_[c];
              v = values_[k][a] * (x - xb) * (x - xc) / ((xa - xb) * (xa - xc)) +
                  values_[k][b] * (x - xa) * (x - xc) / ((xb - xa) * (xb - xc)) +
                  values_[k][c] * (x - xa) * (x - xb) / ((xc - xa) * (xc - xb));
              break;
            }
            break;
          }
        break;
      case ShellMetric::Kind::final_value:
        if (k >= 0 && !values_[k].empty()) v = values_[k].back();
        break;
      case ShellMetric::Kind::first_limit_load:
        if (limit >= 0) v = vertex(loads_, limit, loads_);
        break;
      case ShellMetric::Kind::at_first_limit:
        if (limit >= 0 && k >= 0) v = vertex(loads_, limit, values_[k]);
        break;
      case ShellMetric::Kind::min_load_after_limit:
        // the lowest sample after the limit point, refined like the limit load: the vertex of the
        // parabola through it and its neighbours (a coarse path rarely lands on the minimum)
        if (limit >= 0) {
          const auto lowest = std::min_element(loads_.begin() + limit, loads_.end());
          const int i = static_cast<int>(lowest - loads_.begin());
          std::vector<double> negated(loads_.size());
          for (std::size_t k = 0; k < loads_.size(); ++k) negated[k] = -loads_[k];
          v = i > limit && i + 1 < static_cast<int>(loads_.size()) ? -vertex(negated, i, negated) : *lowest;
        }
        break;
      case ShellMetric::Kind::max_abs:
        if (k >= 0)
          for (double x : values_[k]) v = std::isnan(v) ? std::abs(x) : std::max(v, std::abs(x));
        break;
      case ShellMetric::Kind::linear_buckling_load:
        v = mt.computed;
        break;
    }
    std::string why;
    if (!std::isfinite(v)) why = unreached_reason(mt, limit);
    m.emplace_back(mt.name, v, why);
  }
  return m;
}

std::string ShellStaticSimulation::unreached_reason(const ShellMetric& mt, int limit) const {
  auto number = [](double x) {
    char b[32];
    std::snprintf(b, sizeof b, "%.6g", x);
    return std::string(b);
  };
  if (loads_.empty()) return "the path stored no state";
  const std::string unit = settings_.load_unit.empty() ? "" : " " + settings_.load_unit;
  switch (mt.kind) {
    case ShellMetric::Kind::at_load: {
      const auto [lo, hi] = std::minmax_element(loads_.begin(), loads_.end());
      return settings_.load_label + " " + number(mt.load) + unit + " never reached: the path's " +
             settings_.load_label + " ran from " + number(*lo) + " to " + number(*hi) + unit + " and ended at " +
             number(loads_.back()) + unit + " (lambda = " + number(lambda_) + ")";
    }
    case ShellMetric::Kind::linear_buckling_load:
      return mt.computed_why;
    case ShellMetric::Kind::first_limit_load:
    case ShellMetric::Kind::at_first_limit:
    case ShellMetric::Kind::min_load_after_limit:
      if (limit < 0) return "the path has no limit point (no local maximum of the " + settings_.load_label + ")";
      break;
    default: break;
  }
  return "the value is not finite";
}

}  // namespace ff::shell
