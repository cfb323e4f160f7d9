#pragma once
/// \file shell_eigen_simulation.h
/// Eigen-analyses of a CB shell structure (shell_eigen.md): its natural modes (K φ = ω² M φ) or
/// its linear buckling modes ((K₀ + λ K_G) φ = 0), about the reference state or about the state
/// the scene's loads reach by a nonlinear static solve (preload). The run publishes that state as
/// its frames (the initial frame, then the same state once the modes are known) and modes()
/// returns the modes; metrics() lists their values (frequency_k in Hz, load_multiplier_k).

#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/model/simulation.h"
#include "core/shell/cb_shell_inertia.h"
#include "core/shell/shell_model.h"
#include "core/shell/shell_static_simulation.h"
#include "core/solve/eigen_solve.h"
#include "core/solve/static_newton.h"

namespace ff::shell {

struct ShellEigenSettings {
  enum class Analysis { modal, buckling };
  Analysis analysis = Analysis::modal;
  int modes = 6;
  /// modal: the shift σ [rad²/s²] the modes are found nearest to; none: σ = −kAutomaticShift ω²_ref
  /// (shell_eigen.md (E3)), below every frequency, so rigid-body modes come first
  std::optional<double> shift;
  /// about the state the loads reach at load factor load_control.lambda_end (a nonlinear static
  /// solve, load control) instead of the reference state
  bool preload = false;
  LoadControlSettings load_control;
  EigenSolveSettings solver;   ///< count is set from `modes`
  /// modal: per quad of the mesh, its density (a laminate's plies keep their own, laminate.md (L10))
  std::vector<double> densities;
  double load_scale = 1.0;     ///< load = lambda x load_scale (critical_load, probes)
  std::string load_label = "load";
  std::vector<ShellProbe> probes;
};

/// A modal ω² is a rigid-body (zero-frequency) mode when |ω²| ≤ kRigidBodyTolerance ω²_ref,
/// ω²_ref = max_i K_ii / M_ii over the free unknowns (the mesh's highest stiffness-to-mass ratio,
/// shell_eigen.md (E4)).
inline constexpr double kRigidBodyTolerance = 1e-12;
/// The automatic modal shift, σ = −kAutomaticShift ω²_ref (shell_eigen.md (E3)).
inline constexpr double kAutomaticShift = 1e-8;

/// The nodes of `mesh` moved by `amplitude` times a mode given in the unknowns of `model` (a
/// model of that mesh): positions by the translations, node frames (directors) by the rotations,
/// as ShellModel::update moves them (shell_eigen.md §4). The mode is scaled first so that its
/// largest nodal translation is 1.
mesh::ShellMesh perturbed_mesh(const ShellModel& model, const Eigen::VectorXd& mode, double amplitude);

class ShellEigenSimulation final : public Simulation {
 public:
  /// Throws ShellSpecError as ShellModel does.
  ShellEigenSimulation(ShellModelSpec spec, ShellEigenSettings settings, RunInfo info);
  ~ShellEigenSimulation() override;
  const RunInfo& info() const override { return info_; }
  double end_time() const override { return settings_.preload ? settings_.load_control.lambda_end : 0.0; }
  std::string end_description() const override;
  std::string start() override;
  double time() const override { return lambda_; }
  /// The whole analysis (the preload path, then the eigen-solution) as the run's one step.
  StepDone step(double h) override;
  Frame frame() const override;
  Metrics metrics() const override;
  std::vector<std::string> answer_metrics() const override;
  /// buckling: the multipliers asked for that are not positive (they buckle the reversed loads)
  std::vector<std::pair<std::string, std::string>> metrics_unreached() const override;
  const ModeSet* modes() const override { return done_ ? &modes_ : nullptr; }
  SolverTotals totals() const override { return totals_; }
  std::vector<EffectStat> effect_stats() const override;
  void set_element_threads(int count, const std::atomic<bool>* busy) override { model_->set_threads({count, busy}); }

  const ShellModel& model() const { return *model_; }
  /// The modes in the model's unknowns (columns, in the order of modes()), after the run.
  const Eigen::MatrixXd& mode_vectors() const { return vectors_; }
  /// buckling: K_G of (E7), per unit multiplier, in the model's unknowns (after the run).
  const SparseMatrixD& geometric_stiffness() const { return geometric_; }
  /// What the eigen-solver did (factorizations, Lanczos products, seconds).
  const EigenSolveResult& solve_result() const { return result_; }
  /// Runs the whole analysis at once (start and step): "" or why it failed.
  std::string compute();
  /// modal: ω²_ref = max_i K_ii / M_ii at the current state (shell_eigen.md (E3)), the mesh's
  /// frequency scale that the automatic shift and the rigid-body test are measured against; one
  /// assembly of K and M, for `check` to judge a shift the scene gives.
  double reference_omega2();

 private:
  std::string modal();
  std::string buckling();
  /// modal: the symmetric stiffness and consistent mass at the current state, in solver rows
  void stiffness_and_mass(SparseMatrixD& K, SparseMatrixD& M);
  void add_mode(int number, double value, double eigenvalue, bool rigid, const Eigen::VectorXd& x);
  std::unique_ptr<ShellModel> model_;
  ShellEigenSettings settings_;
  RunInfo info_;
  SolverTotals totals_;
  std::vector<CbShellInertia> inertia_;  // modal: per element, on its reference geometry
  double lambda_ = 0.0;
  bool done_ = false;
  ModeSet modes_;
  Eigen::MatrixXd vectors_;
  SparseMatrixD geometric_;
  EigenSolveResult result_;
  int negative_multipliers_ = 0;
  double strain_per_multiplier_ = 0.0;  // buckling: largest surface strain of the path per unit multiplier
  double reference_omega2_ = 0.0, shift_ = 0.0;
  double inertia_seconds_ = 0.0;
  long long inertia_evaluations_ = 0;
};

}  // namespace ff::shell
