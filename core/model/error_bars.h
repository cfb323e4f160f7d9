#pragma once
/// \file error_bars.h
/// Discretization error of a metric from twins of the run on coarser discretizations: Richardson
/// extrapolation and Roache's Grid Convergence Index. Equation numbers (R1)-(R8) are those of
/// error_bars.md beside this file.

#include <optional>
#include <limits>
#include <string>
#include <vector>

namespace ff {

/// What one source of discretization error (the mesh, the time step) contributes to a metric.
struct SourceError {
  std::string source;        ///< "mesh" or "time"
  double fine = 0.0;         ///< the metric on the finer of the two levels compared (the run, or a twin (R8))
  double coarse = 0.0;       ///< on the coarser level
  double ratio = 0.0;        ///< refinement ratio r > 1 between them ((R5); 2 for a doubled time step)
  double order = 0.0;        ///< order p used in (R2)-(R3)
  bool order_observed = false;  ///< p measured from three levels (R6), not the formal order
  /// three levels: the order (R6) measured, also where it is not used (above the formal order,
  /// which then stays: (R6a)); 0 with two levels
  double observed_order = 0.0;
  double estimate = 0.0;     ///< E (R3): signed estimate of the run's error from this source
  double safety = 3.0;       ///< F_s of (R4)
  double bar = 0.0;          ///< GCI (R4) = F_s |E|
  /// "richardson" (twins, (R2)-(R6)) or "local" (the integrator's accumulated local error (R9):
  /// a magnitude, no signed estimate; coarse and ratio are NaN, estimate 0, safety 1)
  std::string method = "richardson";
};

/// Richardson's two-level estimate (R2)-(R4) from the metric on a fine and a coarse level of
/// ratio r > 1 with order p > 0. Throws std::invalid_argument for r <= 1, p <= 0 or non-finite input.
SourceError richardson(const std::string& source, double fine, double coarse, double ratio, double order,
                       double safety = 3.0);

/// The time source of a dynamic run from its integrator's accumulated local error (R9): `magnitude`
/// (>= 0, the metric's unit) is the bar as it stands; no signed estimate, so the extrapolated value
/// is the run's. Throws std::invalid_argument for a negative or non-finite magnitude.
SourceError local_time_source(double value, double magnitude);

/// The observed order (R6) from three levels f1 (finest), f2, f3 with ratios r21 = h2/h1 and
/// r32 = h3/h2; nothing when the convergence is oscillatory (the differences change sign), when a
/// difference is zero, or when the iteration does not settle.
std::optional<double> observed_order(double f1, double f2, double f3, double r21, double r32);

/// One source's estimate from the metric on two or three levels, finest first (`values`), with the
/// ratios between neighbours (`ratios`: r21, and r32 for three levels). Two levels: (R2)-(R4) with
/// the formal order and F_s = 3. Three: the observed order (R6) with F_s = 1.25 when it lies
/// within [formal/2, 2 formal]; otherwise (or for oscillatory convergence) no number but the
/// returned flag, since the levels are not in the asymptotic range (error_bars.md §3).
struct LevelEstimate {
  std::optional<SourceError> error;
  std::string flag;  ///< why there is no number ("" when there is one)
};
LevelEstimate estimate_from_levels(const std::string& source, const std::vector<double>& values,
                                   const std::vector<double>& ratios, double formal_order);

/// A metric with its error from every source (R7), or a flag instead of a number.
struct MetricError {
  std::string metric;
  double value = 0.0;                ///< the run's value f1
  std::vector<SourceError> sources;  ///< in the order estimated; empty when flagged or not estimated
  /// Why the metric has no bar although twins ran (the twin's path differs in kind, the twin has no
  /// value, ...): a sentence each. A flagged metric's estimate and bar are not to be printed.
  std::vector<std::string> flags;
  /// Sources that could not be estimated and why ("no mesh estimate: part[0].file is a fixed mesh");
  /// the bar then covers only `sources`.
  std::vector<std::string> missing;
  /// How the levels were matched where that is not plain (a mode paired by its shape, not its number)
  std::vector<std::string> notes;
  /// The integrator's accumulated local error at the metric (Simulation::local_time_errors),
  /// absolute; NaN where there is none (statics, stress probes)
  double local_time_error = std::numeric_limits<double>::quiet_NaN();
  double estimate() const;  ///< sum of the sources' E (R7)
  double bar() const;       ///< sum of the sources' GCI (R7)
  double extrapolated() const { return value - estimate(); }  ///< (R2)
  /// bar / |value| (infinity when value is 0 and the bar is not)
  double relative_bar() const;
  bool has_bar() const { return flags.empty() && !sources.empty(); }
};

}  // namespace ff
