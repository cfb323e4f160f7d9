#pragma once
/// \file multibody_modes.h
/// Natural modes of a multibody structure (shells, rigid bodies, joints, supports) about its
/// current configuration at rest (core/shell/shell_eigen.md §1, (E2')): K and M are the dynamic
/// model's iteration matrix with the stiffness weight alone and with the mass weight alone (zero
/// velocities and multipliers), the joints its constraint Jacobian B, honoured exactly with
/// massless multipliers through the bordered shift-invert.

#include <optional>

#include "core/shell/multibody_model.h"
#include "core/solve/eigen_solve.h"

namespace ff::shell {

struct MultibodyModes {
  EigenSolveResult result;          ///< ω² ascending, vectors in the model's unknowns
  double reference_omega2 = 0.0;    ///< max_i K_ii / M_ii (shell_eigen.md (E3), (E4))
  double shift = 0.0;
  std::vector<bool> rigid_body;     ///< per mode: |ω²| ≤ kRigidBodyTolerance ω²_ref
};

/// The `settings.count` lowest modes at time t (loads and gravity at t enter K as load stiffness).
MultibodyModes multibody_modes(MultibodyModel& model, const EigenSolveSettings& settings,
                               std::optional<double> shift = std::nullopt, double t = 0.0);

}  // namespace ff::shell
