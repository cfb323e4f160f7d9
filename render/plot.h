#pragma once
/// \file plot.h
/// XY line/marker charts to PNG, headless, through the same GraphicsContext as frames
/// (VTK's vtkChartXY in a vtkContextActor; no VTK types here).

#include <cmath>
#include <string>
#include <vector>

#include "core/frame/frame.h"
#include "render/graphics_context.h"

namespace ff::render {

/// How a line is stroked: curves that coincide stay distinguishable by their dash pattern.
enum class LineDash { solid, dashed, dotted, dash_dot };
/// A marker's shape. For a line it marks about a dozen of its points (placed differently per
/// series, so that markers of coinciding curves do not cover each other); for a markers-only
/// series every point (`none` there means a circle).
enum class MarkerShape { none, circle, square, diamond, cross, plus };

/// One curve. x and y have equal length; points with a non-finite coordinate (or a
/// non-positive one on a log axis) are left out.
struct PlotSeries {
  std::string label;  ///< legend entry
  std::vector<double> x, y;
  bool markers_only = false;  ///< markers without a connecting line (e.g. reference data)
  LineDash dash = LineDash::solid;
  MarkerShape marker = MarkerShape::none;
  /// text drawn beside each point (empty, or one entry per point; an empty entry draws nothing)
  std::vector<std::string> point_labels{};
  /// a neutral grey instead of the palette colour of its position (e.g. a front drawn under markers)
  bool grey = false;
};

/// A shaded range drawn under the curves, between lo and hi at each x (e.g. a run's error bar along
/// its curve). Points with a non-finite value are left out.
struct PlotBand {
  std::string label;  ///< legend entry
  std::vector<double> x, lo, hi;
  std::size_t colour_of = 0;  ///< drawn in a light shade of this series' palette colour
};

/// A chart. Axis labels should carry their unit, e.g. "hub angle [deg]"; see axis_title().
struct PlotSpec {
  std::string title, x_label, y_label;
  std::vector<PlotSeries> series;
  int width = 900, height = 600;  ///< image size in pixels
  bool log_x = false, log_y = false;
  /// A fixed x axis range when both are finite (linear axis; e.g. room beside the first and last
  /// mode number); else the axis fits the data.
  double x_min = NAN, x_max = NAN;
  /// Tick positions on the x axis (e.g. whole mode numbers), labelled with %g; empty = automatic.
  std::vector<double> x_ticks{};
  std::vector<PlotBand> bands{};  ///< drawn first, under every series
};

/// What write_plot_png drew, read back from the chart (for tests and callers that report it).
struct PlotDrawn {
  double y_min = 0, y_max = 0;     ///< the y axis range as drawn (data values, also on a log axis)
  double x_min = 0, x_max = 0;     ///< the x axis range as drawn
  bool legend_inside = false;      ///< legend over the plot area (with headroom) rather than beside it
  std::size_t curves = 0;          ///< series drawn (a series without a drawable point is not)
  std::size_t point_labels = 0;    ///< point labels drawn
  std::size_t bands = 0;           ///< bands drawn (a band without a drawable point is not)
};

/// Writes spec as a PNG: white background, distinct colours per series (a fixed palette, in
/// order), a legend when there is more than one series, axis titles, chart title.
/// The legend sits in headroom above the data when that costs little axis range (a linear axis,
/// or at most a quarter of a log axis' decades); otherwise beside the plot area, so that a log
/// axis spans the data and no more.
/// Returns false and fills *error (if non-null) when the spec is unusable (no series, x/y
/// length mismatch, no drawable point) or the file cannot be written. *drawn, when given,
/// receives what was drawn.
bool write_plot_png(GraphicsContext& gc, const PlotSpec& spec, const std::string& png_path,
                    std::string* error, PlotDrawn* drawn = nullptr);

/// "label [unit]" for an axis from a Quantity ("label" alone when the unit is empty).
std::string axis_title(const Quantity& q);

}  // namespace ff::render
