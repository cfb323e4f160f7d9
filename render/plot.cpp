#include "render/plot.h"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextActor.h>
#include <vtkContextScene.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkBrush.h>
#include <vtkPlot.h>
#include <vtkPlotArea.h>
#include <vtkPlotPoints.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkStringArray.h>
#include <vtkTable.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

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

int vtk_pen_style(LineDash d) {
  switch (d) {
    case LineDash::dashed: return vtkPen::DASH_LINE;
    case LineDash::dotted: return vtkPen::DOT_LINE;
    case LineDash::dash_dot: return vtkPen::DASH_DOT_LINE;
    case LineDash::solid: break;
  }
  return vtkPen::SOLID_LINE;
}

int vtk_marker(MarkerShape m) {
  switch (m) {
    case MarkerShape::square: return vtkPlotPoints::SQUARE;
    case MarkerShape::diamond: return vtkPlotPoints::DIAMOND;
    case MarkerShape::cross: return vtkPlotPoints::CROSS;
    case MarkerShape::plus: return vtkPlotPoints::PLUS;
    case MarkerShape::circle:
    case MarkerShape::none: break;
  }
  return vtkPlotPoints::CIRCLE;
}

constexpr double kGrey[3] = {0.55, 0.55, 0.58};

// a data value's position along an axis drawn from p1 to p2 (pixels) over [lo, hi] (data values)
double to_pixel(double v, double lo, double hi, double p1, double p2, bool log) {
  if (log) {
    v = std::log10(v);
    lo = std::log10(lo);
    hi = std::log10(hi);
  }
  return hi > lo ? p1 + (v - lo) / (hi - lo) * (p2 - p1) : p1;
}

}  // namespace

std::string axis_title(const Quantity& q) {
  std::string s = q.label.empty() ? q.name : q.label;
  if (!q.unit.empty()) s.append(" [").append(q.unit).append("]");
  return s;
}

bool write_plot_png(GraphicsContext& gc, const PlotSpec& spec, const std::string& png_path,
                    std::string* error, PlotDrawn* drawn) {
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
  RenderSurface surface(gc.state(), spec.width, spec.height);
  if (!surface.ok()) return fail(surface.error());

  const double font_px = std::max(11.0, std::round(std::min(spec.width, spec.height) / 38.0));
  const double ink[3] = {0.10, 0.10, 0.12};
  vtkNew<vtkChartXY> chart;
  chart->SetTitle(spec.title);
  set_text_style(chart->GetTitleProperties(), fitting_font(spec.title, 0.94 * spec.width, 1.25 * font_px), ink, true);
  style_axis(chart->GetAxis(vtkAxis::BOTTOM), spec.x_label, spec.log_x, font_px, 0.85 * spec.width);
  style_axis(chart->GetAxis(vtkAxis::LEFT), spec.y_label, spec.log_y, font_px, 0.75 * spec.height);
  double y_lo = INFINITY, y_hi = -INFINITY;  // of what is drawn, for the legend's headroom
  std::size_t curves = 0;

  std::size_t bands = 0;
  for (const PlotBand& b : spec.bands) {  // under the curves: added first, painted first
    if (b.lo.size() != b.x.size() || b.hi.size() != b.x.size())
      return fail("plot band '" + b.label + "' has " + std::to_string(b.x.size()) + " x values but " +
                  std::to_string(b.lo.size()) + " lower and " + std::to_string(b.hi.size()) + " upper values");
    vtkNew<vtkTable> table;
    vtkNew<vtkDoubleArray> xs, lo, hi;
    xs->SetName("x");
    lo->SetName("lo");
    hi->SetName("hi");
    for (std::size_t i = 0; i < b.x.size(); ++i) {
      if (!keep_point(b.x[i], b.lo[i], spec) || !keep_point(b.x[i], b.hi[i], spec)) continue;
      xs->InsertNextValue(b.x[i]);
      lo->InsertNextValue(b.lo[i]);
      hi->InsertNextValue(b.hi[i]);
      y_lo = std::min(y_lo, b.lo[i]);
      y_hi = std::max(y_hi, b.hi[i]);
    }
    if (xs->GetNumberOfTuples() < 2) continue;
    table->AddColumn(xs);
    table->AddColumn(lo);
    table->AddColumn(hi);
    auto* area = vtkPlotArea::SafeDownCast(chart->AddPlot(vtkChart::AREA));
    if (!area) return fail("plot band '" + b.label + "': this VTK cannot draw an area");
    area->SetInputData(table);
    area->SetInputArray(0, "x");
    area->SetInputArray(1, "lo");
    area->SetInputArray(2, "hi");
    area->SetLabel(b.label);
    const double* c = kPalette[b.colour_of % kPaletteSize];
    area->SetColor(static_cast<unsigned char>(255 * c[0]), static_cast<unsigned char>(255 * c[1]),
                   static_cast<unsigned char>(255 * c[2]), 64);  // a light shade: the curves stay readable over it
    ++bands;
  }

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
    ++curves;
    const double* c = s.grey ? kGrey : kPalette[k % kPaletteSize];
    plot->SetColor(c[0], c[1], c[2]);
    plot->SetWidth(markers ? 1.5f : 2.5f);
    if (!markers) plot->GetPen()->SetLineType(vtk_pen_style(s.dash));
    if (auto* points = vtkPlotPoints::SafeDownCast(plot)) {
      points->SetMarkerStyle(markers ? vtk_marker(s.marker) : vtkPlotPoints::NONE);
      points->SetMarkerSize(static_cast<float>((s.marker == MarkerShape::none ? 0.6 : 0.8) * font_px));
    }
    // a line's markers: about a dozen of its points, starting at an offset of its own so that
    // the markers of coinciding curves sit side by side instead of on top of each other
    if (!markers && s.marker != MarkerShape::none) {
      const vtkIdType n = xs->GetNumberOfTuples();
      const vtkIdType stride = std::max<vtkIdType>(4, n / 12);
      const vtkIdType offset = (static_cast<vtkIdType>(k) * std::max<vtkIdType>(1, stride / 4)) % stride;
      vtkNew<vtkTable> marks;
      vtkNew<vtkDoubleArray> mx, my;
      mx->SetName("x");
      my->SetName((std::string(ys->GetName()) + " markers").c_str());
      for (vtkIdType i = offset; i < n; i += stride) {
        mx->InsertNextValue(xs->GetValue(i));
        my->InsertNextValue(ys->GetValue(i));
      }
      marks->AddColumn(mx);
      marks->AddColumn(my);
      vtkPlot* mp = chart->AddPlot(vtkChart::POINTS);
      mp->SetInputData(marks, 0, 1);
      mp->SetColor(c[0], c[1], c[2]);
      mp->SetWidth(1.5f);
      mp->SetLegendVisibility(false);
      if (auto* points = vtkPlotPoints::SafeDownCast(mp)) {
        points->SetMarkerStyle(vtk_marker(s.marker));
        points->SetMarkerSize(static_cast<float>(0.8 * font_px));
      }
    }
  }
  if (std::isfinite(spec.x_min) && std::isfinite(spec.x_max) && spec.x_max > spec.x_min && !spec.log_x) {
    vtkAxis* x = chart->GetAxis(vtkAxis::BOTTOM);
    x->SetRange(spec.x_min, spec.x_max);
    x->SetBehavior(vtkAxis::FIXED);
  }
  if (!spec.x_ticks.empty()) {
    vtkNew<vtkDoubleArray> positions;
    vtkNew<vtkStringArray> labels;
    for (double t : spec.x_ticks) {
      char text[32];
      std::snprintf(text, sizeof text, "%g", t);
      positions->InsertNextValue(t);
      labels->InsertNextValue(text);
    }
    chart->GetAxis(vtkAxis::BOTTOM)->SetCustomTickPositions(positions, labels);
  }
  chart->SetShowLegend(spec.series.size() + bands > 1);
  bool legend_inside = false;
  if (spec.series.size() + bands > 1) {
    set_text_style(chart->GetLegend()->GetLabelProperties(), 0.9 * font_px, ink, false);
    chart->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
    chart->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);
    // headroom above the data for the legend box (one row per series), so it covers no curve
    const double plot_px = spec.height - 7.0 * font_px;
    const double legend_px = (1.5 * static_cast<double>(spec.series.size() + bands) + 1.0) * font_px;
    vtkAxis* y = chart->GetAxis(vtkAxis::LEFT);
    const double f = legend_px / plot_px;
    if (std::isfinite(y_lo) && plot_px > 2.0 * legend_px) {
      if (spec.log_y && y_lo > 0) {
        // headroom on a log axis grows with the decades the data span: for errors from 1e-3 % to
        // 159 % it ran the axis to 1e6 %. Beyond one decade above the data the legend goes beside.
        const double lo = std::log10(y_lo), hi = std::log10(y_hi), span = std::max(hi - lo, 1.0);
        const double headroom = span * f / (1.0 - f);
        legend_inside = headroom <= 1.0;
        y->SetUnscaledRange(std::pow(10.0, lo - 0.05 * span),
                            std::pow(10.0, hi + (legend_inside ? headroom : 0.05 * span)));
      } else if (!spec.log_y) {
        const double span = y_hi > y_lo ? y_hi - y_lo : std::max(std::abs(y_hi), 1.0);
        y->SetRange(y_lo - 0.05 * span, y_hi + span * (f / (1.0 - f) + 0.05));
        legend_inside = true;
      }
      y->SetBehavior(vtkAxis::FIXED);
    }
    if (!legend_inside) chart->GetLegend()->SetInline(false);  // beside the plot area, right
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

  // point labels: placed in pixels from the axes as laid out by the render above
  std::size_t labels = 0;
  vtkAxis* xa = chart->GetAxis(vtkAxis::BOTTOM);
  vtkAxis* ya = chart->GetAxis(vtkAxis::LEFT);
  std::vector<vtkSmartPointer<vtkTextActor>> texts;
  const double label_ink[3] = {0.15, 0.15, 0.18};
  for (const PlotSeries& s : spec.series) {
    if (s.point_labels.size() != s.x.size()) continue;
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      if (s.point_labels[i].empty() || !keep_point(s.x[i], s.y[i], spec)) continue;
      const double px = to_pixel(s.x[i], xa->GetUnscaledMinimum(), xa->GetUnscaledMaximum(), xa->GetPoint1()[0],
                                 xa->GetPoint2()[0], spec.log_x);
      const double py = to_pixel(s.y[i], ya->GetUnscaledMinimum(), ya->GetUnscaledMaximum(), ya->GetPoint1()[1],
                                 ya->GetPoint2()[1], spec.log_y);
      auto& t = texts.emplace_back(vtkSmartPointer<vtkTextActor>::New());
      t->SetInput(s.point_labels[i].c_str());
      set_text_style(t->GetTextProperty(), 0.8 * font_px, label_ink, false);
      // right of the point, or left of it where the text would run off the image
      std::size_t glyphs = 0;
      for (unsigned char c : s.point_labels[i]) glyphs += (c & 0xC0) != 0x80;
      const double text_px = 0.6 * 0.8 * font_px * static_cast<double>(glyphs);
      const double left = px + 0.5 * font_px + text_px < spec.width - 4.0 ? px + 0.5 * font_px
                                                                          : px - 0.5 * font_px - text_px;
      t->SetDisplayPosition(static_cast<int>(std::max(2.0, left)), static_cast<int>(py + 0.3 * font_px));
      renderer->AddActor2D(t);
      ++labels;
    }
  }
  if (drawn) {
    drawn->y_min = ya->GetUnscaledMinimum();
    drawn->y_max = ya->GetUnscaledMaximum();
    drawn->x_min = xa->GetUnscaledMinimum();
    drawn->x_max = xa->GetUnscaledMaximum();
    drawn->legend_inside = legend_inside;
    drawn->curves = curves;
    drawn->bands = bands;
    drawn->point_labels = labels;
  }
  std::string why;
  // the surface, declared first, is destroyed last: it frees the GL objects of all of the above
  return surface.render_to_png(png_path, &why) ? true : fail(why);
}

}  // namespace ff::render
