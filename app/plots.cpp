#include "app/plots.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>

#include "core/frame/file_name.h"
#include "render/graphics_context.h"
#include "render/plot.h"

namespace ff::app {

void PlotHistory::add(const Frame& f) {
  time.push_back(f.time);
  if (probes.size() < f.probes.size()) probes.resize(f.probes.size());
  for (std::size_t i = 0; i < f.probes.size(); ++i) probes[i].push_back(f.probes[i]);
}

namespace {

int probe_index(const RunInfo& info, const std::string& name) {
  for (std::size_t k = 0; k < info.probes.size(); ++k)
    if (info.probes[k].name == name) return static_cast<int>(k);
  return -1;
}

// a run's x (its load probe for statics, else time) and its series of `probe`; nullptrs if absent
std::pair<const std::vector<double>*, const std::vector<double>*> run_series(const LabelledRun& r,
                                                                            const std::string& probe) {
  const int k = probe_index(r.info, probe);
  if (k < 0 || k >= static_cast<int>(r.history.probes.size())) return {nullptr, nullptr};
  const int kx = r.info.plot_x_probe.empty() ? -1 : probe_index(r.info, r.info.plot_x_probe);
  const std::vector<double>& x = kx >= 0 && kx < static_cast<int>(r.history.probes.size()) ? r.history.probes[kx]
                                                                                           : r.history.time;
  return {&x, &r.history.probes[k]};
}

// probes to plot: those of every run, first run's order first; not the x probe nor lambda
std::vector<std::pair<std::string, Quantity>> plotted_probes(const std::vector<LabelledRun>& runs) {
  std::vector<std::pair<std::string, Quantity>> out;
  for (const LabelledRun& r : runs)
    for (const Quantity& q : r.info.probes) {
      if (q.name == r.info.plot_x_probe || q.name == "lambda") continue;
      if (std::none_of(out.begin(), out.end(), [&](const auto& p) { return p.first == q.name; }))
        out.emplace_back(q.name, q);
    }
  return out;
}

// linear interpolation in a non-decreasing x (x within its range)
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at) {
  const auto it = std::lower_bound(x.begin(), x.end(), at);
  const std::size_t j = static_cast<std::size_t>(it - x.begin());
  if (j < x.size() && x[j] == at) return y[j];
  if (j == 0) return y.front();
  if (j >= x.size()) return y.back();
  const double w = (at - x[j - 1]) / (x[j] - x[j - 1]);
  return y[j - 1] + w * (y[j] - y[j - 1]);
}

}  // namespace

double max_abs_difference(const std::vector<double>& xa, const std::vector<double>& ya, const std::vector<double>& xb,
                          const std::vector<double>& yb, double* lo_out, double* hi_out) {
  const auto usable = [](const std::vector<double>& x, const std::vector<double>& y) {
    if (x.empty() || x.size() != y.size()) return false;
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!std::isfinite(x[i]) || (i > 0 && x[i] < x[i - 1])) return false;
    return true;
  };
  if (!usable(xa, ya) || !usable(xb, yb)) return NAN;
  const double lo = std::max(xa.front(), xb.front()), hi = std::min(xa.back(), xb.back());
  if (lo > hi) return NAN;
  if (lo_out) *lo_out = lo;
  if (hi_out) *hi_out = hi;
  double worst = NAN;
  const auto visit = [&](const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& ox,
                         const std::vector<double>& oy) {
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (x[i] < lo || x[i] > hi) continue;
      const double d = std::abs(y[i] - interpolate(ox, oy, x[i]));
      if (std::isfinite(d) && (std::isnan(worst) || d > worst)) worst = d;  // samples after a divergence are skipped
    }
  };
  visit(xa, ya, xb, yb);
  visit(xb, yb, xa, ya);
  return worst;
}

std::vector<ProbeBand> richardson_bands(const LabelledRun& run, const LabelledRun& twin, double ratio,
                                        const std::string& label) {
  std::vector<ProbeBand> out;
  if (!(ratio > 1.0)) return out;
  const double denominator = ratio * ratio - 1.0;  // (R3) with p = 2
  const auto monotone = [](const std::vector<double>& x) {
    for (std::size_t i = 0; i < x.size(); ++i)
      if (!std::isfinite(x[i]) || (i > 0 && x[i] < x[i - 1])) return false;
    return !x.empty();
  };
  for (const auto& [name, q] : plotted_probes({run})) {
    const auto [x, y] = run_series(run, name);
    const auto [tx, ty] = run_series(twin, name);
    if (!x || !tx || x->size() != y->size() || tx->size() != ty->size() || !monotone(*x) || !monotone(*tx)) continue;
    ProbeBand b;
    b.probe = name;
    b.label = label;
    for (std::size_t i = 0; i < x->size(); ++i) {
      const double at = (*x)[i];
      if (at < tx->front() || at > tx->back()) continue;
      const double e = (interpolate(*tx, *ty, at) - (*y)[i]) / denominator;
      const double half = 3.0 * std::abs(e);  // (R4), F_s = 3
      if (!std::isfinite(half)) continue;
      b.x.push_back(at);
      b.lo.push_back((*y)[i] - half);
      b.hi.push_back((*y)[i] + half);
    }
    if (b.x.size() >= 2) out.push_back(std::move(b));
  }
  return out;
}

std::vector<ProbeDelta> overlay_deltas(const std::vector<LabelledRun>& runs) {
  std::vector<ProbeDelta> out;
  for (const auto& [name, q] : plotted_probes(runs)) {
    ProbeDelta d;
    d.probe = name;
    d.unit = q.unit;
    std::size_t having = 0;
    for (std::size_t a = 0; a < runs.size(); ++a) {
      const auto [xa, ya] = run_series(runs[a], name);
      if (!xa) continue;
      ++having;
      for (std::size_t b = a + 1; b < runs.size(); ++b) {
        const auto [xb, yb] = run_series(runs[b], name);
        if (!xb) continue;
        double lo = NAN, hi = NAN;
        const double m = max_abs_difference(*xa, *ya, *xb, *yb, &lo, &hi);
        if (std::isfinite(m) && !(m <= d.max_abs)) {
          d.max_abs = m;
          d.run_a = runs[a].label;
          d.run_b = runs[b].label;
          d.x_lo = lo;
          d.x_hi = hi;
        }
      }
    }
    if (having >= 2) out.push_back(d);
  }
  return out;
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
  // statics plot against a load probe, dynamics against time
  const int xi = first.plot_x_probe.empty() ? -1 : probe_index(first, first.plot_x_probe);
  const std::vector<ProbeDelta> deltas = runs.size() > 1 ? overlay_deltas(runs) : std::vector<ProbeDelta>{};
  // a run's look: dash pattern and marker shape as well as colour, so coinciding curves stay visible
  constexpr render::LineDash kDashes[] = {render::LineDash::solid, render::LineDash::dashed, render::LineDash::dotted,
                                          render::LineDash::dash_dot};
  constexpr render::MarkerShape kMarkers[] = {render::MarkerShape::circle, render::MarkerShape::square,
                                              render::MarkerShape::diamond, render::MarkerShape::cross,
                                              render::MarkerShape::plus};
  for (const auto& [name, q] : plotted_probes(runs)) {
    render::PlotSpec spec;
    spec.title = q.label.empty() ? q.name : q.label;
    if (runs.size() == 1) spec.title += " — " + first.scene_name;
    for (const ProbeDelta& d : deltas)
      if (d.probe == name && std::isfinite(d.max_abs)) {
        char b[64];
        std::snprintf(b, sizeof b, "%.3g", d.max_abs);
        spec.title += std::string(" — max |Δ| ") + b + (d.unit.empty() ? "" : " " + d.unit);
      }
    spec.x_label = xi >= 0 ? render::axis_title(first.probes[xi])
                           : "time" + (first.time_unit.empty() ? std::string() : " [" + first.time_unit + "]");
    spec.y_label = render::axis_title(q);
    for (std::size_t n = 0; n < runs.size(); ++n) {
      const LabelledRun& r = runs[n];
      // match probes by name: runs of different models may order them differently
      const auto [x, y] = run_series(r, name);
      if (!x) continue;
      for (const ProbeBand& b : r.bands)
        if (b.probe == name) spec.bands.push_back({b.label, b.x, b.lo, b.hi, spec.series.size()});
      render::PlotSeries series{r.label, *x, *y, false};
      if (runs.size() > 1) {
        series.dash = kDashes[n % std::size(kDashes)];
        series.marker = kMarkers[n % std::size(kMarkers)];
      }
      spec.series.push_back(std::move(series));
      for (const ReferenceSeries& ref : r.info.references)
        if (ref.y_probe == name && (xi < 0 || ref.x_probe == first.probes[xi].name))
          spec.series.push_back({ref.label, ref.x, ref.y, true});
    }
    if (spec.series.empty()) continue;
    // a name becomes a file name only once it is known to be one (results files are checked on
    // reading, scenes at their key: this is the last word)
    if (const std::string why = file_name_problem(name); !why.empty()) {
      if (error && error->empty()) *error = "probe name '" + name + "' " + why + ": no plot file made for it";
      continue;
    }
    const std::string file = name + ".png";
    std::string e;
    if (render::write_plot_png(*gc, spec, (std::filesystem::path(dir) / file).string(), &e))
      written.push_back("plots/" + file);
    else if (error && error->empty())
      *error = e;
  }
  return written;
}

}  // namespace ff::app
