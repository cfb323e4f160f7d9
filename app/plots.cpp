#include "app/plots.h"

#include <filesystem>

#include "render/graphics_context.h"
#include "render/plot.h"

namespace ff::app {

void PlotHistory::add(const Frame& f) {
  time.push_back(f.time);
  if (probes.size() < f.probes.size()) probes.resize(f.probes.size());
  for (std::size_t i = 0; i < f.probes.size(); ++i) probes[i].push_back(f.probes[i]);
}

std::vector<std::string> write_run_plots(const RunInfo& info, const PlotHistory& history, const std::string& dir,
                                         std::string* error) {
  LabelledRun run{info.scene_name, info, history};
  return write_overlay_plots({run}, dir, error);
}

std::vector<std::string> write_overlay_plots(const std::vector<LabelledRun>& runs, const std::string& dir,
                                             std::string* error) {
  std::vector<std::string> written;
  if (runs.empty()) return written;
  std::unique_ptr<render::GraphicsContext> gc = render::GraphicsContext::create(error);
  if (!gc) return written;
  const RunInfo& first = runs.front().info;
  for (std::size_t p = 0; p < first.probes.size(); ++p) {
    const Quantity& q = first.probes[p];
    render::PlotSpec spec;
    spec.title = q.label + (runs.size() == 1 ? " — " + first.scene_name : "");
    spec.x_label = "time [" + first.time_unit + "]";
    spec.y_label = render::axis_title(q);
    for (const LabelledRun& r : runs) {
      // match probes by name: runs of different models may order them differently
      for (std::size_t k = 0; k < r.info.probes.size(); ++k)
        if (r.info.probes[k].name == q.name && k < r.history.probes.size())
          spec.series.push_back({r.label, r.history.time, r.history.probes[k], false});
    }
    if (spec.series.empty()) continue;
    const std::string file = q.name + ".png";
    std::string e;
    if (render::write_plot_png(*gc, spec, (std::filesystem::path(dir) / file).string(), &e))
      written.push_back("plots/" + file);
    else if (error && error->empty())
      *error = e;
  }
  return written;
}

}  // namespace ff::app
