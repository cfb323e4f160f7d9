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
                                         std::string* error, render::GraphicsContext* gc) {
  LabelledRun run{info.scene_name, info, history};
  return write_overlay_plots({run}, dir, error, gc);
}

std::vector<std::string> write_overlay_plots(const std::vector<LabelledRun>& runs, const std::string& dir,
                                             std::string* error, render::GraphicsContext* given) {
  std::vector<std::string> written;
  if (runs.empty()) return written;
  std::unique_ptr<render::GraphicsContext> own;
  if (!given) {
    own = render::GraphicsContext::create(error);
    if (!own) return written;
  }
  render::GraphicsContext* gc = given ? given : own.get();
  const RunInfo& first = runs.front().info;
  auto probe_index = [](const RunInfo& info, const std::string& name) {
    for (std::size_t k = 0; k < info.probes.size(); ++k)
      if (info.probes[k].name == name) return static_cast<int>(k);
    return -1;
  };
  // statics plot against a load probe, dynamics against time
  const int xi = first.plot_x_probe.empty() ? -1 : probe_index(first, first.plot_x_probe);
  for (std::size_t p = 0; p < first.probes.size(); ++p) {
    const Quantity& q = first.probes[p];
    if (static_cast<int>(p) == xi || q.name == "lambda") continue;
    render::PlotSpec spec;
    spec.title = q.label + (runs.size() == 1 ? " — " + first.scene_name : "");
    spec.x_label = xi >= 0 ? render::axis_title(first.probes[xi])
                           : "time" + (first.time_unit.empty() ? std::string() : " [" + first.time_unit + "]");
    spec.y_label = render::axis_title(q);
    for (const LabelledRun& r : runs) {
      // match probes by name: runs of different models may order them differently
      const int k = probe_index(r.info, q.name);
      const int kx = r.info.plot_x_probe.empty() ? -1 : probe_index(r.info, r.info.plot_x_probe);
      if (k < 0 || k >= static_cast<int>(r.history.probes.size())) continue;
      const std::vector<double>& x = kx >= 0 ? r.history.probes[kx] : r.history.time;
      spec.series.push_back({r.label, x, r.history.probes[k], false});
      for (const ReferenceSeries& ref : r.info.references)
        if (ref.y_probe == q.name && (xi < 0 || ref.x_probe == first.probes[xi].name))
          spec.series.push_back({ref.label, ref.x, ref.y, true});
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
