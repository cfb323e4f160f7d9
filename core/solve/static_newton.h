#pragma once
/// \file static_newton.h
/// Load control: λ goes from λ_start to λ_end in steps, Newton at each fixed λ, automatic
/// cut-back (halve Δλ, restore the last converged state) and growth after easy steps.
/// Equations and rules: core/solve/static_solvers.md §2. Cannot pass limit points: it stops there
/// with status diverged and a reason naming the load reached (use static_arclength.h to go on).

#include <memory>
#include <vector>

#include "core/solve/static_common.h"

namespace ff {

struct LoadControlSettings {
  double lambda_start = 0.0;  ///< the state passed in is taken as converged at λ_start
  double lambda_end = 1.0;    ///< may be below λ_start (unloading)
  double initial_step = 0.1;  ///< |Δλ| of the first attempt
  double min_step = 1e-6;     ///< a cut-back below this ends the run (diverged, step_too_small)
  double max_step = 0.25;     ///< |Δλ| never grows beyond this
  double growth_factor = 1.5; ///< |Δλ| ← min(growth·|Δλ|, max_step) after an easy or no harder step, eq. (9)
  int easy_iterations = 4;    ///< a step converged in at most this many corrections, without cut-back, is easy
  /// λ values a step lands on exactly, as it lands on λ_end (static_solvers.md §3): where the run
  /// reports a value (a scene's at_load metrics), so it is a converged state, not an interpolation
  std::vector<double> stations;
  /// Snap-through guard (eq. 8): a converged step whose increment ||Δq|| exceeds this multiple of
  /// its first, linearized correction ||K0⁻¹(Δλ f − r0)|| jumped to a distant branch past a limit
  /// point (on the stable branch the ratio is ≤ 2 near a fold); it is rejected like a failed
  /// attempt. 0 disables the guard.
  double max_increment_ratio = 10.0;
  /// Limit-point guard (eq. 7): reject an attempt whose iterates change the sign of det K (they
  /// left the stable branch). Off lets load control follow a path through a bifurcation point.
  bool hold_determinant_sign = true;
  int max_steps = 100000;
  std::string lambda_end_name = "λ_end";  ///< how reasons name λ_end (a scene gives its key)
  StaticConvergence convergence;
  StaticStepCallback on_step;              ///< after every converged step
  const std::atomic<bool>* stop = nullptr; ///< raised by another thread: return after restoring the last converged state
};

/// Load control one step at a time: each advance() makes attempts (with cut-backs) until a step is
/// accepted (true) or the run ends (false; result() says how). The problem always holds the last
/// converged state. `settings` must outlive the path.
class LoadControlPath {
 public:
  LoadControlPath(StaticProblem& problem, const LoadControlSettings& settings);
  ~LoadControlPath();
  bool advance();
  bool finished() const { return finished_; }
  const StaticResult& result() const { return res_; }
  double lambda() const { return lambda_; }
  const StaticStepInfo& last_step() const { return last_; }  ///< of the last accepted step
  /// attempts the last advance() made and did not accept, in order (cut-backs, an interrupted one)
  const std::vector<StaticAttempt>& rejected() const { return rejected_; }

 private:
  struct State;
  void finish(StaticStatus status, StaticStop stop, std::string reason);
  void check_end();
  const LoadControlSettings& settings_;
  std::unique_ptr<State> state_;
  StaticResult res_;
  StaticStepInfo last_;
  std::vector<StaticAttempt> rejected_;
  double lambda_ = 0.0, h_ = 0.0;
  int attempts_ = 1;
  int previous_iterations_ = 0;  // corrections of the last step if it took one attempt, else 0
  bool finished_ = false;
};

/// Runs load control on `problem` from its current state to its end. On return the problem holds
/// the last converged state (λ = result.lambda).
StaticResult solve_load_control(StaticProblem& problem, const LoadControlSettings& settings);

}  // namespace ff
