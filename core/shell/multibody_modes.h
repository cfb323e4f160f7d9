#pragma once
/// \file multibody_modes.h
/// Natural modes of a multibody structure (shells, rigid bodies, joints, supports) about its
/// current configuration at rest (core/shell/shell_eigen.md §1, (E2')): K and M are the dynamic
/// model's iteration matrix with the stiffness weight alone and with the mass weight alone (zero
/// velocities and multipliers), the joints its constraint Jacobian B, honoured exactly with
/// massless multipliers through the bordered shift-invert.

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/model/simulation.h"

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

/// ω²_ref = max_i K_ii / M_ii of the structure at rest at time t (shell_eigen.md (E3)), what
/// multibody_modes measures its shift and its rigid-body test against.
double multibody_reference_omega2(MultibodyModel& model, double t = 0.0);

/// The modal analysis of a multibody structure as a run (scene.analysis = "modal" with rigid bodies
/// or joints): it publishes the reference configuration and modes() returns the modes; drawn
/// points are the shell nodes (bodies in order) and one point per rigid body (its centre of mass).
class MultibodyEigenSimulation final : public Simulation {
 public:
  struct Probe {
    std::string name, label;
    int node = -1;
    Vec3 direction = Vec3::UnitZ();
  };
  /// `settings`: the modes wanted (count), the Lanczos basis (subspace) and the linear solver.
  MultibodyEigenSimulation(MultibodySpec spec, EigenSolveSettings settings, std::optional<double> shift,
                           std::vector<Probe> probes, RunInfo info);
  const RunInfo& info() const override { return info_; }
  double end_time() const override { return 0.0; }
  std::string end_description() const override;
  std::string start() override { return ""; }
  double time() const override { return 0.0; }
  StepDone step(double h) override;
  Frame frame() const override;
  Metrics metrics() const override;
  std::vector<std::string> answer_metrics() const override;
  const ModeSet* modes() const override { return done_ ? &modes_ : nullptr; }
  SolverTotals totals() const override { return totals_; }
  std::vector<EffectStat> effect_stats() const override { return model_->effect_stats(); }
  void set_element_threads(int count, const std::atomic<bool>* busy) override { model_->set_threads({count, busy}); }
  const MultibodyModel& model() const { return *model_; }
  const MultibodyModes& result() const { return result_; }
  /// ω²_ref of the structure at rest (multibody_reference_omega2), for `check` to judge a shift.
  double reference_omega2() { return multibody_reference_omega2(*model_); }

 private:
  std::unique_ptr<MultibodyModel> model_;
  EigenSolveSettings settings_;
  std::optional<double> shift_;
  std::vector<Probe> probes_;
  RunInfo info_;
  SolverTotals totals_;
  MultibodyModes result_;
  ModeSet modes_;
  bool done_ = false;
};

}  // namespace ff::shell
