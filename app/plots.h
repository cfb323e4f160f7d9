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

/// A shaded error bar along one probe's curve of a run: lo and hi at the run's own x samples.
struct ProbeBand {
  std::string probe, label;
  std::vector<double> x, lo, hi;
};

/// One run in an overlay.
struct LabelledRun {
  std::string label;
  RunInfo info;
  PlotHistory history;
  std::vector<ProbeBand> bands{};  ///< drawn under its curves, in a light shade of its colour
};

/// The GCI band along every probe the run shares with a coarser `twin` of refinement ratio
/// `ratio` > 1 (core/model/error_bars.md (R3)-(R4), formal order 2, F_s = 3): at each of the run's
/// x samples inside the twin's x range, E = (twin − run) / (ratio² − 1) with the twin linearly
/// interpolated there, and the band is run ± 3 |E|. No band for a probe whose x goes back (a path
/// past a limit point) in either run.
std::vector<ProbeBand> richardson_bands(const LabelledRun& run, const LabelledRun& twin, double ratio,
                                        const std::string& label);

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
