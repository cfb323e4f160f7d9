#pragma once
/// \file generalized_alpha.h
/// Lie-group generalized-α for index-3 DAEs with iteration-matrix policies (generalized_alpha.md).
/// One object per run; it owns v, v̇, a and λ, the problem owns q.

#include <Eigen/Core>
#include <string>
#include <vector>

#include "core/solve/dynamic_problem.h"
#include "core/solve/step_report.h"
#include "core/solve/sparse_solver.h"

namespace ff {

/// Iteration-matrix policies (generalized_alpha.md §4).
enum class MatrixPolicy { full, nni, frozen, lazy };
/// The acceleration a step's iteration starts from (generalized_alpha.md §3, (G3')): zero
/// (v̇_{n+1} = 0, Arnold & Brüls), or the last step's (v̇_{n+1} = v̇_n).
enum class AccelerationPredictor { zero, previous };

struct GeneralizedAlphaSettings {
  double rho_inf = 0.9;          ///< spectral radius at infinity, (G2)
  double tolerance = 1e-6;       ///< ‖Δx‖₂ below this ends the iteration (§3)
  int max_iterations = 30;       ///< corrections per attempt
  MatrixPolicy policy = MatrixPolicy::full;
  int nni_threshold = 3;         ///< policy nni: update at this and later iterations of a step
  double refresh_ratio = 0.3;    ///< policy lazy: update when ‖Δx_k‖ > refresh_ratio ‖Δx_{k−1}‖ (G10)
  /// policy lazy: the next step starts with an update when a step that kept its matrix ended on a
  /// contraction ‖Δx_k‖/‖Δx_{k−1}‖ above this (G10'); 1 turns it off
  double step_refresh_ratio = 0.1;
  AccelerationPredictor predictor = AccelerationPredictor::zero;
  int max_cutbacks = 6;          ///< halvings of h before giving up
  LinearBackend backend = default_linear_backend();
};


class GeneralizedAlpha {
 public:
  GeneralizedAlpha(DynamicProblem& problem, GeneralizedAlphaSettings settings);
  ~GeneralizedAlpha();
  GeneralizedAlpha(const GeneralizedAlpha&) = delete;
  GeneralizedAlpha& operator=(const GeneralizedAlpha&) = delete;

  /// Consistent initial accelerations and multipliers at rest or with the given v (§3).
  /// Returns an empty string on success, otherwise why it failed.
  std::string initialize(double t0, const Eigen::VectorXd& v0);
  /// Moves the problem to its static equilibrium at time t0 before the run (a static preload):
  /// full Newton on r(q; v = 0, v̇ = 0) = 0, Φ = 0 (generalized_alpha.md (G11)), committed when the
  /// correction falls below the settings' tolerance. Returns "" or why it failed (a mechanism:
  /// "singular"). `iterations` gets the Newton corrections it took. Call initialize() after it.
  std::string find_static_equilibrium(double t0, int& iterations);
  /// Advances from time() by h (with cut-backs when needed). On failure the state is the last one
  /// that converged (time() tells where: a converged first half of a cut-back step is kept).
  StepReport step(double h);
  /// Restarts at the current (converged) state after a jump of the load (a scene's [[timeline]]
  /// change): initialize() at time() with the current velocity; the counters are kept (the
  /// mass-matrix factorization, like initialize()'s, is not counted as an update).
  std::string restart();

  double time() const { return t_; }
  const Eigen::VectorXd& velocity() const { return v_; }
  const Eigen::VectorXd& acceleration() const { return vdot_; }  ///< v̇ (physical)
  const Eigen::VectorXd& multipliers() const { return lambda_; }
  long long total_iterations() const { return noi_; }
  long long total_updates() const { return nou_; }
  long long total_fallbacks() const { return fallbacks_; }  ///< stale-matrix steps redone with updates
  /// The estimated local error of the position increments h Δq (G3) of the steps since the last
  /// call, summed (generalized_alpha.md §9, (G12)): moved into `out`, and the sum starts again at 0.
  void take_local_error(Eigen::VectorXd& out) {
    out = local_error_;
    local_error_.setZero();
  }
  /// ‖Δx‖₂ of each correction of the last attempt, in order (convergence-rate checks).
  const std::vector<double>& last_corrections() const { return corrections_; }
  const GeneralizedAlphaSettings& settings() const { return settings_; }

 private:
  struct Attempt {
    bool converged;
    int iterations, updates;
    double increment_norm, residual_norm;
    std::string failure;
  };
  Attempt attempt(double h, bool force_full);
  bool update_matrix(std::string& why);  // refills A from S_, B_ and factorizes it
  void build_augmented_pattern();
  /// S's diagonal, whole on every rank also when S is held in parts (each rank's held entries,
  /// summed over the ranks): the mass fix of initialize() and the constraint scale (G7) read it
  const Eigen::VectorXd& diagonal_of_S();

  DynamicProblem& problem_;
  GeneralizedAlphaSettings settings_;
  double am_, af_, gamma_, beta_;
  double local_error_coefficient_;  // β + (α_m − α_f)/2 − 1/6 (G13)
  Eigen::VectorXd local_error_;     // Σ (G12) since take_local_error
  double t_ = 0.0;
  Eigen::VectorXd v_, vdot_, a_, lambda_;
  double constraint_scale_ = 0.0;  // constraint row scale (G7)
  double matrix_h_ = 0.0;  // step size the factorized matrix was built for
  SparseMatrixD S_, B_, A_;
  std::vector<int> s_map_, b_map_, bt_map_;  // value positions of S, B, Bᵀ inside A
  // over ranks: the positions of S this rank holds (the problem's, null when S is whole), and its
  // diagonal's positions in S (−1 absent, or not this rank's in parts) with the buffer they fill
  const std::vector<int>* s_held_ = nullptr;
  std::vector<int> s_diagonal_;
  Eigen::VectorXd diagonal_;
  SparseLinearSolver solver_;
  bool have_matrix_ = false;
  long long noi_ = 0, nou_ = 0, fallbacks_ = 0;
  std::vector<double> corrections_;  // reserved once: no allocation in the Newton loop
  bool refresh_at_next_step_ = false;  // (G10'): the last step's kept matrix contracted too slowly
};

}  // namespace ff
