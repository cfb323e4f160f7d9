#include "core/shell/multibody_modes.h"

#include <algorithm>
#include <cmath>

#include "core/shell/shell_eigen_simulation.h"

namespace ff::shell {

namespace {
// K and M at rest at time t (the iteration matrix with the stiffness and with the mass weight
// alone) and the constraint Jacobian B
void rest_matrices(MultibodyModel& model, double t, SparseMatrixD& K, SparseMatrixD& M, SparseMatrixD& B) {
  const int n = model.size(), m = model.constraint_count();
  const Eigen::VectorXd zero_n = Eigen::VectorXd::Zero(n), zero_m = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd r, phi;
  const IterationWeights stiffness{0.0, 0.0, 1.0}, mass{1.0, 0.0, 0.0};
  model.evaluate(t, zero_n, zero_n, zero_m, r, phi, &stiffness, &K, &B);
  model.evaluate(t, zero_n, zero_n, zero_m, r, phi, &mass, &M, nullptr);
  // symmetric parts: K = Kᵀ at rest up to load stiffness and O(|r|); M is symmetric
  SparseMatrixD Kt = K.transpose(), Mt = M.transpose();
  K = 0.5 * (K + Kt);
  M = 0.5 * (M + Mt);
  K.makeCompressed(), M.makeCompressed(), B.makeCompressed();
}
}  // namespace

double multibody_reference_omega2(MultibodyModel& model, double t) {
  SparseMatrixD K, M, B;
  rest_matrices(model, t, K, M, B);
  return largest_stiffness_to_mass(K, M);
}

MultibodyModes multibody_modes(MultibodyModel& model, const EigenSolveSettings& settings, std::optional<double> shift,
                               double t) {
  MultibodyModes out;
  SparseMatrixD K, M, B;
  rest_matrices(model, t, K, M, B);
  out.reference_omega2 = largest_stiffness_to_mass(K, M);
  if (!(out.reference_omega2 > 0.0)) {
    out.result.error = "the structure has no stiffness or no mass to vibrate with";
    return out;
  }
  out.shift = shift ? *shift : -kAutomaticShift * out.reference_omega2;
  out.result = lowest_constrained_vibration_modes(K, M, B, out.shift, settings);
  for (double w2 : out.result.values) out.rigid_body.push_back(std::abs(w2) <= kRigidBodyTolerance * out.reference_omega2);
  return out;
}

MultibodyEigenSimulation::MultibodyEigenSimulation(MultibodySpec spec, EigenSolveSettings settings,
                                                   std::optional<double> shift, std::vector<Probe> probes, RunInfo info)
    : settings_(settings), shift_(shift), probes_(std::move(probes)), info_(std::move(info)) {
  model_ = std::make_unique<MultibodyModel>(std::move(spec));
  info_.time_unit = "";
  info_.mesh = {};
  for (int I = 0; I < model_->node_count(); ++I) {
    const Vec3& p = model_->reference_pose(I).p;
    info_.mesh.reference_points.insert(info_.mesh.reference_points.end(), {p.x(), p.y(), p.z()});
  }
  for (std::size_t b = 0; b < model_->spec().shells.size(); ++b)
    for (const auto& q : model_->spec().shells[b].mesh.quads)
      for (int c = 0; c < 4; ++c) info_.mesh.quads.push_back(model_->shell_node_offset(static_cast<int>(b)) + q[c]);
  info_.probes = {{"lambda", "", "load factor"}};
  for (const Probe& p : probes_) info_.probes.push_back({p.name, "", p.label});
  info_.fields = {{"displacement", "", "displacement magnitude"}};
  modes_.analysis = "modal";
  modes_.value_name = "frequency";
  modes_.value_unit = "Hz";
  modes_.value_label = "natural frequency";
  modes_.about = "reference state";
  info_.settings.emplace_back("eigen_analysis", "modal, " + std::to_string(settings_.count) +
                                                    " modes about the reference state, joints as constraints "
                                                    "(bordered shift-invert)");
}

std::string MultibodyEigenSimulation::end_description() const {
  return "the " + std::to_string(settings_.count) + " lowest natural modes about the reference state (joints honoured)";
}

Frame MultibodyEigenSimulation::frame() const {
  Frame f;
  const int n = model_->node_count();
  f.fields.assign(1, std::vector<double>(n, 0.0));
  for (int I = 0; I < n; ++I) {
    const Vec3& p = model_->poses()[I].p;
    const Vec3& p0 = model_->reference_pose(I).p;
    f.points.insert(f.points.end(), {p.x(), p.y(), p.z()});
    f.base_points.insert(f.base_points.end(), {p0.x(), p0.y(), p0.z()});
    f.fields[0][I] = (p - p0).norm();
  }
  f.probes = {0.0};
  for (const Probe& p : probes_) f.probes.push_back(p.direction.dot(model_->node_displacement(p.node)));
  return f;
}

StepDone MultibodyEigenSimulation::step(double) {
  StepDone d;
  d.finished = true;
  d.accepted = true;
  result_ = multibody_modes(*model_, settings_, shift_);
  totals_ = {1, 1, result_.result.factorizations, 0};
  d.stats = {0.0, 1, static_cast<std::int32_t>(result_.result.factorizations), 0.0, 0.0, result_.result.ok()};
  if (!result_.result.ok()) {
    d.status = RunStatus::diverged;
    d.reason = "the modal analysis failed: " + result_.result.error;
    return d;
  }
  const double two_pi = 2.0 * std::acos(-1.0);
  const int n = model_->node_count();
  for (std::size_t k = 0; k < result_.result.values.size(); ++k) {
    Mode m;
    m.number = static_cast<int>(k) + 1;
    m.eigenvalue = result_.result.values[k];
    m.rigid_body = result_.rigid_body[k];
    m.value = m.rigid_body ? 0.0 : std::copysign(std::sqrt(std::abs(m.eigenvalue)), m.eigenvalue) / two_pi;
    m.displacement.assign(3 * n, 0.0);
    double largest = 0.0, signed_largest = 0.0;
    for (int I = 0; I < n; ++I) {
      // local increments x <- x + R du: the world translation is R du
      const Vec3 u = model_->poses()[I].R * model_->node_vector(result_.result.vectors.col(k), I).head<3>();
      for (int c = 0; c < 3; ++c) {
        m.displacement[3 * I + c] = u[c];
        if (std::abs(u[c]) > std::abs(signed_largest)) signed_largest = u[c];
      }
      largest = std::max(largest, u.norm());
    }
    const double scale = largest > 0.0 ? (signed_largest < 0 ? -1.0 : 1.0) / largest : 0.0;
    for (double& v : m.displacement) v *= scale;
    modes_.modes.push_back(std::move(m));
  }
  done_ = true;
  d.status = RunStatus::completed;
  return d;
}

std::vector<std::string> MultibodyEigenSimulation::answer_metrics() const {
  std::vector<std::string> out;  // rigid-body modes have no frequency to converge to
  for (const Mode& mode : modes_.modes)
    if (!mode.rigid_body) out.push_back("frequency_" + std::to_string(mode.number));
  return out;
}

Metrics MultibodyEigenSimulation::metrics() const {
  Metrics m;
  if (!done_) return m;
  int rigid = 0;
  for (const Mode& mode : modes_.modes) {
    m.emplace_back("frequency_" + std::to_string(mode.number), mode.value);
    rigid += mode.rigid_body;
  }
  m.emplace_back("rigid_body_modes", rigid);
  return m;
}

}  // namespace ff::shell
