#pragma once
/// Plots of a run's probes against time (and overlays of several runs), through render/.
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
/// plots/<probe>.png with one series per run, for every probe the runs share.
std::vector<std::string> write_overlay_plots(const std::vector<LabelledRun>& runs, const std::string& dir,
                                             std::string* error, render::GraphicsContext* gc = nullptr);

}  // namespace ff::app
