#pragma once
/// \file static_arclength.h
/// Path following with an arc-length constraint: Crisfield's cylindrical (ψ = 0) or spherical
/// (ψ > 0) constraint with the exact quadratic corrector, or Lam & Morley's variant (load-parallel
/// residual absorbed into λ, automatic load scaling, reduced correction when the roots are complex).
/// Passes limit points and snap-backs. Equations and rules: core/solve/static_solvers.md §3.

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
  double max_arc_length_ratio = 10.0;   ///< Δl ≤ ratio × first Δl
  int desired_iterations = 4;           ///< N_d in Δl ← Δl sqrt(N_d/N) (eq. 13)
  double max_growth = 2.0;              ///< bound on that factor per step
  double lambda_max = 1.0;              ///< stop when λ reaches it
  bool land_on_lambda_max = true;       ///< finish exactly at λ_max (a Newton step at fixed λ_max)
  int monitor_dof = -1;                 ///< DoF reported in StaticStepInfo::monitored and limited below
  /// the monitored quantity when set (instead of monitor_dof), read at each converged state
  std::function<double()> monitor;
  double displacement_limit = std::numeric_limits<double>::infinity();  ///< stop when |u(monitor_dof)| ≥ this
  int max_steps = 500;                  ///< stop (completed, max_steps) after this many steps
  StaticConvergence convergence;
  StaticStepCallback on_step;
  const std::atomic<bool>* stop = nullptr;
};

/// Runs path following on `problem` from its current state. On return the problem holds the last
/// converged state (λ = result.lambda).
StaticResult solve_arc_length(StaticProblem& problem, const ArcLengthSettings& settings);

}  // namespace ff
