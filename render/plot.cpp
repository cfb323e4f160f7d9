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

void style_axis(vtkAxis* axis, const std::string& title, bool log, double font_px) {
  const double ink[3] = {0.10, 0.10, 0.12};
  axis->SetTitle(title);
  axis->SetLogScale(log);
  set_text_style(axis->GetTitleProperties(), font_px, ink, true);
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
  set_text_style(chart->GetTitleProperties(), 1.25 * font_px, ink, true);
  style_axis(chart->GetAxis(vtkAxis::BOTTOM), spec.x_label, spec.log_x, font_px);
  style_axis(chart->GetAxis(vtkAxis::LEFT), spec.y_label, spec.log_y, font_px);

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
    }
    if (xs->GetNumberOfTuples() == 0) continue;
    table->AddColumn(xs);
    table->AddColumn(ys);
    vtkPlot* plot = chart->AddPlot(s.markers_only ? vtkChart::POINTS : vtkChart::LINE);
    plot->SetInputData(table, 0, 1);
    const double* c = kPalette[k % kPaletteSize];
    plot->SetColor(c[0], c[1], c[2]);
    plot->SetWidth(s.markers_only ? 1.5f : 2.5f);
    if (auto* points = vtkPlotPoints::SafeDownCast(plot)) {
      points->SetMarkerStyle(s.markers_only ? vtkPlotPoints::CIRCLE : vtkPlotPoints::NONE);
      points->SetMarkerSize(static_cast<float>(0.6 * font_px));
    }
  }
  chart->SetShowLegend(spec.series.size() > 1);
  if (spec.series.size() > 1) {
    set_text_style(chart->GetLegend()->GetLabelProperties(), 0.9 * font_px, ink, false);
    chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
    chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
  }

  vtkNew<vtkContextScene> scene;
  scene->AddItem(chart);
  vtkNew<vtkContextActor> actor;
  actor->SetScene(scene);
  vtkNew<vtkRenderer> renderer;
  renderer->SetBackground(1.0, 1.0, 1.0);
  renderer->AddActor(actor);
  surface.window()->AddRenderer(renderer);

  // vtkChartXY applies a log axis to its plots only after it has laid out once
  surface.window()->Render();
  std::string why;
  // the surface, declared first, is destroyed last: it frees the GL objects of all of the above
  return surface.render_to_png(png_path, &why) ? true : fail(why);
}

}  // namespace ff::render
