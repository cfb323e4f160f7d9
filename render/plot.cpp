#include "render/plot.h"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextActor.h>
#include <vtkContextScene.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

#include <cmath>

#include "render/render_surface.h"
#include "render/text_style.h"

namespace ff::render {
namespace {

// well-separated hues, in the order series get them
constexpr double kPalette[][3] = {
    {0.122, 0.467, 0.706}, {0.890, 0.420, 0.055}, {0.173, 0.627, 0.173}, {0.839, 0.153, 0.157},
    {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294}, {0.890, 0.467, 0.761}, {0.400, 0.400, 0.400},
    {0.737, 0.741, 0.133}, {0.090, 0.745, 0.812}};
constexpr std::size_t kPaletteSize = sizeof kPalette / sizeof kPalette[0];

bool keep_point(double x, double y, const PlotSpec& spec) {
  if (!std::isfinite(x) || !std::isfinite(y)) return false;
  if (spec.log_x && !(x > 0)) return false;
  if (spec.log_y && !(y > 0)) return false;
  return true;
}

// the largest font size (<= font_px, >= 8 px) at which `text` fits in `room_px` (about 0.6 em per
// character for the sans-serif face): long titles and labels shrink instead of being cut off
double fitting_font(const std::string& text, double room_px, double font_px) {
  std::size_t glyphs = 0;
  for (unsigned char c : text) glyphs += (c & 0xC0) != 0x80;  // UTF-8: count code points
  if (glyphs == 0) return font_px;
  return std::max(8.0, std::min(font_px, room_px / (0.6 * static_cast<double>(glyphs))));
}

void style_axis(vtkAxis* axis, const std::string& title, bool log, double font_px, double room_px) {
  const double ink[3] = {0.10, 0.10, 0.12};
  axis->SetTitle(title);
  axis->SetLogScale(log);
  set_text_style(axis->GetTitleProperties(), fitting_font(title, room_px, font_px), ink, true);
  set_text_style(axis->GetLabelProperties(), 0.9 * font_px, ink, false);
  axis->GetGridPen()->SetColor(220, 220, 224, 255);
}

}  // namespace

std::string axis_title(const Quantity& q) {
  std::string s = q.label.empty() ? q.name : q.label;
  if (!q.unit.empty()) s.append(" [").append(q.unit).append("]");
  return s;
}

bool write_plot_png(GraphicsContext& gc, const PlotSpec& spec, const std::string& png_path,
                    std::string* error) {
  auto fail = [&](const std::string& why) {
    if (error) *error = why;
    return false;
  };
  if (spec.series.empty()) return fail("plot '" + spec.title + "' has no series");
  std::size_t drawable = 0;
  for (const PlotSeries& s : spec.series) {
    if (s.x.size() != s.y.size())
      return fail("plot series '" + s.label + "' has " + std::to_string(s.x.size()) +
                  " x values but " + std::to_string(s.y.size()) + " y values");
    for (std::size_t i = 0; i < s.x.size(); ++i) drawable += keep_point(s.x[i], s.y[i], spec);
  }
  if (drawable == 0) return fail("plot '" + spec.title + "' has no finite point to draw");

  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  RenderSurface surface(gc, spec.width, spec.height);
  if (!surface.ok()) return fail(surface.error());

  const double font_px = std::max(11.0, std::round(std::min(spec.width, spec.height) / 38.0));
  const double ink[3] = {0.10, 0.10, 0.12};
  vtkNew<vtkChartXY> chart;
  chart->SetTitle(spec.title);
  set_text_style(chart->GetTitleProperties(), fitting_font(spec.title, 0.94 * spec.width, 1.25 * font_px), ink, true);
  style_axis(chart->GetAxis(vtkAxis::BOTTOM), spec.x_label, spec.log_x, font_px, 0.85 * spec.width);
  style_axis(chart->GetAxis(vtkAxis::LEFT), spec.y_label, spec.log_y, font_px, 0.75 * spec.height);
  double y_lo = INFINITY, y_hi = -INFINITY;  // of what is drawn, for the legend's headroom

  for (std::size_t k = 0; k < spec.series.size(); ++k) {
    const PlotSeries& s = spec.series[k];
    vtkNew<vtkTable> table;
    vtkNew<vtkDoubleArray> xs, ys;
    xs->SetName("x");
    ys->SetName(s.label.empty() ? ("series " + std::to_string(k + 1)).c_str() : s.label.c_str());
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (!keep_point(s.x[i], s.y[i], spec)) continue;
      xs->InsertNextValue(s.x[i]);
      ys->InsertNextValue(s.y[i]);
      y_lo = std::min(y_lo, s.y[i]);
      y_hi = std::max(y_hi, s.y[i]);
    }
    if (xs->GetNumberOfTuples() == 0) continue;
    table->AddColumn(xs);
    table->AddColumn(ys);
    // a line needs two points: a single sample (a run that stopped at once) is drawn as a marker
    const bool markers = s.markers_only || xs->GetNumberOfTuples() < 2;
    vtkPlot* plot = chart->AddPlot(markers ? vtkChart::POINTS : vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    const double* c = kPalette[k % kPaletteSize];
    plot->SetColor(c[0], c[1], c[2]);
    plot->SetWidth(markers ? 1.5f : 2.5f);
    if (auto* points = vtkPlotPoints::SafeDownCast(plot)) {
      points->SetMarkerStyle(markers ? vtkPlotPoints::CIRCLE : vtkPlotPoints::NONE);
      points->SetMarkerSize(static_cast<float>(0.6 * font_px));
    }
  }
  chart->SetShowLegend(spec.series.size() > 1);
  if (spec.series.size() > 1) {
    set_text_style(chart->GetLegend()->GetLabelProperties(), 0.9 * font_px, ink, false);
    chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
    chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
    // headroom above the data for the legend box (one row per series), so it covers no curve
    const double plot_px = spec.height - 7.0 * font_px;
    const double legend_px = (1.5 * static_cast<double>(spec.series.size()) + 1.0) * font_px;
    if (std::isfinite(y_lo) && plot_px > 2.0 * legend_px) {
      const double f = legend_px / plot_px;
      vtkAxis* y = chart->GetAxis(vtkAxis::LEFT);
      if (spec.log_y && y_lo > 0) {
        const double lo = std::log10(y_lo), hi = std::log10(y_hi), span = std::max(hi - lo, 1.0);
        y->SetRange(std::pow(10.0, lo - 0.05 * span), std::pow(10.0, hi + span * f / (1.0 - f)));
      } else if (!spec.log_y) {
        const double span = y_hi > y_lo ? y_hi - y_lo : std::max(std::abs(y_hi), 1.0);
        y->SetRange(y_lo - 0.05 * span, y_hi + span * (f / (1.0 - f) + 0.05));
      }
      y->SetBehavior(vtkAxis::FIXED);
    }
  }

  vtkNew<vtkContextScene> scene;
  scene->AddItem(chart);
  vtkNew<vtkContextActor> actor;
  actor->SetScene(scene);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1.0, 1.0, 1.0);
  renderer->AddActor(actor);
  surface.window()->AddRenderer(renderer);

  // vtkChartXY applies a log axis to its plots only after it has laid out once, and the shift and
  // scale it gives values far from zero relative to their spread (an energy near 327 J varying by
  // 2 J): a single render leaves such a curve out (measured 2026-11-25)
  surface.window()->Render();
  std::string why;
  // the surface, declared first, is destroyed last: it frees the GL objects of all of the above
  return surface.render_to_png(png_path, &why) ? true : fail(why);
}

}  // namespace ff::render
