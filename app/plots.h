#pragma once
/// Plots of a run's probes against time (and overlays of several runs), through render/.
#include <cmath>
#include <string>
#include <vector>

#include "core/frame/frame.h"

namespace ff::render {
class GraphicsContext;
}

namespace ff::app {

/// Probe time series gathered while frames stream past.
struct PlotHistory {
  std::vector<double> time;
  std::vector<std::vector<double>> probes;  ///< [probe][frame]
  void add(const Frame& f);
};

/// One run in an overlay.
struct LabelledRun {
  std::string label;
  RunInfo info;
  PlotHistory history;
};

/// plots/<probe>.png for every probe. Returns the file names written (relative to dir). Both
/// draw on `gc` when given (a context of the calling thread, e.g. the one that rendered the
/// frames), else on a context of their own.
std::vector<std::string> write_run_plots(const RunInfo& info, const PlotHistory& history, const std::string& dir,
                                         std::string* error, render::GraphicsContext* gc = nullptr);
/// The largest |difference| of one probe between any two runs of an overlay, over the x range
/// the two share (x: time, or the load probe of a static run), each run linearly interpolated at
/// the other's samples.
struct ProbeDelta {
  std::string probe, unit;
  double max_abs = NAN;        ///< NaN: no two runs have the probe over a common range
  std::string run_a, run_b;    ///< the pair where it occurs
  double x_lo = NAN, x_hi = NAN;  ///< that pair's common range
};
/// One entry per probe that at least two runs have (the x probe and lambda excepted), in the
/// order of the plots.
std::vector<ProbeDelta> overlay_deltas(const std::vector<LabelledRun>& runs);
/// max |ya - yb| over [max(xa0, xb0), min(xa_end, xb_end)]; NaN when that range is empty or an x
/// is not non-decreasing (a load that goes back and forth has no single y per x).
double max_abs_difference(const std::vector<double>& xa, const std::vector<double>& ya, const std::vector<double>& xb,
                          const std::vector<double>& yb, double* lo = nullptr, double* hi = nullptr);

/// plots/<probe>.png with one series per run, for every probe of any run (each run drawn with a
/// dash pattern and marker shape of its own; with several runs the title gives the max |Δ|).
std::vector<std::string> write_overlay_plots(const std::vector<LabelledRun>& runs, const std::string& dir,
                                             std::string* error, render::GraphicsContext* gc = nullptr);

}  // namespace ff::app
