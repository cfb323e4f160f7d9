#include "core/solve/static_newton.h"

#include "core/frame/text.h"

#include <algorithm>
#include <cmath>

namespace ff {

namespace {

std::string check_settings(const LoadControlSettings& s) {
  const bool finite = std::isfinite(s.lambda_start) && std::isfinite(s.lambda_end) && std::isfinite(s.initial_step) &&
                      std::isfinite(s.min_step) && std::isfinite(s.max_step) && std::isfinite(s.growth_factor);
  if (!finite) return "non-finite load-control setting";
  if (!(s.min_step > 0.0 && s.min_step <= s.initial_step && s.initial_step <= s.max_step))
    return "load steps must satisfy 0 < min_step <= initial_step <= max_step";
  if (s.growth_factor < 1.0) return "growth_factor must be >= 1";
  if (s.convergence.max_iterations < 1) return "max_iterations must be >= 1";
  if (s.max_steps < 1) return "max_steps must be >= 1";
  return {};
}

}  // namespace

struct LoadControlPath::State {
  State(StaticProblem& problem, const LoadControlSettings& s) : kernel(problem, s.convergence), step(kernel.size()) {}
  StaticKernel kernel;
  Eigen::VectorXd step;
};

LoadControlPath::LoadControlPath(StaticProblem& problem, const LoadControlSettings& s) : settings_(s) {
  res_.lambda = lambda_ = s.lambda_start;
  h_ = s.initial_step;
  if (std::string why = check_settings(s); !why.empty()) {
    finish(StaticStatus::diverged, StaticStop::invalid_settings, why);
    return;
  }
  state_ = std::make_unique<State>(problem, s);
  state_->kernel.save();
  check_end();
}

LoadControlPath::~LoadControlPath() = default;

void LoadControlPath::finish(StaticStatus status, StaticStop stop, std::string reason) {
  res_.status = status;
  res_.stop = stop;
  res_.reason = std::move(reason);
  res_.lambda = lambda_;
  if (state_) res_.factorizations = state_->kernel.factorizations();
  finished_ = true;
}

// the ends that need no further attempt: λ_end reached, the step budget used up
void LoadControlPath::check_end() {
  const double remaining = std::abs(settings_.lambda_end - lambda_);
  if (remaining <= 1e-14 * std::max(1.0, std::abs(settings_.lambda_end)))
    finish(StaticStatus::completed, StaticStop::lambda_reached,
           "reached " + settings_.lambda_end_name + " = " + significant(settings_.lambda_end));
  else if (res_.steps >= settings_.max_steps)
    finish(StaticStatus::incomplete, StaticStop::max_steps,
           "step budget of " + std::to_string(settings_.max_steps) + " used up at λ = " + significant(lambda_) + " (step " +
               std::to_string(res_.steps) + "), before " + settings_.lambda_end_name + " = " +
               significant(settings_.lambda_end));
}

bool LoadControlPath::advance() {
  if (finished_) return false;
  rejected_.clear();
  StaticKernel& kernel = state_->kernel;
  Eigen::VectorXd& step = state_->step;
  const double direction = settings_.lambda_end >= settings_.lambda_start ? 1.0 : -1.0;
  while (true) {
    if (stop_requested(settings_.stop)) {
      finish(StaticStatus::interrupted, StaticStop::stop_requested, "stop requested at λ = " + significant(lambda_));
      return false;
    }
    // the step lands exactly on the next station or λ_end when it would reach it (and absorbs a
    // remainder below the minimum step)
    double stop_at = settings_.lambda_end;
    for (double s : settings_.stations)
      if (direction * (s - lambda_) > settings_.min_step && direction * (s - stop_at) < 0.0) stop_at = s;
    const double remaining = std::abs(stop_at - lambda_);
    const bool lands = h_ >= remaining || remaining - h_ < settings_.min_step;
    const double dlambda = lands ? stop_at - lambda_ : direction * h_;
    const double target = lands ? stop_at : lambda_ + dlambda;
    step.setZero();
    AttemptOutcome out = newton_at_fixed_load(kernel, target, step, settings_.stop, settings_.hold_determinant_sign);
    res_.iterations += out.iterations;
    const double step_norm = kernel.norm_u(step);

    // eq. (8): a converged increment far beyond its linearization jumped over a limit point
    if (out.converged && settings_.max_increment_ratio > 0.0 &&
        step_norm > settings_.max_increment_ratio * out.first_increment_norm) {
      out.converged = false;
      out.crossed_limit = true;
      out.failure = "converged to a distant state at λ = " + significant(target) + ": the step is " +
                    significant(step_norm / out.first_increment_norm) +
                    "× its linearized first correction (snap-through past a limit point)";
    }
    if (!out.converged)  // into the record before the state goes back
      rejected_.push_back(rejected_attempt(out, res_.steps + 1, target, dlambda,
                                           out.interrupted ? "stop requested" : out.failure));
    if (out.interrupted) {
      kernel.restore();
      finish(StaticStatus::interrupted, StaticStop::stop_requested, "stop requested at λ = " + significant(lambda_));
      return false;
    }
    if (!out.converged) {
      // cut-back: back to the last converged state, half the step, a fresh tangent
      kernel.restore();
      kernel.invalidate_factorization();
      ++res_.cutbacks;
      ++attempts_;
      h_ = 0.5 * std::abs(dlambda);
      if (h_ < settings_.min_step) {
        finish(StaticStatus::diverged, StaticStop::step_too_small,
               (out.crossed_limit ? "limit point of the load path at λ = " + significant(lambda_) +
                                        ": load control cannot pass it (arc-length can); "
                                  : "load control stopped at λ = " + significant(lambda_) + ": ") +
                   "no load step ≥ min_step = " + significant(settings_.min_step) + " converges; last attempt: " + out.failure);
        return false;
      }
      continue;
    }

    lambda_ = target;
    kernel.save();
    ++res_.steps;
    res_.lambda = lambda_;
    last_ = step_info(out, res_.steps, lambda_, dlambda, attempts_, step_norm);
    if (res_.steps == 1 && attempts_ > 1)
      res_.events.push_back(first_step_cut_back(attempts_, lambda_, std::abs(dlambda) / settings_.initial_step));
    if (settings_.on_step) settings_.on_step(last_);
    // growth after an easy step, or one that took no more corrections than the step before (the
    // path is not getting harder), never right after a cut-back; a step shortened to land on a
    // station keeps the size it had
    const bool shortened = attempts_ == 1 && std::abs(dlambda) < (1.0 - 1e-12) * h_;
    const bool not_harder = previous_iterations_ > 0 && out.iterations <= previous_iterations_ &&
                            2 * out.iterations <= settings_.convergence.max_iterations;
    if (!shortened) {
      h_ = std::abs(dlambda);
      if (attempts_ == 1 && (out.iterations <= settings_.easy_iterations || not_harder))
        h_ = std::min(settings_.growth_factor * h_, settings_.max_step);
    }
    previous_iterations_ = attempts_ == 1 && !shortened ? out.iterations : 0;
    attempts_ = 1;
    check_end();
    return true;
  }
}

StaticResult solve_load_control(StaticProblem& problem, const LoadControlSettings& s) {
  LoadControlPath path(problem, s);
  while (path.advance()) {
  }
  return path.result();
}

}  // namespace ff
