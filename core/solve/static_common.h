#pragma once
/// \file static_common.h
/// Settings, step reports and results shared by the static solvers (load-control Newton,
/// arc-length), and the kernel both drive: weighted norms, the tangent-update policy, linear
/// solves and the Newton iteration at fixed load. Equations: core/solve/static_solvers.md.

#include <atomic>
#include <cmath>
#include <functional>
#include <limits>
#include <string>
#include <string_view>
#include <vector>

#include "core/frame/text.h"
#include "core/solve/sparse_solver.h"
#include "core/solve/static_problem.h"

namespace ff {

enum class StaticStatus {
  completed,   ///< reached the requested end (λ_end, λ_max, displacement limit) on one continuous path
  incomplete,  ///< the step budget ran out before the end: the state is the last converged step
  diverged,    ///< could not continue: `reason` says why, the state is the last converged step
  interrupted  ///< the stop flag was raised; the state is the last converged step
};

/// Machine-readable cause of the end of a run (the sentence is StaticResult::reason).
enum class StaticStop {
  none,
  lambda_reached,      ///< λ_end (load control) or λ_max (arc-length)
  displacement_limit,  ///< |u| of the monitored DoF reached its limit (arc-length)
  max_steps,           ///< the step budget is used up
  step_too_small,      ///< cut-backs exhausted: Δλ or Δl fell below its minimum (last failure in reason)
  load_factor_bound,   ///< the path left the allowed range of λ (arc-length: below lambda_min)
  limit_point,         ///< stopped at the first limit point, as asked (arc-length)
  invalid_settings,
  stop_requested
};

std::string_view to_string(StaticStatus status);
std::string_view to_string(StaticStop stop);

enum class TangentPolicy {
  every_iteration,  ///< full Newton: evaluate and factorize K at every iteration
  modified          ///< keep the last factorization (across steps too) while the residual contracts
};

/// Convergence and divergence rules of one Newton iteration sequence (static_solvers.md eqs. 3–5).
struct StaticConvergence {
  double residual_tolerance = 1e-8;   ///< ε_r: ||r||_r ≤ ε_r ||f_ref||_r + residual_floor + c ρ (eq. 3)
  double residual_floor = 0.0;        ///< absolute residual floor (force units)
  /// c in eq. (3): multiple of the round-off level ρ of the residual (eq. 3'); 0 ignores round-off
  double round_off_factor = 10.0;
  double increment_tolerance = 1e-8;  ///< ε_u: e(δ) ≤ ε_u ||Δq_step||_u + increment_floor (eq. 4)
  double increment_floor = 1e-14;     ///< absolute increment floor (length units)
  int max_iterations = 25;            ///< corrections per attempt
  double divergence_ratio = 1e6;      ///< ||r|| above this × its smallest value in the attempt: diverging
  int max_residual_increases = 5;     ///< that many consecutive residual increases: diverging
  TangentPolicy tangent = TangentPolicy::every_iteration;
  double refactor_contraction = 0.5;  ///< modified Newton refactors when ||r_k|| > this × ||r_{k−1}||
  int refactor_iterations = 4;        ///< ... or after this many iterations on one factorization
  LinearBackend linear_backend = default_linear_backend();
};

/// Published after every converged step (the app turns it into a Frame and a convergence-log row).
struct StaticStepInfo {
  int step = 0;                  ///< converged steps so far (1 for the first)
  double lambda = 0.0;           ///< load factor of the converged state
  double dlambda = 0.0;          ///< its increment over the previous step
  double arc_length = 0.0;       ///< Δl of the step (arc-length), 0 for load control
  int iterations = 0;            ///< corrections in the accepted attempt
  int attempts = 1;              ///< 1 + cut-backs spent on this step
  int factorizations = 0;        ///< tangent factorizations in the accepted attempt
  bool tangent_refactored = false;
  double residual_norm = 0.0;    ///< ||r||_r at acceptance
  double increment_norm = 0.0;   ///< ||δ||_u of the last correction
  double step_norm = 0.0;        ///< ||Δq||_u of the whole step
  double turn = 0.0;             ///< arc-length: angle [rad] between predictor and converged increment (eq. 13')
  double monitored = std::numeric_limits<double>::quiet_NaN();  ///< displacement of the monitored DoF
};

/// An attempt at a step that was not accepted (static_solvers.md §4.5): its corrector failed, a
/// path guard rejected it, the landing on the end replaced it, or a stop request ended it. The
/// record keeps it so that every correction counted in StaticResult::iterations has its row.
struct StaticAttempt {
  int step = 0;                ///< the step it attempted (converged steps before it + 1)
  double lambda = 0.0;         ///< load factor of its last iterate
  double dlambda = 0.0;        ///< its load increment from the last converged state
  int iterations = 0;          ///< corrections it spent
  int factorizations = 0;
  double residual_norm = 0.0;
  double increment_norm = 0.0;
  std::string why;             ///< one phrase
};
using StaticStepCallback = std::function<void(const StaticStepInfo&)>;

/// Something the path did at a converged step (static_solvers.md §4.4).
struct StaticEvent {
  enum class Kind {
    limit_point,  ///< λ passed a local maximum or minimum (Δλ changed sign)
    bifurcation,  ///< det K changed sign with no limit point: a branch crosses here (not followed)
    turn_back,    ///< the path turned back on itself (the increment reversed); it was not avoidable
    unloaded,     ///< λ crossed zero from the loaded side: the path returned to the unloaded state
    loop,         ///< after an `unloaded`, λ crossed zero back to the loaded side: the path came back
    first_step_cut_back  ///< the first step converged only after cut-backs (the initial step was too long)
  };
  Kind kind = Kind::limit_point;
  int step = 0;         ///< the converged step after which it was seen
  double lambda = 0.0;  ///< load factor there (the extreme λ for a limit point)
  std::string detail;   ///< one sentence, e.g. "maximum of λ; det K changed sign"
};
std::string_view to_string(StaticEvent::Kind kind);

struct StaticResult {
  StaticStatus status = StaticStatus::completed;
  StaticStop stop = StaticStop::none;
  std::string reason;     ///< one sentence: what ended the run and, on divergence, the last failure
  double lambda = 0.0;    ///< load factor of the final (last converged) state
  int steps = 0;          ///< converged steps
  int iterations = 0;     ///< corrections over all attempts, rejected ones included
  int factorizations = 0; ///< tangent factorizations over all attempts
  int cutbacks = 0;       ///< rejected attempts
  int limit_points = 0;   ///< sign changes of Δλ between consecutive steps (arc-length)
  std::vector<StaticEvent> events;  ///< limit points, bifurcations, turn-backs, ... in path order
  /// what the path did that a reader must know even when the run completed (returns to the
  /// unloaded state, loops); empty when nothing. Also the tail of `reason`.
  std::string notes;
};

/// While alive, a problem assembles its tangent in parts over the ranks a linear solver spans and
/// the solver reads only this rank's part (StaticProblem::assemble_tangent_in_parts): no rank
/// gathers the whole matrix. Nothing when the solver spans one rank or the problem cannot.
class TangentInParts {
 public:
  TangentInParts(StaticProblem& problem, SparseLinearSolver& solver);
  ~TangentInParts();
  TangentInParts(const TangentInParts&) = delete;
  TangentInParts& operator=(const TangentInParts&) = delete;
  /// The positions of the tangent's values this rank holds, nullptr when it holds them all.
  const std::vector<int>* held() const { return held_; }

 private:
  StaticProblem& problem_;
  const std::vector<int>* held_ = nullptr;
};

/// Shared numerics of one solve() call. Owns the residual, load, tangent and linear solver; every
/// state change goes through it so it knows whether the held tangent belongs to the current state.
class StaticKernel {
 public:
  StaticKernel(StaticProblem& problem, const StaticConvergence& convergence);

  StaticProblem& problem() { return problem_; }
  const StaticProblem& problem() const { return problem_; }
  const StaticConvergence& convergence() const { return convergence_; }
  int size() const { return n_; }

  // weighted norms (static_solvers.md eq. 2): displacement-like u, force-like r
  double dot_u(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;
  double norm_u(const Eigen::VectorXd& v) const { return std::sqrt(dot_u(v, v)); }
  double dot_r(const Eigen::VectorXd& a, const Eigen::VectorXd& b) const;
  double norm_r(const Eigen::VectorXd& v) const { return std::sqrt(dot_r(v, v)); }

  /// r and f_ref (and K when with_tangent) at the current state; false with failure() set when
  /// anything is non-finite.
  bool evaluate(double lambda, bool with_tangent);
  /// r and f_ref belong to the current state and λ (no update()/restore() since evaluate(λ)).
  bool evaluated_at(double lambda) const { return evaluated_ && evaluated_lambda_ == lambda; }
  /// evaluate(with_tangent) unless K already belongs to the current state, then factorize it;
  /// nothing when the held factorization already is of K at this state and λ (no factorization
  /// counted): the arc-length end-tangent check and the next predictor share one.
  bool refresh_tangent(double lambda);
  /// Decides from the policy whether this iteration refactors (k: correction index from 0).
  bool wants_new_tangent(int k, double residual_norm, double previous_residual_norm);
  /// x = K⁻¹ b with the held factorization; false with failure() set on any problem.
  bool solve(const Eigen::VectorXd& b, Eigen::VectorXd& x);

  void update(const Eigen::VectorXd& delta);
  void save();
  void restore();
  /// forget the factorization (after a rejected attempt: never retry with the tangent that failed)
  void invalidate_factorization() {
    factorized_ = factorization_current_ = false;
    updates_since_factorization_ = -1;
  }
  /// eq. (4''): the held factorization is of K one correction before the current state, and that
  /// correction converged the attempt, so it stands in for K at this converged state
  bool factorization_of_last_correction() const { return factorized_ && updates_since_factorization_ == 1; }

  /// eqs. (3)-(4): the residual test, and the increment test on the error estimate e(δ) that
  /// the contraction ||δ_k|| / ||δ_{k-1}|| gives (previous_increment_norm 0: none yet)
  bool converged(double residual_norm, double increment_norm, double previous_increment_norm, double step_norm) const;
  /// eq. (4) alone: known before the iterate is evaluated, it tells whether the iterate will
  /// likely be the converged state, whose K is not factorized (eq. 4''')
  bool increment_converged(double increment_norm, double previous_increment_norm, double step_norm) const;
  double residual_limit() const;  ///< right-hand side of the residual criterion at the held f_ref
  const Eigen::VectorXd& residual() const { return r_; }
  const Eigen::VectorXd& load() const { return f_; }
  const std::string& failure() const { return failure_; }
  int factorizations() const { return factorizations_; }  ///< since construction
  /// sign of det K of the held factorization (0 when none or singular)
  int determinant_sign() const { return factorized_ ? linear_.determinant_sign() : 0; }

 private:
  void estimate_round_off();
  StaticProblem& problem_;
  StaticConvergence convergence_;
  int n_;
  Eigen::VectorXd w2_, iw2_;  // s_i², 1/s_i²
  Eigen::VectorXd magnitude_;  // state magnitudes m_j of eq. (3')
  Eigen::VectorXd r_, f_;
  SparseMatrixD tangent_;
  SparseLinearSolver linear_;
  TangentInParts tangent_parts_;  // over ranks: this rank's part of tangent_ (after linear_)
  bool tangent_current_ = false;  // tangent_ was evaluated at the current state, at λ = tangent_lambda_
  double tangent_lambda_ = 0.0;
  bool evaluated_ = false;  // r_, f_ were evaluated at the current state, at λ = evaluated_lambda_
  double evaluated_lambda_ = 0.0;
  bool factorized_ = false;
  bool factorization_current_ = false;  // the held factorization is of K at the current state, at λ = tangent_lambda_
  /// ρ of eq. (3'): the residual change that one-ulp errors in every state coordinate make,
  /// estimated from the last evaluated tangent (0 before one, or without state magnitudes)
  double round_off_ = 0.0;
  int factorizations_ = 0;
  int iterations_on_factorization_ = 0;
  int updates_since_factorization_ = -1;  // -1: no factorization of a state on this attempt's path
  std::string failure_;
};

/// Outcome of one attempt at a step (a Newton or arc-length corrector sequence).
struct AttemptOutcome {
  bool converged = false;
  bool interrupted = false;
  bool crossed_limit = false;  ///< failed by guard (7) or (8): the load path has a limit point here
  int iterations = 0;
  int factorizations = 0;
  double residual_norm = 0.0;
  double increment_norm = 0.0;        ///< ||δ||_u of the last correction
  double previous_increment_norm = 0.0;  ///< ||δ||_u of the correction before it (0: none)
  double first_increment_norm = 0.0;  ///< ||δ||_u of the first correction (the linearized step)
  std::string failure;
};

/// Newton iterations at fixed λ from the current state (eq. 6). `step` holds the increment of the
/// step so far on entry (zero, or a predictor already applied) and the whole increment on return.
/// With hold_determinant_sign, a factorization whose det K sign differs from the first one of the
/// attempt ends it (eq. 7: the iterates crossed a limit or bifurcation point).
AttemptOutcome newton_at_fixed_load(StaticKernel& kernel, double lambda, Eigen::VectorXd& step,
                                   const std::atomic<bool>* stop, bool hold_determinant_sign);

/// Residual-growth and non-finite checks shared by the Newton and arc-length correctors.
class DivergenceMonitor {
 public:
  explicit DivergenceMonitor(const StaticConvergence& c) : convergence_(c) {}
  /// empty when fine, otherwise why the iteration is diverging; residuals at or below
  /// converged_level (the residual criterion) are never a divergence
  std::string check(int k, double residual_norm, double converged_level);

 private:
  const StaticConvergence& convergence_;
  double smallest_ = std::numeric_limits<double>::infinity();
  double previous_ = std::numeric_limits<double>::infinity();
  int increases_ = 0;
};

/// The report of a converged step (arc_length and monitored left for the caller).
StaticStepInfo step_info(const AttemptOutcome& outcome, int step, double lambda, double dlambda, int attempts,
                         double step_norm);
/// The record of an attempt that was not accepted.
StaticAttempt rejected_attempt(const AttemptOutcome& outcome, int step, double lambda, double dlambda, std::string why);
/// The event of a first step that converged only after `attempts - 1` cut-backs (§4.5).
/// `fraction`: the accepted step's length over the initial one.
StaticEvent first_step_cut_back(int attempts, double lambda, double fraction);

bool stop_requested(const std::atomic<bool>* stop);

}  // namespace ff
