#pragma once
/// \file plot.h
/// XY line/marker charts to PNG, headless, through the same GraphicsContext as frames
/// (VTK's vtkChartXY in a vtkContextActor; no VTK types here).

#include <string>
#include <vector>

#include "core/frame/frame.h"
#include "render/graphics_context.h"

namespace ff::render {

/// One curve. x and y have equal length; points with a non-finite coordinate (or a
/// non-positive one on a log axis) are left out.
struct PlotSeries {
  std::string label;  ///< legend entry
  std::vector<double> x, y;
  bool markers_only = false;  ///< markers without a connecting line (e.g. reference data)
};

/// A chart. Axis labels should carry their unit, e.g. "hub angle [deg]"; see axis_title().
struct PlotSpec {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  int width = 900, height = 600;  ///< image size in pixels
  bool log_x = false, log_y = false;
};

/// Writes spec as a PNG: white background, distinct colours per series (a fixed palette, in
/// order), a legend when there is more than one series, axis titles, chart title.
/// Returns false and fills *error (if non-null) when the spec is unusable (no series, x/y
/// length mismatch, no drawable point) or the file cannot be written.
bool write_plot_png(GraphicsContext& gc, const PlotSpec& spec, const std::string& png_path,
                    std::string* error);

/// "label [unit]" for an axis from a Quantity ("label" alone when the unit is empty).
std::string axis_title(const Quantity& q);

}  // namespace ff::render
