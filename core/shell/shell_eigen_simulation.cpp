#include "core/shell/shell_eigen_simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "core/frame/text.h"
#include "core/lie/so3.h"
#include "core/solve/sparse_solver.h"

namespace ff::shell {

namespace {
using Clock = std::chrono::steady_clock;
double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }
// the difference step of (E6): its largest translation is this fraction of the structure's size
constexpr double kBucklingStep = 1e-6;
SparseMatrixD symmetric_part(const SparseMatrixD& k) {
  SparseMatrixD t = k.transpose();
  SparseMatrixD s = 0.5 * (k + t);
  s.makeCompressed();
  return s;
}
// largest nodal translation (world) of a vector of the model's unknowns
double largest_translation(const ShellModel& model, const Eigen::VectorXd& x) {
  double largest = 0.0;
  for (int I = 0; I < model.spec().mesh.node_count(); ++I) {
    Vec3 u = Vec3::Zero();
    for (int s = 0; s < 3; ++s)
      if (model.equation(I, s) >= 0) u += model.translation_basis(I).col(s) * x[model.equation(I, s)];
    largest = std::max(largest, u.norm());
  }
  return largest;
}
}  // namespace

mesh::ShellMesh perturbed_mesh(const ShellModel& model, const Eigen::VectorXd& mode, double amplitude) {
  mesh::ShellMesh m = model.spec().mesh;
  const double largest = largest_translation(model, mode);
  const double scale = largest > 0.0 ? amplitude / largest : 0.0;
  for (int I = 0; I < m.node_count(); ++I) {
    auto slot = [&](int s) { return model.equation(I, s) >= 0 ? scale * mode[model.equation(I, s)] : 0.0; };
    const Vec3 du(slot(0), slot(1), slot(2));
    m.points[I] += model.translation_basis(I) * du;
    const Vec3 dtheta(slot(3), slot(4), model.dofs_of_node(I) == 6 ? slot(5) : 0.0);
    // as ShellModel::update: spatial increments about T_r at 6-DoF nodes, the node's own e1, e2 at 5-DoF ones
    const Mat3 old = m.frames[I];
    m.frames[I] = model.dofs_of_node(I) == 6 ? Mat3(lie::exp_so3(model.rotation_basis(I) * dtheta) * old)
                                             : Mat3(old * lie::exp_so3(dtheta));
    const Mat3 turn = m.frames[I] * old.transpose();
    m.normals[I] = m.frames[I].col(2);
    for (std::size_t q = 0; q < m.corner_normals.size(); ++q)
      for (int c = 0; c < 4; ++c)
        if (m.quads[q][c] == I) m.corner_normals[q][c] = turn * m.corner_normals[q][c];
  }
  return m;
}

ShellEigenSimulation::ShellEigenSimulation(ShellModelSpec spec, ShellEigenSettings settings, RunInfo info)
    : settings_(std::move(settings)), info_(std::move(info)) {
  model_ = std::make_unique<ShellModel>(std::move(spec));
  settings_.solver.count = settings_.modes;
  const mesh::ShellMesh& m = model_->spec().mesh;
  info_.time_unit = "";
  info_.mesh.reference_points.clear();
  for (const Vec3& p : m.points) info_.mesh.reference_points.insert(info_.mesh.reference_points.end(), {p.x(), p.y(), p.z()});
  for (const auto& q : m.quads) info_.mesh.quads.insert(info_.mesh.quads.end(), q.begin(), q.end());
  info_.probes = {{"lambda", "", "load factor"}, {"load", "", settings_.load_label}};
  for (const ShellProbe& p : settings_.probes) info_.probes.push_back({p.name, "", p.label});
  info_.fields = {{"displacement", "", "displacement magnitude"}, {"strain", "", "largest principal surface strain"}};
  info_.plot_x_probe = "load";
  const bool modal = settings_.analysis == ShellEigenSettings::Analysis::modal;
  if (modal) {
    // the consistent mass of every element on its reference geometry (cb_shell_dynamics.md (D3))
    const ShellElements& elements = model_->elements();
    inertia_.reserve(elements.size());
    ElementPoses ref;
    for (int k = 0; k < elements.size(); ++k) {
      ShellElements::corner_poses(elements[k], model_->poses(), ref);
      inertia_.emplace_back(ref, elements[k].elastic->section(), settings_.densities.at(k));
    }
  }
  modes_.analysis = modal ? "modal" : "buckling";
  modes_.value_name = modal ? "frequency" : "load_multiplier";
  modes_.value_unit = modal ? "Hz" : "";
  modes_.value_label = modal ? "natural frequency" : "load multiplier";
  modes_.about = settings_.preload ? "preloaded to λ = " + significant(settings_.load_control.lambda_end) : "reference state";
  info_.settings.emplace_back("eigen_analysis", modes_.analysis + ", " + std::to_string(settings_.modes) +
                                                    " modes about the " + modes_.about);
}

ShellEigenSimulation::~ShellEigenSimulation() = default;

std::string ShellEigenSimulation::end_description() const {
  std::string s = "the " + std::to_string(settings_.modes) +
                  (settings_.analysis == ShellEigenSettings::Analysis::modal ? " lowest natural modes"
                                                                             : " lowest buckling load multipliers");
  return s + " about the " + modes_.about;
}

std::string ShellEigenSimulation::start() {
  lambda_ = 0.0;
  return "";
}

Frame ShellEigenSimulation::frame() const {
  Frame f;
  f.time = lambda_;
  f.load_factor = lambda_;
  const auto& poses = model_->poses();
  const auto& ref = model_->spec().mesh.points;
  f.fields.assign(1, std::vector<double>(poses.size()));
  f.fields.push_back(model_->nodal_surface_strain());
  for (std::size_t i = 0; i < poses.size(); ++i) {
    f.points.insert(f.points.end(), {poses[i].p.x(), poses[i].p.y(), poses[i].p.z()});
    f.base_points.insert(f.base_points.end(), {ref[i].x(), ref[i].y(), ref[i].z()});
    f.fields[0][i] = (poses[i].p - ref[i]).norm();
  }
  f.probes = {lambda_, lambda_ * settings_.load_scale};
  for (const ShellProbe& p : settings_.probes) {
    if (p.quantity == ShellProbe::Quantity::displacement) {
      f.probes.push_back(p.direction.dot(model_->node_displacement(p.node)));
    } else if (p.quantity == ShellProbe::Quantity::reaction) {
      Vec3 total = Vec3::Zero();
      for (int I : p.nodes) total += model_->node_reaction(I);
      f.probes.push_back(p.direction.dot(total));
    } else {
      std::size_t field = std::string::npos;
      const std::vector<StressField> fields = stress_fields(model_->stress_layout());
      for (std::size_t k = 0; k < fields.size(); ++k)
        if (fields[k].name == p.field) field = k;
      f.probes.push_back(field == std::string::npos ? std::numeric_limits<double>::quiet_NaN()
                                                    : model_->nodal_stress(p.node, field));
    }
  }
  return f;
}

StepDone ShellEigenSimulation::step(double) {
  StepDone d;
  d.finished = true;
  const std::string why = compute();
  d.accepted = true;  // the state (reference or preloaded) is a converged one either way
  d.stats = {lambda_, static_cast<std::int32_t>(totals_.newton_iterations),
             static_cast<std::int32_t>(totals_.jacobian_updates), 0.0, 0.0, why.empty()};
  d.status = why.empty() ? RunStatus::completed : RunStatus::diverged;
  d.reason = why;
  return d;
}

std::string ShellEigenSimulation::compute() {
  totals_ = {};
  totals_.steps = 1;
  totals_.cutbacks = 0;
  if (settings_.preload) {
    // the state the modes are about: load control to lambda_end (static_solvers.md §2)
    const StaticResult r = solve_load_control(*model_, settings_.load_control);
    totals_.newton_iterations = r.iterations;
    totals_.jacobian_updates = r.factorizations;
    totals_.cutbacks = r.cutbacks;
    lambda_ = r.lambda;
    if (r.status != StaticStatus::completed)
      return "the preload did not reach λ = " + significant(settings_.load_control.lambda_end) + ": " + r.reason;
  }
  const std::string why = settings_.analysis == ShellEigenSettings::Analysis::modal ? modal() : buckling();
  totals_.newton_iterations += 1;
  totals_.jacobian_updates += result_.factorizations;
  done_ = why.empty();
  return why;
}

void ShellEigenSimulation::add_mode(int number, double value, double eigenvalue, bool rigid, const Eigen::VectorXd& x) {
  Mode mode;
  mode.number = number;
  mode.value = value;
  mode.eigenvalue = eigenvalue;
  mode.rigid_body = rigid;
  const int nn = model_->spec().mesh.node_count();
  mode.displacement.assign(3 * nn, 0.0);
  double largest = 0.0, signed_largest = 0.0;
  for (int I = 0; I < nn; ++I) {
    Vec3 u = Vec3::Zero();
    for (int s = 0; s < 3; ++s)
      if (model_->equation(I, s) >= 0) u += model_->translation_basis(I).col(s) * x[model_->equation(I, s)];
    for (int c = 0; c < 3; ++c) {
      mode.displacement[3 * I + c] = u[c];
      if (std::abs(u[c]) > std::abs(signed_largest)) signed_largest = u[c];
    }
    largest = std::max(largest, u.norm());
  }
  // unit largest nodal translation, its largest component positive (a sign the run reproduces)
  const double scale = largest > 0.0 ? (signed_largest < 0 ? -1.0 : 1.0) / largest : 0.0;
  for (double& v : mode.displacement) v *= scale;
  vectors_.col(number - 1) = scale * x;
  modes_.modes.push_back(std::move(mode));
}

void ShellEigenSimulation::stiffness_and_mass(SparseMatrixD& K, SparseMatrixD& M) {
  Eigen::VectorXd r;
  model_->evaluate(lambda_, r, &K, nullptr);
  K = symmetric_part(K);  // at equilibrium K = Kᵀ to O(|r|) (static_problem.h)
  const Clock::time_point t0 = Clock::now();
  model_->assemble_element_matrices(
      [&](int k, const ElementPoses& cur, Mat24& m) {
        ElementRates still;
        for (Vec6& v : still) v.setZero();
        Vec24 force;
        m.setZero();
        InertiaJacobians jac;
        jac.mass = &m;
        inertia_[k].evaluate(cur, still, still, force, jac);
      },
      M);
  M = symmetric_part(M);
  inertia_seconds_ += seconds_since(t0);
  inertia_evaluations_ += static_cast<long long>(inertia_.size());
}

double ShellEigenSimulation::reference_omega2() {
  SparseMatrixD K, M;
  stiffness_and_mass(K, M);
  return largest_stiffness_to_mass(K, M);
}

std::string ShellEigenSimulation::modal() {
  SparseMatrixD K, M;
  stiffness_and_mass(K, M);
  // (E4): the mesh's largest stiffness-to-mass ratio scales the automatic shift and the zero test
  reference_omega2_ = largest_stiffness_to_mass(K, M);
  if (!(reference_omega2_ > 0.0)) return "the structure has no stiffness or no mass to vibrate with";
  shift_ = settings_.shift ? *settings_.shift : -kAutomaticShift * reference_omega2_;
  result_ = lowest_vibration_modes(K, M, shift_, settings_.solver);
  if (!result_.ok()) return "the modal analysis failed: " + result_.error;
  const int count = static_cast<int>(result_.values.size());
  vectors_.resize(K.rows(), count);
  const double two_pi = 2.0 * std::acos(-1.0);
  for (int k = 0; k < count; ++k) {
    const double w2 = result_.values[k];
    const bool rigid = std::abs(w2) <= kRigidBodyTolerance * reference_omega2_;
    // a negative ω² beyond the zero test is an unstable state (a preload past buckling): its
    // frequency is reported negative, -sqrt|ω²| / 2π, so that it cannot pass for a vibration
    const double f = rigid ? 0.0 : std::copysign(std::sqrt(std::abs(w2)), w2) / two_pi;
    add_mode(k + 1, f, w2, rigid, result_.vectors.col(k));
  }
  info_.settings.emplace_back("eigen_shift", significant(shift_) + " rad^2/s^2");
  return "";
}

std::string ShellEigenSimulation::buckling() {
  Eigen::VectorXd r, f_ref, path;
  SparseMatrixD K;
  model_->evaluate(lambda_, r, &K, &f_ref);
  K = symmetric_part(K);
  // the path tangent dq/dλ at the state (the linear solution at the reference state)
  {
    SparseLinearSolver solver(settings_.solver.backend);
    LinearStatus s = solver.factorize(K);
    ++totals_.jacobian_updates;
    if (s) s = solver.solve(f_ref, path);
    if (!s)
      return "the stiffness at the " + modes_.about + " could not be factorized: " + s.message +
             (s.code == LinearStatus::Code::singular ? " (a mechanism: some part is not held against rigid motion)" : "");
    if (solver.determinant_sign() < 0 && settings_.preload)
      return "the preloaded state is not stable (its stiffness is not positive definite): it is past buckling";
  }
  // (E6): K_G = dK_T/dλ along the path, by central differences of the tangent at q ⊕ ±ε dq/dλ
  const double largest = largest_translation(*model_, path);
  if (!(largest > 0.0)) return "the scene's loads do not deform the structure: nothing can buckle";
  Vec3 lo = model_->spec().mesh.points.front(), hi = lo;
  for (const Vec3& p : model_->spec().mesh.points) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  const double size = (hi - lo).norm();
  const double eps = kBucklingStep * size / largest;
  model_->save_state();
  SparseMatrixD k_plus, k_minus;
  Eigen::VectorXd rr;
  model_->update(eps * path);
  model_->evaluate(lambda_ + eps, rr, &k_plus, nullptr);
  {  // the largest surface strain of the prebuckling path per unit multiplier (linear along it)
    const std::vector<double> strain = model_->nodal_surface_strain();
    double largest = 0.0;
    for (double e : strain) largest = std::max(largest, std::abs(e));
    strain_per_multiplier_ = largest / eps;
  }
  model_->restore_state();
  model_->update(-eps * path);
  model_->evaluate(lambda_ - eps, rr, &k_minus, nullptr);
  model_->restore_state();
  model_->evaluate(lambda_, rr, nullptr, nullptr);  // the reactions of the state again
  geometric_ = symmetric_part((k_plus - k_minus) / (2.0 * eps));
  result_ = lowest_buckling_multipliers(K, geometric_, settings_.solver, &negative_multipliers_);
  if (!result_.ok()) return "the buckling analysis failed: " + result_.error;
  const int count = static_cast<int>(result_.values.size());
  vectors_.resize(K.rows(), count);
  for (int k = 0; k < count; ++k)
    add_mode(k + 1, lambda_ + result_.values[k], result_.values[k], false, result_.vectors.col(k));
  if (negative_multipliers_ > 0)
    info_.settings.emplace_back("buckling_reversed", std::to_string(negative_multipliers_) +
                                                         " of the lowest multipliers are negative (buckling under "
                                                         "the reversed loads) and are not reported");
  return "";
}

std::vector<std::string> ShellEigenSimulation::answer_metrics() const {
  std::vector<std::string> out;  // rigid-body modes have no frequency to converge to
  if (!done_) return out;
  for (const Mode& mode : modes_.modes)
    if (!mode.rigid_body) out.push_back(modes_.value_name + "_" + std::to_string(mode.number));
  if (settings_.analysis == ShellEigenSettings::Analysis::buckling && !modes_.modes.empty()) out.push_back("critical_load");
  return out;
}

Metrics ShellEigenSimulation::metrics() const {
  Metrics m;
  if (!done_) return m;
  const bool modal = settings_.analysis == ShellEigenSettings::Analysis::modal;
  int rigid = 0;
  for (const Mode& mode : modes_.modes) {
    m.emplace_back(modes_.value_name + "_" + std::to_string(mode.number), mode.value);
    rigid += mode.rigid_body;
  }
  if (modal) {
    m.emplace_back("rigid_body_modes", rigid);
  } else if (!modes_.modes.empty()) {
    m.emplace_back("critical_load", modes_.modes.front().value * settings_.load_scale);
    // shell_eigen.md §2: beyond ~1e-2 the linear prediction is outside its validity
    m.emplace_back("prebuckling_strain", strain_per_multiplier_ * modes_.modes.front().eigenvalue);
  }
  return m;
}

std::vector<std::pair<std::string, std::string>> ShellEigenSimulation::metrics_unreached() const {
  std::vector<std::pair<std::string, std::string>> out;
  if (!done_ || settings_.analysis != ShellEigenSettings::Analysis::buckling) return out;
  const int found = static_cast<int>(modes_.modes.size());
  const std::string why = std::to_string(negative_multipliers_) + " of the " + std::to_string(settings_.modes) +
                          " lowest multipliers are negative: those modes buckle under the reversed loads";
  for (int k = found + 1; k <= settings_.modes; ++k) out.emplace_back("load_multiplier_" + std::to_string(k), why);
  if (found == 0) out.emplace_back("critical_load", why);
  return out;
}

std::vector<EffectStat> ShellEigenSimulation::effect_stats() const {
  std::vector<EffectStat> s = model_->effect_stats();
  if (inertia_evaluations_ > 0) s.push_back({"inertia", inertia_evaluations_, inertia_seconds_, ""});
  return s;
}

}  // namespace ff::shell
