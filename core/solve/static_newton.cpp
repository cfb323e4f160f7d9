#include "core/solve/static_newton.h"

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

StaticResult solve_load_control(StaticProblem& problem, const LoadControlSettings& s) {
  StaticResult res;
  res.lambda = s.lambda_start;
  if (std::string why = check_settings(s); !why.empty()) {
    res.status = StaticStatus::diverged;
    res.stop = StaticStop::invalid_settings;
    res.reason = why;
    return res;
  }
  StaticKernel kernel(problem, s.convergence);
  const double direction = s.lambda_end >= s.lambda_start ? 1.0 : -1.0;
  double lambda = s.lambda_start;
  double h = s.initial_step;
  int attempts = 1;
  Eigen::VectorXd step(kernel.size());
  kernel.save();

  auto finish = [&](StaticStatus status, StaticStop stop, std::string reason) {
    res.status = status;
    res.stop = stop;
    res.reason = std::move(reason);
    res.lambda = lambda;
    res.factorizations = kernel.factorizations();
    return res;
  };

  while (true) {
    const double remaining = std::abs(s.lambda_end - lambda);
    if (remaining <= 1e-14 * std::max(1.0, std::abs(s.lambda_end)))
      return finish(StaticStatus::completed, StaticStop::lambda_reached, "reached λ_end = " + fmt(s.lambda_end));
    if (res.steps >= s.max_steps)
      return finish(StaticStatus::incomplete, StaticStop::max_steps,
                    "step budget of " + std::to_string(s.max_steps) + " used up at λ = " + fmt(lambda) + " (step " +
                        std::to_string(res.steps) + "), before λ_end = " + fmt(s.lambda_end));
    if (stop_requested(s.stop))
      return finish(StaticStatus::interrupted, StaticStop::stop_requested, "stop requested at λ = " + fmt(lambda));

    // the last step lands exactly on λ_end (and absorbs a remainder below the minimum step)
    const bool last = h >= remaining || remaining - h < s.min_step;
    const double dlambda = last ? s.lambda_end - lambda : direction * h;
    const double target = last ? s.lambda_end : lambda + dlambda;
    step.setZero();
    AttemptOutcome out = newton_at_fixed_load(kernel, target, step, s.stop, s.hold_determinant_sign);
    res.iterations += out.iterations;
    const double step_norm = kernel.norm_u(step);

    // eq. (8): a converged increment far beyond its linearization jumped over a limit point
    if (out.converged && s.max_increment_ratio > 0.0 && step_norm > s.max_increment_ratio * out.first_increment_norm) {
      out.converged = false;
      out.crossed_limit = true;
      out.failure = "converged to a distant state at λ = " + fmt(target) + ": the step is " +
                    fmt(step_norm / out.first_increment_norm) +
                    "× its linearized first correction (snap-through past a limit point)";
    }
    if (out.interrupted) {
      kernel.restore();
      return finish(StaticStatus::interrupted, StaticStop::stop_requested, "stop requested at λ = " + fmt(lambda));
    }
    if (!out.converged) {
      // cut-back: back to the last converged state, half the step, a fresh tangent
      kernel.restore();
      kernel.invalidate_factorization();
      ++res.cutbacks;
      ++attempts;
      h = 0.5 * std::abs(dlambda);
      if (h < s.min_step)
        return finish(StaticStatus::diverged, StaticStop::step_too_small,
                      (out.crossed_limit ? "limit point of the load path at λ = " + fmt(lambda) +
                                               ": load control cannot pass it (arc-length can); "
                                         : "load control stopped at λ = " + fmt(lambda) + ": ") +
                          "no load step ≥ min_step = " + fmt(s.min_step) + " converges; last attempt: " + out.failure);
      continue;
    }

    lambda = target;
    kernel.save();
    ++res.steps;
    res.lambda = lambda;
    if (s.on_step) s.on_step(step_info(out, res.steps, lambda, dlambda, attempts, step_norm));
    // growth after an easy step (never right after a cut-back)
    h = std::abs(dlambda);
    if (attempts == 1 && out.iterations <= s.easy_iterations) h = std::min(s.growth_factor * h, s.max_step);
    attempts = 1;
  }
}

}  // namespace ff
