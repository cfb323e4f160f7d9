#include "core/shell/multibody_modes.h"

#include <algorithm>
#include <cmath>

#include "core/shell/shell_eigen_simulation.h"

namespace ff::shell {

MultibodyModes multibody_modes(MultibodyModel& model, const EigenSolveSettings& settings, std::optional<double> shift,
                               double t) {
  MultibodyModes out;
  const int n = model.size(), m = model.constraint_count();
  const Eigen::VectorXd zero_n = Eigen::VectorXd::Zero(n), zero_m = Eigen::VectorXd::Zero(m);
  Eigen::VectorXd r, phi;
  SparseMatrixD K, M, B;
  const IterationWeights stiffness{0.0, 0.0, 1.0}, mass{1.0, 0.0, 0.0};
  model.evaluate(t, zero_n, zero_n, zero_m, r, phi, &stiffness, &K, &B);
  model.evaluate(t, zero_n, zero_n, zero_m, r, phi, &mass, &M, nullptr);
  // symmetric parts: K = Kᵀ at rest up to load stiffness and O(|r|); M is symmetric
  SparseMatrixD Kt = K.transpose(), Mt = M.transpose();
  K = 0.5 * (K + Kt);
  M = 0.5 * (M + Mt);
  K.makeCompressed(), M.makeCompressed(), B.makeCompressed();
  for (int i = 0; i < n; ++i)
    if (M.coeff(i, i) > 0.0) out.reference_omega2 = std::max(out.reference_omega2, K.coeff(i, i) / M.coeff(i, i));
  if (!(out.reference_omega2 > 0.0)) {
    out.result.error = "the structure has no stiffness or no mass to vibrate with";
    return out;
  }
  out.shift = shift ? *shift : -kAutomaticShift * out.reference_omega2;
  out.result = lowest_constrained_vibration_modes(K, M, B, out.shift, settings);
  for (double w2 : out.result.values) out.rigid_body.push_back(std::abs(w2) <= kRigidBodyTolerance * out.reference_omega2);
  return out;
}

}  // namespace ff::shell
