#pragma once
/// \file static_arclength.h
/// Path following with an arc-length constraint: Crisfield's cylindrical (ψ = 0) or spherical
/// (ψ > 0) constraint with the exact quadratic corrector, or Lam & Morley's variant (load-parallel
/// residual absorbed into λ, automatic load scaling, reduced correction when the roots are complex).
/// Passes limit points and snap-backs. Equations and rules: core/solve/static_solvers.md §3.

#include <memory>

#include "core/solve/static_common.h"

namespace ff {

enum class ArcLengthMethod {
  crisfield,  ///< Crisfield (1981): ||Δq||² + ψ²Δλ²||f||² = Δl², tangent predictor, cut Δl on complex roots
  lam_morley  ///< Lam & Morley (1992): ||Δq||² + A0 Δλ² = Δl², A0 = ||q||²/λ², secant predictor, η-reduction
};

struct ArcLengthSettings {
  ArcLengthMethod method = ArcLengthMethod::crisfield;
  double psi = 0.0;                     ///< ψ (Crisfield): 0 = cylindrical, > 0 spherical
  /// Lam–Morley: A0 = ||q||²/λ² (eq. 19) is capped at this × its value at the start (eq. 20). Ours,
  /// not the paper's: uncapped, A0 → ∞ where the path crosses λ = 0 and the steps crawl
  /// (static_solvers.md §3.3). Infinity restores the paper's rule.
  double lam_morley_a0_cap = 10.0;
  double lambda_start = 0.0;            ///< the state passed in is taken as converged at λ_start
  double initial_load_increment = 0.1;  ///< Δλ of the first predictor; fixes the first Δl (eq. 12)
  double arc_length = 0.0;              ///< first Δl when > 0 (overrides initial_load_increment)
  double min_arc_length_ratio = 1e-4;   ///< Δl ≥ ratio × first Δl; a cut-back below ends the run
  double max_arc_length_ratio = 1e3;    ///< Δl ≤ ratio × first Δl
  int desired_iterations = 5;           ///< N_d: more corrections than this shrink Δl by sqrt(N_d/N) (eq. 13)
  double max_growth = 2.0;              ///< bound on the growth of Δl per step (eq. 13)
  /// eq. (13'): the angle [rad] between predictor and converged increment that Δl aims at; the
  /// angle grows with Δl times the curvature of the path, so long steps on straight stretches and
  /// short ones where the path turns
  double target_turn = 8.0 * 3.14159265358979323846 / 180.0;
  /// eq. (22): a converged step whose increment turned more than this [rad] from its predictor is
  /// rejected and retried shorter (it may have jumped to another branch); 0 disables the guard
  double max_turn = 24.0 * 3.14159265358979323846 / 180.0;
  /// eq. (23): the predictor's orientation follows the previous step unless the cosine between
  /// them is below this in magnitude; then the secant predictor is used
  double ambiguous_orientation = 0.05;
  /// eq. (24): correct the tangent predictor for the curvature the last step showed
  bool curvature_predictor = true;
  double lambda_max = 1.0;              ///< stop when λ reaches it
  /// a converged λ below this ends the run (incomplete, load_factor_bound): a path that runs far into
  /// reversed load has left the question the run asks (static_solvers.md §4.4)
  double lambda_min = -std::numeric_limits<double>::infinity();
  bool stop_at_first_limit_point = false;  ///< end (completed, limit_point) at the first limit point
  /// how reasons name λ_max and λ_min (a scene gives its keys)
  std::string lambda_max_name = "λ_max", lambda_min_name = "λ_min";
  bool land_on_lambda_max = true;       ///< finish exactly at λ_max (a Newton step at fixed λ_max)
  int monitor_dof = -1;                 ///< DoF reported in StaticStepInfo::monitored and limited below
  /// the monitored quantity when set (instead of monitor_dof), read at each converged state
  std::function<double()> monitor;
  double displacement_limit = std::numeric_limits<double>::infinity();  ///< stop when |u(monitor_dof)| ≥ this
  int max_steps = 500;                  ///< stop (incomplete, max_steps) after this many steps
  StaticConvergence convergence;
  StaticStepCallback on_step;
  const std::atomic<bool>* stop = nullptr;
};

namespace arclength_detail {
class PathFollower;
}

/// Path following one step at a time: start() sets up (false: the run ended at once), then each
/// advance() makes attempts until a step is accepted (true; the run may end with it: finished())
/// or the run ends without one (false). result() says how it ended. The problem always holds the
/// last converged state. `settings` must outlive the path.
class ArcLengthPath {
 public:
  ArcLengthPath(StaticProblem& problem, const ArcLengthSettings& settings);
  ~ArcLengthPath();
  bool start();
  bool advance();
  bool finished() const;
  const StaticResult& result() const;
  const StaticStepInfo& last_step() const;  ///< of the last accepted step
  /// attempts the last advance() made and did not accept, in order (before its accepted step, or
  /// all of them when it accepted none)
  const std::vector<StaticAttempt>& rejected() const;

 private:
  std::unique_ptr<arclength_detail::PathFollower> impl_;
};

/// Runs path following on `problem` from its current state to its end. On return the problem
/// holds the last converged state (λ = result.lambda).
StaticResult solve_arc_length(StaticProblem& problem, const ArcLengthSettings& settings);

}  // namespace ff
