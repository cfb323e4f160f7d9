#include "core/solve/static_arclength.h"

#include "core/frame/text.h"

#include <algorithm>
#include <cmath>

namespace ff {

namespace arclength_detail {

std::string check_settings(const ArcLengthSettings& s, int n) {
  if (!(std::isfinite(s.lambda_start) && std::isfinite(s.initial_load_increment) && std::isfinite(s.arc_length) &&
        std::isfinite(s.psi) && !std::isnan(s.lambda_max) && !std::isnan(s.lambda_min) &&
        !std::isnan(s.displacement_limit)))
    return "non-finite arc-length setting";
  if (s.lambda_min > s.lambda_start) return "lambda_min must not exceed lambda_start";
  if (s.arc_length <= 0.0 && s.initial_load_increment == 0.0)
    return "arc-length needs arc_length > 0 or a non-zero initial_load_increment";
  if (s.psi < 0.0) return "psi must be >= 0";
  if (!(s.lam_morley_a0_cap >= 1.0)) return "lam_morley_a0_cap must be >= 1";
  if (!(s.min_arc_length_ratio > 0.0 && s.min_arc_length_ratio <= 1.0 && s.max_arc_length_ratio >= 1.0))
    return "arc-length bounds must satisfy 0 < min_arc_length_ratio <= 1 <= max_arc_length_ratio";
  if (s.desired_iterations < 1 || s.max_growth < 1.0) return "desired_iterations >= 1 and max_growth >= 1 required";
  if (s.monitor_dof >= n) return "monitor_dof is not a DoF of the problem";
  if (std::isfinite(s.displacement_limit) && s.monitor_dof < 0 && !s.monitor)
    return "a displacement limit needs monitor_dof or monitor";
  if (s.convergence.max_iterations < 1 || s.max_steps < 1) return "max_iterations and max_steps must be >= 1";
  return {};
}

class PathFollower {
 public:
  PathFollower(StaticProblem& problem, const ArcLengthSettings& s)
      : settings_(s), kernel_(problem, s.convergence), n_(problem.size()) {}
  /// Sets up (the first arc length); false when the run ends at once (result()).
  bool start();
  /// Attempts until a step is accepted (true; the run may have ended with it: finished()) or the
  /// run ends without one (false).
  bool advance();
  bool finished() const { return finished_; }
  const StaticResult& result() const { return res_; }
  const StaticStepInfo& last_step() const { return last_; }
  const std::vector<StaticAttempt>& rejected() const { return rejected_; }

 private:
  AttemptOutcome crisfield_step(double dl);
  AttemptOutcome lam_morley_step(double dl);
  // δq_f = K⁻¹ f_ref at the current state: the origin or a converged state
  bool load_tangent(double lambda, Eigen::VectorXd& dq_f);
  bool evaluate_iterate(int k, double lambda, AttemptOutcome& a);
  bool start_iteration(int k, double lambda, double rn, double previous, DivergenceMonitor& monitor, AttemptOutcome& a);
  double monitored() const;
  double monitored_after(const Eigen::VectorXd& step) const;  // at the current (unaccepted) state

  // eq. (23): the tangent predictor oriented by the previous step, or the secant one
  bool predict(double dl, Eigen::VectorXd& dq_f, std::string& failure);
  void secant(double dl, double load_weight);
  std::vector<StaticEvent> path_events(int steps) const;
  std::string path_notes(const std::vector<StaticEvent>& events) const;
  void reject(const AttemptOutcome& a, std::string why);

  const ArcLengthSettings& settings_;
  StaticKernel kernel_;
  int n_;
  double alpha2_ = 0.0;            // λ weight of the orientation metric (eq. 23): ||K0⁻¹ f||² at the start
  Eigen::VectorXd dq_pred_;        // the predictor of the attempt (eq. 22)
  double dlambda_pred_ = 0.0;
  std::vector<int> det_sign_;      // sign of det K at converged state k (0: unknown)
  std::vector<double> state_lambda_;  // λ of converged state k
  std::vector<int> reversals_;     // states where Δλ changed sign (limit points)
  std::vector<int> turn_backs_;    // states after which the increment reversed
  void finish(StaticStatus status, StaticStop stop, std::string reason);
  // after an accepted step: true when the path ends there (λ_max, the displacement limit, the
  // load-factor range, the first limit point when asked, the step budget), finished
  bool path_ends_after_step(bool final_step);
  // eqs. (13), (13'), (19): the next step's Δl from this step's corrections and turn
  void size_next_step(int iterations, double bend);
  StaticResult res_;
  StaticStepInfo last_;            // of the last accepted step
  std::vector<StaticAttempt> rejected_;  // attempts of the current advance() not accepted
  int first_step_attempts_ = 0;    // attempts the first step took (0: none accepted yet)
  double dl_first_ = 0.0;          // the first step's initial Δl
  double first_step_fraction_ = 1.0;  // the first step's accepted Δl over dl_first_
  bool finished_ = false;
  double dl_ = 0.0, dl_min_ = 0.0, dl_max_ = 0.0;  // arc length of the next attempt and its bounds
  int attempts_ = 1;               // of the step under way (1 + cut-backs)
  bool landing_failed_ = false;
  double lambda_ = 0.0;            // last converged load factor
  double monitor_last_ = 0.0;      // the monitored displacement there
  Eigen::VectorXd dq_;             // increment of the step being attempted (Σ of the applied δ)
  double dlambda_ = 0.0;           // its load increment
  Eigen::VectorXd dq_prev_;        // increment of the last converged step
  double dlambda_prev_ = 0.0;
  bool has_previous_ = false;
  Eigen::VectorXd u_total_;        // Σ of all converged increments (displacement for eq. 19, monitor)
  double a0_ = 0.0;                // Lam–Morley load scaling A0 (eqs. 19–20)
  double a0_origin_ = 0.0;         // A0 at the start (eq. 20), the base of the cap on eq. (19)
};

bool PathFollower::load_tangent(double lambda, Eigen::VectorXd& dq_f) {
  const bool full = settings_.convergence.tangent == TangentPolicy::every_iteration;
  // eq. (4''): at a converged state the factorization of the converging correction stands in for K
  // (the kernel knows it is one correction old; at the origin or after a restore there is none).
  // Lam–Morley moves λ at convergence: r and f are evaluated again, K is not wanted
  const bool last_correction = full && kernel_.factorization_of_last_correction();
  if (!kernel_.evaluated_at(lambda) && !kernel_.evaluate(lambda, full && !last_correction)) return false;
  if (!last_correction && kernel_.wants_new_tangent(0, 0.0, 0.0) && !kernel_.refresh_tangent(lambda)) return false;
  return kernel_.solve(kernel_.load(), dq_f);
}

double PathFollower::monitored() const {
  if (settings_.monitor) return settings_.monitor();
  if (settings_.monitor_dof < 0) return std::numeric_limits<double>::quiet_NaN();
  const std::optional<double> u = kernel_.problem().displacement(settings_.monitor_dof);
  return u ? *u : u_total_[settings_.monitor_dof];
}

double PathFollower::monitored_after(const Eigen::VectorXd& step) const {
  if (settings_.monitor) return settings_.monitor();
  if (settings_.monitor_dof < 0) return std::numeric_limits<double>::quiet_NaN();
  const std::optional<double> u = kernel_.problem().displacement(settings_.monitor_dof);
  return u ? *u : u_total_[settings_.monitor_dof] + step[settings_.monitor_dof];
}

// stop flag and evaluation at the current iterate (K too under full Newton, unless the last
// correction already passes the increment test (4): eq. 4'''); false ends the attempt
bool PathFollower::evaluate_iterate(int k, double lambda, AttemptOutcome& a) {
  if (stop_requested(settings_.stop)) {
    a.interrupted = true;
    return false;
  }
  const bool expect_converged =
      k > 0 && kernel_.increment_converged(a.increment_norm, a.previous_increment_norm, kernel_.norm_u(dq_));
  if (!kernel_.evaluate(lambda, settings_.convergence.tangent == TangentPolicy::every_iteration && !expect_converged)) {
    a.failure = kernel_.failure();
    return false;
  }
  return true;
}

// after the convergence test: iteration budget, divergence, tangent policy
bool PathFollower::start_iteration(int k, double lambda, double rn, double previous, DivergenceMonitor& monitor,
                                   AttemptOutcome& a) {
  if (k >= settings_.convergence.max_iterations) {
    a.failure = "no convergence in " + std::to_string(k) + " iterations near λ = " + significant(lambda) + " (residual " +
                significant(rn) + " vs limit " + significant(kernel_.residual_limit()) + ", increment " + significant(a.increment_norm) + ")";
    return false;
  }
  if (std::string why = monitor.check(k, rn, kernel_.residual_limit()); !why.empty()) {
    a.failure = "diverging near λ = " + significant(lambda) + ": " + why;
    return false;
  }
  if (kernel_.wants_new_tangent(k, rn, previous)) {
    if (!kernel_.refresh_tangent(lambda)) {
      a.failure = kernel_.failure() + " (iteration " + std::to_string(k) + ")";
      return false;
    }
  }
  return true;
}

// the previous converged increment scaled to Δl (the secant predictor, eq. 18 with the load weight)
void PathFollower::secant(double dl, double load_weight) {
  const double mu = dl / std::sqrt(kernel_.dot_u(dq_prev_, dq_prev_) + load_weight * dlambda_prev_ * dlambda_prev_);
  dq_ = mu * dq_prev_;
  dlambda_ = mu * dlambda_prev_;
}

// eq. (23): δq_f = K⁻¹ f at the converged state, oriented by the angle to the previous increment
// (displacements only: at a fold the λ part of the path's tangent changes sign, its displacement
// part does not); when that cosine is nearly zero (δq_f almost orthogonal to the path, as near a
// bifurcation) the secant predictor continues the path instead
bool PathFollower::predict(double dl, Eigen::VectorXd& dq_f, std::string& failure) {
  const double psi2 = settings_.psi * settings_.psi;
  // under modified Newton the held factorization may be older: then det K is not recorded
  const bool full = settings_.convergence.tangent == TangentPolicy::every_iteration;
  const bool tangent = load_tangent(lambda_, dq_f);
  if (!det_sign_.empty() && det_sign_.back() == 0) det_sign_.back() = tangent && full ? kernel_.determinant_sign() : 0;
  const double ff = psi2 * kernel_.dot_r(kernel_.load(), kernel_.load());
  if (!tangent) {
    if (!has_previous_) {
      failure = "predictor: " + kernel_.failure();
      return false;
    }
    secant(dl, ff);  // K singular at the converged point
  } else {
    double sign = settings_.initial_load_increment < 0.0 ? -1.0 : 1.0;
    bool use_secant = false;
    if (has_previous_) {
      const double o = kernel_.dot_u(dq_prev_, dq_f);
      const double np = std::sqrt(kernel_.dot_u(dq_prev_, dq_prev_)), nt = std::sqrt(kernel_.dot_u(dq_f, dq_f));
      use_secant = !(std::abs(o) >= settings_.ambiguous_orientation * np * nt);
      sign = o >= 0.0 ? 1.0 : -1.0;
    }
    if (use_secant) {
      secant(dl, ff);
    } else {
      dlambda_ = sign * dl / std::sqrt(kernel_.dot_u(dq_f, dq_f) + ff);
      dq_ = dlambda_ * dq_f;
      // eq. (24): on a path of constant curvature the next chord turns from the tangent by as much
      // as the tangent turned from the last chord: direction 2 τ - c (unit vectors in the metric of
      // eq. 23), used while that turn is moderate
      if (has_previous_ && settings_.curvature_predictor) {
        const double nt = std::sqrt(kernel_.dot_u(dq_f, dq_f) + alpha2_);
        const double nc = std::sqrt(kernel_.dot_u(dq_prev_, dq_prev_) + alpha2_ * dlambda_prev_ * dlambda_prev_);
        const double cos_tc = sign * (kernel_.dot_u(dq_f, dq_prev_) + alpha2_ * dlambda_prev_) / (nt * nc);
        const Eigen::VectorXd dq_dir = (2.0 * sign / nt) * dq_f - dq_prev_ / nc;
        const double dl_dir = 2.0 * sign / nt - dlambda_prev_ / nc;
        // ... and keeps at least half of the tangent's own displacement direction: where the path
        // stands nearly vertical in λ the correction could flip the displacement part, which the
        // arc-length constraint then scales up
        const double along = sign * kernel_.dot_u(dq_dir, dq_f) / (kernel_.dot_u(dq_f, dq_f) / nt);
        if (cos_tc > std::cos(2.0 * settings_.target_turn) && along >= 0.5) {
          const double mu = dl / std::sqrt(kernel_.dot_u(dq_dir, dq_dir) + ff * dl_dir * dl_dir);
          dq_ = mu * dq_dir;
          dlambda_ = mu * dl_dir;
        }
      }
    }
  }
  dq_pred_ = dq_;
  dlambda_pred_ = dlambda_;
  return true;
}

// Crisfield (1981): tangent predictor (eq. 9), exact quadratic corrector (eqs. 10–11)
AttemptOutcome PathFollower::crisfield_step(double dl) {
  AttemptOutcome a;
  const int f0 = kernel_.factorizations();
  const double psi2 = settings_.psi * settings_.psi;
  Eigen::VectorXd dq_f(n_), dq_r(n_), delta(n_), rhs;
  dq_.setZero(n_);

  std::string failure;
  if (!predict(dl, dq_f, failure)) {
    a.failure = failure;
    return a;
  }
  kernel_.update(dq_);

  DivergenceMonitor monitor(settings_.convergence);
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 0;; ++k) {
    const double lambda = lambda_ + dlambda_;
    if (!evaluate_iterate(k, lambda, a)) break;
    a.residual_norm = kernel_.norm_r(kernel_.residual());
    if (k > 0 && kernel_.converged(a.residual_norm, a.increment_norm, a.previous_increment_norm, kernel_.norm_u(dq_))) {
      a.converged = true;
      break;
    }
    if (!start_iteration(k, lambda, a.residual_norm, previous, monitor, a)) break;
    rhs = -kernel_.residual();
    if (!kernel_.solve(rhs, dq_r) || !kernel_.solve(kernel_.load(), dq_f)) {
      a.failure = kernel_.failure();
      break;
    }
    // eq. (10): ||Δq + δq_r + δλ δq_f||² + ψ²||f||²(Δλ + δλ)² = Δl²
    const double ff = psi2 * kernel_.dot_r(kernel_.load(), kernel_.load());
    const Eigen::VectorXd base = dq_ + dq_r;
    const double qa = kernel_.dot_u(dq_f, dq_f) + ff;
    const double qb = 2.0 * (kernel_.dot_u(base, dq_f) + ff * dlambda_);
    const double qc = kernel_.dot_u(base, base) + ff * dlambda_ * dlambda_ - dl * dl;
    const double disc = qb * qb - 4.0 * qa * qc;
    if (!(disc >= 0.0)) {
      a.failure = "the arc-length constraint has complex roots near λ = " + significant(lambda) + " (Δl = " + significant(dl) +
                  " too long for the local curvature of the path)";
      break;
    }
    // numerically stable roots, then eq. (11): the one continuing the step's direction
    const double sq = std::sqrt(disc);
    const double q = -0.5 * (qb + (qb >= 0.0 ? sq : -sq));
    const double r1 = q / qa, r2 = q != 0.0 ? qc / q : -r1;
    auto alignment = [&](double x) { return kernel_.dot_u(base + x * dq_f, dq_); };
    const double x = alignment(r1) >= alignment(r2) ? r1 : r2;
    delta = dq_r + x * dq_f;
    kernel_.update(delta);
    dq_ += delta;
    dlambda_ += x;
    a.previous_increment_norm = a.increment_norm;
    a.increment_norm = kernel_.norm_u(delta);
    a.iterations = k + 1;
    previous = a.residual_norm;
  }
  a.factorizations = kernel_.factorizations() - f0;
  return a;
}

// Lam & Morley (1992): secant predictor (eq. 18), residual split (eq. 14), corrector (eqs. 15–17)
AttemptOutcome PathFollower::lam_morley_step(double dl) {
  AttemptOutcome a;
  const int f0 = kernel_.factorizations();
  Eigen::VectorXd dq_f(n_), dq_h(n_), delta(n_), rhs, r_perp;
  // det K at the converged state, for the path's events (§4.4; eq. 4'')
  if (!det_sign_.empty() && det_sign_.back() == 0 && settings_.convergence.tangent == TangentPolicy::every_iteration &&
      (kernel_.factorization_of_last_correction() || kernel_.refresh_tangent(lambda_)))
    det_sign_.back() = kernel_.determinant_sign();
  if (has_previous_) {
    const double mu = dl / std::sqrt(kernel_.dot_u(dq_prev_, dq_prev_) + a0_ * dlambda_prev_ * dlambda_prev_);
    dq_ = mu * dq_prev_;
    dlambda_ = mu * dlambda_prev_;
  } else {
    if (!load_tangent(lambda_, dq_f)) {
      a.failure = "predictor: " + kernel_.failure();
      return a;
    }
    const double sign = settings_.initial_load_increment < 0.0 ? -1.0 : 1.0;
    dlambda_ = sign * dl / std::sqrt(kernel_.dot_u(dq_f, dq_f) + a0_);
    dq_ = dlambda_ * dq_f;
  }
  dq_pred_ = dq_;
  dlambda_pred_ = dlambda_;
  kernel_.update(dq_);

  DivergenceMonitor monitor(settings_.convergence);
  double previous = std::numeric_limits<double>::infinity();
  for (int k = 0;; ++k) {
    const double lambda = lambda_ + dlambda_;
    if (!evaluate_iterate(k, lambda, a)) break;
    // eq. (14): the load-parallel part of r is a load-factor error g, the rest h = r − g f
    const Eigen::VectorXd& f = kernel_.load();
    const double ff = kernel_.dot_r(f, f);
    const double g = ff > 0.0 ? kernel_.dot_r(kernel_.residual(), f) / ff : 0.0;
    r_perp = kernel_.residual() - g * f;
    a.residual_norm = kernel_.norm_r(r_perp);
    if (k > 0 && kernel_.converged(a.residual_norm, a.increment_norm, a.previous_increment_norm, kernel_.norm_u(dq_))) {
      dlambda_ += g;  // λ that leaves only h: r(q, λ + g) = h
      a.converged = true;
      break;
    }
    if (!start_iteration(k, lambda, a.residual_norm, previous, monitor, a)) break;
    rhs = -r_perp;
    if (!kernel_.solve(kernel_.load(), dq_f) || !kernel_.solve(rhs, dq_h)) {
      a.failure = kernel_.failure();
      break;
    }
    // eq. (15): ||Δq + η δq_h + x δq_f||² + A0 (Δλ + g + x)² = Δl²
    const double s = dlambda_ + g;
    const double qa = a0_ + kernel_.dot_u(dq_f, dq_f);
    auto coefficients = [&](double eta, double& qb, double& qc) {
      const Eigen::VectorXd v = dq_ + eta * dq_h;
      qb = a0_ * s + kernel_.dot_u(dq_f, v);
      qc = a0_ * s * s + kernel_.dot_u(v, v) - dl * dl;
      return qb * qb - qa * qc;
    };
    double eta = 1.0, qb = 0.0, qc = 0.0;
    double disc = coefficients(eta, qb, qc);
    if (!(disc >= 0.0)) {
      // eq. (16): real roots need η in [η1, η2]; take the end nearest to 1, 5 % inside
      const double fh = kernel_.dot_u(dq_f, dq_h), fd = kernel_.dot_u(dq_f, dq_);
      const double ea = qa * kernel_.dot_u(dq_h, dq_h) - fh * fh;
      const double eb = qa * kernel_.dot_u(dq_, dq_h) - (a0_ * s + fd) * fh;
      const double ec = qa * (kernel_.dot_u(dq_, dq_) - dl * dl) - (2.0 * a0_ * s + fd) * fd +
                        a0_ * s * s * kernel_.dot_u(dq_f, dq_f);
      const double edisc = eb * eb - ea * ec;
      if (ea > 0.0 && edisc >= 0.0) {
        const double e1 = (-eb - std::sqrt(edisc)) / ea, e2 = (-eb + std::sqrt(edisc)) / ea;
        const double ksi = 0.05 * (e2 - e1);
        eta = e2 < 1.0 ? e2 - ksi : e1 + ksi;
        disc = std::max(0.0, coefficients(eta, qb, qc));
      } else {
        // eq. (17): take the full correction, read λ off the equilibrium there, scale back to Δl
        const Eigen::VectorXd dq_cr = dq_ + dq_h;
        kernel_.update(dq_h);
        if (!kernel_.evaluate(lambda, false)) {
          a.failure = kernel_.failure();
          break;
        }
        const Eigen::VectorXd f_int = kernel_.residual() + lambda * kernel_.load();
        const double fl = kernel_.dot_r(kernel_.load(), kernel_.load());
        const double dlambda_cr = (fl > 0.0 ? kernel_.dot_r(f_int, kernel_.load()) / fl : lambda) - lambda_;
        const double mu = dl / std::sqrt(kernel_.dot_u(dq_cr, dq_cr) + a0_ * dlambda_cr * dlambda_cr);
        kernel_.restore();
        delta = mu * dq_cr;
        kernel_.update(delta);
        a.previous_increment_norm = a.increment_norm;
        a.increment_norm = kernel_.norm_u(delta - dq_);
        dq_ = delta;
        dlambda_ = mu * dlambda_cr;
        a.iterations = k + 1;
        previous = a.residual_norm;
        continue;
      }
    }
    const double sq = std::sqrt(disc);
    const Eigen::VectorXd base = dq_ + eta * dq_h;
    auto alignment = [&](double x) { return kernel_.dot_u(base + x * dq_f, dq_); };
    const double x1 = (-qb - sq) / qa, x2 = (-qb + sq) / qa;
    const double x = alignment(x1) >= alignment(x2) ? x1 : x2;
    delta = eta * dq_h + x * dq_f;
    kernel_.update(delta);
    dq_ += delta;
    dlambda_ = s + x;
    a.previous_increment_norm = a.increment_norm;
    a.increment_norm = kernel_.norm_u(delta);
    a.iterations = k + 1;
    previous = a.residual_norm;
  }
  a.factorizations = kernel_.factorizations() - f0;
  return a;
}

// the events of the path (§4.4): a Δλ sign change is a limit point; a det K sign change between
// two converged states with no limit point within one step of it is a bifurcation
std::vector<StaticEvent> PathFollower::path_events(int steps) const {
  std::vector<StaticEvent> ev;
  auto near_reversal = [&](int k) {
    return std::any_of(reversals_.begin(), reversals_.end(), [&](int r) { return std::abs(r - k) <= 1; });
  };
  auto det_changed_near = [&](int k) {
    for (int j = std::max(1, k - 1); j <= k + 1 && j < static_cast<int>(det_sign_.size()); ++j)
      if (det_sign_[j] != 0 && det_sign_[j - 1] != 0 && det_sign_[j] != det_sign_[j - 1]) return true;
    return false;
  };
  for (int r : reversals_) {
    const bool max = r > 0 && state_lambda_[r] >= state_lambda_[r - 1];
    ev.push_back({StaticEvent::Kind::limit_point, r, state_lambda_[r],
                  std::string(max ? "maximum" : "minimum") + " of λ; det K " +
                      (det_changed_near(r) ? "changed sign there" : "kept its sign (an even number of its eigenvalues "
                                                                     "crossed zero, or the solver could not tell)")});
  }
  for (int k = 1; k < static_cast<int>(det_sign_.size()) && k <= steps; ++k)
    if (det_sign_[k] != 0 && det_sign_[k - 1] != 0 && det_sign_[k] != det_sign_[k - 1] && !near_reversal(k) &&
        !near_reversal(k - 1))
      ev.push_back({StaticEvent::Kind::bifurcation, k, state_lambda_[k],
                    "det K changed sign between λ = " + significant(state_lambda_[k - 1]) + " and " + significant(state_lambda_[k]) +
                        " with no limit point: a branch crosses the path here; the path followed stays on its own "
                        "branch (no branch switching)"});
  // returns to the unloaded state and back (§4.4): λ crossing zero, the loaded side being the
  // side of the first step
  const double loaded = settings_.initial_load_increment < 0.0 ? -1.0 : 1.0;
  int unloaded_at = -1;
  for (int k = 1; k < static_cast<int>(state_lambda_.size()) && k <= steps; ++k) {
    const double before = loaded * state_lambda_[k - 1], now = loaded * state_lambda_[k];
    if (before > 0.0 && now <= 0.0) {
      unloaded_at = k;
      ev.push_back({StaticEvent::Kind::unloaded, k, state_lambda_[k],
                    "the path returned to the unloaded state: λ went from " + significant(state_lambda_[k - 1]) + " to " +
                        significant(state_lambda_[k]) + " (reversed load)"});
    } else if (before < 0.0 && now >= 0.0 && unloaded_at >= 0) {
      double extreme = 0.0;
      int at = unloaded_at;
      for (int j = unloaded_at; j < k; ++j)
        if (loaded * state_lambda_[j] < loaded * extreme) extreme = state_lambda_[at = j];
      ev.push_back({StaticEvent::Kind::loop, k, state_lambda_[k],
                    "the path came back from reversed load (out to λ = " + significant(extreme) + " at step " +
                        std::to_string(at) + ") to the loaded side: it passes loads it has passed before"});
      unloaded_at = -1;
    }
  }
  if (first_step_attempts_ > 1 && steps >= 1)
    ev.push_back(first_step_cut_back(first_step_attempts_, state_lambda_[1], first_step_fraction_));
  for (int k : turn_backs_)
    ev.push_back({StaticEvent::Kind::turn_back, k, state_lambda_[k],
                  "the increment reversed against the previous one even at the smallest arc length: the path turns "
                  "back on itself (a cusp) or the solver lost it"});
  std::stable_sort(ev.begin(), ev.end(), [](const StaticEvent& a, const StaticEvent& b) { return a.step < b.step; });
  return ev;
}

// the sentence about returns to the unloaded state and loops, which the reason carries even when
// the run completes (an empty string when there were none)
std::string PathFollower::path_notes(const std::vector<StaticEvent>& events) const {
  std::string notes;
  int unloaded_at = 0;
  for (const StaticEvent& e : events) {
    if (e.kind == StaticEvent::Kind::unloaded) {
      notes += std::string(notes.empty() ? "on the way" : ", then") + " the path returned to the unloaded state at step " +
               std::to_string(e.step) + " (λ = " + significant(e.lambda) + ")";
      unloaded_at = e.step;
    } else if (e.kind == StaticEvent::Kind::loop) {
      double extreme = 0.0;
      for (int j = unloaded_at; j < e.step; ++j)
        if (std::abs(state_lambda_[j]) > std::abs(extreme)) extreme = state_lambda_[j];
      notes += ", went out to λ = " + significant(extreme) + " and came back to the loaded side at step " +
               std::to_string(e.step) + " (a loop)";
    }
  }
  return notes;
}

// an attempt that will not be accepted: into the record (the state is restored by the caller)
void PathFollower::reject(const AttemptOutcome& a, std::string why) {
  rejected_.push_back(rejected_attempt(a, res_.steps + 1, lambda_ + dlambda_, dlambda_, std::move(why)));
}

bool PathFollower::start() {
  lambda_ = settings_.lambda_start;
  res_.lambda = lambda_;
  if (std::string why = check_settings(settings_, n_); !why.empty()) {
    finish(StaticStatus::diverged, StaticStop::invalid_settings, why);
    return false;
  }
  if (lambda_ >= settings_.lambda_max) {
    finish(StaticStatus::completed, StaticStop::lambda_reached, "λ_start is already at λ_max");
    return false;
  }

  dq_.setZero(n_);
  dq_prev_.setZero(n_);
  u_total_.setZero(n_);
  kernel_.save();
  if (settings_.monitor || settings_.monitor_dof >= 0) monitor_last_ = monitored();

  // the first Δl from the initial load increment along the initial tangent (eq. 12)
  Eigen::VectorXd dq_f(n_);
  if (!load_tangent(lambda_, dq_f)) {
    finish(StaticStatus::diverged, StaticStop::step_too_small, "initial tangent: " + kernel_.failure());
    return false;
  }
  det_sign_.push_back(kernel_.determinant_sign());
  state_lambda_.push_back(lambda_);
  const double qf = kernel_.dot_u(dq_f, dq_f);
  alpha2_ = qf;
  double dl0 = 0.0;
  if (settings_.method == ArcLengthMethod::crisfield) {
    dl0 = std::abs(settings_.initial_load_increment) *
          std::sqrt(qf + settings_.psi * settings_.psi * kernel_.dot_r(kernel_.load(), kernel_.load()));
  } else {
    a0_ = a0_origin_ = qf;  // eq. (20) at the origin
    dl0 = std::abs(settings_.initial_load_increment) * std::sqrt(2.0 * a0_);
  }
  if (settings_.arc_length > 0.0) dl0 = settings_.arc_length;
  dl_first_ = dl0;
  dl_min_ = settings_.min_arc_length_ratio * dl0;
  dl_max_ = settings_.max_arc_length_ratio * dl0;
  dl_ = dl0;
  return true;
}

void PathFollower::finish(StaticStatus status, StaticStop stop, std::string reason) {
  res_.status = status;
  res_.stop = stop;
  res_.reason = std::move(reason);
  res_.lambda = lambda_;
  res_.factorizations = kernel_.factorizations();
  res_.events = path_events(res_.steps);
  res_.notes = path_notes(res_.events);
  if (!res_.notes.empty()) res_.reason += "; " + res_.notes;
  finished_ = true;
}

bool PathFollower::path_ends_after_step(bool final_step) {
  const std::string end = settings_.lambda_max_name + " = " + significant(settings_.lambda_max);
  if (final_step) {
    finish(StaticStatus::completed, StaticStop::lambda_reached, "reached " + end);
    return true;
  }
  if ((settings_.monitor || settings_.monitor_dof >= 0) && std::abs(monitored()) >= settings_.displacement_limit) {
    finish(StaticStatus::completed, StaticStop::displacement_limit,
           "the monitored displacement reached " + significant(monitored()) + " (limit " + significant(settings_.displacement_limit) +
               ") at λ = " + significant(lambda_));
    return true;
  }
  if (lambda_ >= settings_.lambda_max) {
    finish(StaticStatus::completed, StaticStop::lambda_reached,
           "reached " + end + " (overshot to λ = " + significant(lambda_) + ": landing failed)");
    return true;
  }
  if (lambda_ < settings_.lambda_min) {
    finish(StaticStatus::incomplete, StaticStop::load_factor_bound,
           "the path left the load-factor range [" + settings_.lambda_min_name + " = " + significant(settings_.lambda_min) +
               ", " + end + "]: λ = " + significant(lambda_) + " at step " + std::to_string(res_.steps) +
               " (a reversed load beyond the bound; the state is that step's)");
    return true;
  }
  if (settings_.stop_at_first_limit_point && res_.limit_points > 0) {
    const std::vector<StaticEvent> ev = path_events(res_.steps);
    const StaticEvent first = *std::find_if(ev.begin(), ev.end(), [](const StaticEvent& e) {
      return e.kind == StaticEvent::Kind::limit_point;
    });
    finish(StaticStatus::completed, StaticStop::limit_point,
           "stopped after the first limit point, as asked: a " + first.detail.substr(0, first.detail.find(';')) +
               " at step " + std::to_string(first.step) + " (λ = " + significant(first.lambda) + "); the run ends at step " +
               std::to_string(res_.steps) + ", λ = " + significant(lambda_));
    return true;
  }
  if (res_.steps >= settings_.max_steps) {
    finish(StaticStatus::incomplete, StaticStop::max_steps,
           "step budget of " + std::to_string(settings_.max_steps) + " used up at λ = " + significant(lambda_) + " (step " +
               std::to_string(res_.steps) + "), before " + end);
    return true;
  }
  return false;
}

void PathFollower::size_next_step(int iterations, double bend) {
  double factor = settings_.max_growth;
  if (iterations > settings_.desired_iterations)
    factor = std::sqrt(static_cast<double>(settings_.desired_iterations) / iterations);
  if (settings_.target_turn > 0.0 && bend > 0.0) factor = std::min(factor, settings_.target_turn / bend);
  factor = std::max(factor, 0.25);
  if (attempts_ > 1) factor = std::min(factor, 1.0);
  dl_ = std::clamp(dl_ * factor, dl_min_, dl_max_);
  dq_prev_ = dq_;
  dlambda_prev_ = dlambda_;
  has_previous_ = true;
  attempts_ = 1;
  landing_failed_ = false;
  // eq. (19): A0 = ||q||²/λ² at the converged point, capped where λ passes close to zero
  if (settings_.method == ArcLengthMethod::lam_morley) {
    const double cap = settings_.lam_morley_a0_cap * a0_origin_;
    a0_ = lambda_ != 0.0 ? std::min(cap, kernel_.dot_u(u_total_, u_total_) / (lambda_ * lambda_)) : cap;
  }
}

bool PathFollower::advance() {
  if (finished_) return false;
  rejected_.clear();
  while (true) {
    if (stop_requested(settings_.stop)) {
      finish(StaticStatus::interrupted, StaticStop::stop_requested, "stop requested at λ = " + significant(lambda_));
      return false;
    }
    AttemptOutcome a = settings_.method == ArcLengthMethod::crisfield ? crisfield_step(dl_) : lam_morley_step(dl_);
    res_.iterations += a.iterations;
    if (a.interrupted) {
      reject(a, "stop requested");
      kernel_.restore();
      finish(StaticStatus::interrupted, StaticStop::stop_requested, "stop requested at λ = " + significant(lambda_));
      return false;
    }
    // eq. (22): a converged increment far from its predictor may sit on another branch, and one
    // pointing back along the previous step turns the path back on itself: retry shorter
    double turn = 0.0, end_turn = 0.0;
    bool reversed = false;
    if (a.converged) {
      // in the metric of eq. (23): a jump that keeps the direction of Δq but not the sign of Δλ turns too
      const double np = std::sqrt(kernel_.dot_u(dq_pred_, dq_pred_) + alpha2_ * dlambda_pred_ * dlambda_pred_);
      const double nc = std::sqrt(kernel_.dot_u(dq_, dq_) + alpha2_ * dlambda_ * dlambda_);
      const double c = kernel_.dot_u(dq_pred_, dq_) + alpha2_ * dlambda_pred_ * dlambda_;
      turn = np > 0.0 && nc > 0.0 ? std::acos(std::clamp(c / (np * nc), -1.0, 1.0)) : 0.0;
      reversed = has_previous_ && kernel_.dot_u(dq_, dq_prev_) < 0.0;
      // eq. (22'): the tangent at the converged end must fit the chord as the start tangent does;
      // an increment that landed on another branch has an end tangent unrelated to it. Under full
      // Newton it costs no factorization: the converging correction's serves (eq. 4''), and the
      // next predictor's too.
      Eigen::VectorXd t_end(n_);
      if (settings_.convergence.tangent == TangentPolicy::every_iteration && load_tangent(lambda_ + dlambda_, t_end)) {
        const double ne = std::sqrt(kernel_.dot_u(t_end, t_end) + alpha2_);
        const double nc = std::sqrt(kernel_.dot_u(dq_, dq_) + alpha2_ * dlambda_ * dlambda_);
        const double c = std::abs(kernel_.dot_u(t_end, dq_) + alpha2_ * dlambda_);
        end_turn = ne > 0.0 && nc > 0.0 ? std::acos(std::clamp(c / (ne * nc), 0.0, 1.0)) : 0.0;
      }
      const bool can_shorten = 0.5 * dl_ >= dl_min_;
      // a step that needed more than twice the desired corrections started far from the path: its
      // predictor crossed a region the path curves through (it may have landed on another branch)
      const bool laborious = a.iterations > 2 * settings_.desired_iterations;
      if (can_shorten &&
          (reversed || laborious || (settings_.max_turn > 0.0 && std::max(turn, end_turn) > settings_.max_turn))) {
        a.converged = false;
        a.failure =
            laborious ? "the step needed " + std::to_string(a.iterations) +
                            " corrections, more than twice the desired " +
                            std::to_string(settings_.desired_iterations) + " (its predictor was far from the path)"
            : reversed ? "the converged increment points back along the previous step (the path would turn back "
                         "on itself)"
                       : "the converged increment turned " + significant(std::max(turn, end_turn) * 180.0 / std::acos(-1.0)) +
                             "° from the tangent at its " + (turn >= end_turn ? "start" : "end") +
                             " (more than max_turn: it may have left the path)";
      }
    }
    if (a.converged && reversed) {
      // even the shortest arc turns back: the path cannot be followed on as one continuous curve
      turn_backs_.push_back(res_.steps);
      reject(a, "turns back on itself");
      kernel_.restore();
      finish(StaticStatus::diverged, StaticStop::step_too_small,
             "the path turns back on itself at λ = " + significant(lambda_) + " (step " + std::to_string(res_.steps) +
                 "): even at the smallest arc length " + significant(dl_) +
                 " the converged increment points back along the previous step (a cusp, or a path the solver lost)");
      return false;
    }
    if (!a.converged) {
      reject(a, a.failure);
      kernel_.restore();
      kernel_.invalidate_factorization();
      ++res_.cutbacks;
      ++attempts_;
      dl_ *= 0.5;
      if (dl_ < dl_min_) {
        finish(StaticStatus::diverged, StaticStop::step_too_small,
               "arc-length stopped at λ = " + significant(lambda_) + " (step " + std::to_string(res_.steps) +
                   "): Δl cut below its minimum " + significant(dl_min_) + "; last attempt: " + a.failure);
        return false;
      }
      continue;
    }

    // land exactly on λ_max: Newton at fixed λ_max from the interpolated increment (eq. 21), unless
    // the displacement limit comes first along this step
    bool final_step = false;
    const bool crosses_max = lambda_ < settings_.lambda_max && lambda_ + dlambda_ > settings_.lambda_max;
    if (settings_.land_on_lambda_max && !landing_failed_ && crosses_max) {
      const double t = (settings_.lambda_max - lambda_) / dlambda_;
      Eigen::VectorXd landing = t * dq_;
      const Eigen::VectorXd arc_step = dq_;
      kernel_.restore();
      kernel_.update(landing);
      const AttemptOutcome out = newton_at_fixed_load(kernel_, settings_.lambda_max, landing, settings_.stop, false);
      res_.iterations += out.iterations;
      if (!out.converged) {
        rejected_.push_back(rejected_attempt(out, res_.steps + 1, settings_.lambda_max, settings_.lambda_max - lambda_,
                                             "landing on " + settings_.lambda_max_name + ": " + out.failure));
        // take the arc-length step again and stop just past λ_max
        kernel_.restore();
        kernel_.invalidate_factorization();
        landing_failed_ = true;
        continue;
      }
      if ((settings_.monitor || settings_.monitor_dof >= 0) &&
          std::abs(monitored_after(landing)) >= settings_.displacement_limit) {
        // the displacement limit comes before λ_max along this step: keep the arc-length state,
        // which ends the run at the limit below
        rejected_.push_back(rejected_attempt(out, res_.steps + 1, settings_.lambda_max, settings_.lambda_max - lambda_,
                                             "landing on " + settings_.lambda_max_name +
                                                 " replaced: the displacement limit comes first"));
        kernel_.restore();
        kernel_.update(arc_step);
        kernel_.evaluate(lambda_ + dlambda_, false);  // the model's derived quantities (reactions) of this state
        dq_ = arc_step;
      } else {
        reject(a, "converged past " + settings_.lambda_max_name + "; replaced by the landing on it");
        dq_ = landing;
        dlambda_ = settings_.lambda_max - lambda_;
        a = out;
        final_step = true;
      }
    }

    // accept
    const int previous_state = res_.steps;
    lambda_ += dlambda_;
    kernel_.save();
    u_total_ += dq_;
    ++res_.steps;
    state_lambda_.push_back(lambda_);
    det_sign_.push_back(0);  // filled by the next predictor's factorization
    if (has_previous_ && dlambda_ * dlambda_prev_ < 0.0) {
      ++res_.limit_points;
      reversals_.push_back(previous_state);
    }
    if (settings_.monitor || settings_.monitor_dof >= 0) monitor_last_ = monitored();
    last_ = step_info(a, res_.steps, lambda_, dlambda_, attempts_, kernel_.norm_u(dq_));
    last_.arc_length = dl_;
    last_.turn = std::max(turn, end_turn);
    last_.monitored = monitored();
    if (res_.steps == 1) {
      first_step_attempts_ = attempts_;
      first_step_fraction_ = dl_ / dl_first_;
    }
    if (settings_.on_step) settings_.on_step(last_);
    if (path_ends_after_step(final_step)) return true;
    size_next_step(a.iterations, std::max(turn, end_turn));  // the step's turn seen from both of its ends
    return true;
  }
}

}  // namespace arclength_detail

using arclength_detail::PathFollower;

ArcLengthPath::ArcLengthPath(StaticProblem& problem, const ArcLengthSettings& settings)
    : impl_(std::make_unique<PathFollower>(problem, settings)) {}
ArcLengthPath::~ArcLengthPath() = default;
bool ArcLengthPath::start() { return impl_->start(); }
bool ArcLengthPath::advance() { return impl_->advance(); }
bool ArcLengthPath::finished() const { return impl_->finished(); }
const StaticResult& ArcLengthPath::result() const { return impl_->result(); }
const StaticStepInfo& ArcLengthPath::last_step() const { return impl_->last_step(); }
const std::vector<StaticAttempt>& ArcLengthPath::rejected() const { return impl_->rejected(); }

StaticResult solve_arc_length(StaticProblem& problem, const ArcLengthSettings& settings) {
  PathFollower path(problem, settings);
  if (path.start())
    while (path.advance() && !path.finished()) {
    }
  return path.result();
}

}  // namespace ff
