#pragma once
/// \file mesh_picture.h
/// A picture of a mesh with coloured and labelled items on it, headless: `flexframe check
/// --picture` draws a scene's structure with its parts, its mesh's named groups and the node sets
/// its supports, loads and probes select, so a user sees what the names select before a run.
/// Plain arrays in (render/ never sees the scene or the model); world coordinates p_W; colours RGB
/// in [0, 1].
///
/// What it shows:
///  - the quads, lit, in a neutral light grey where no item fills them, with thin element edges
///    when elements are large enough on screen to read them;
///  - each item's quads filled with its colour (a later item over an earlier one);
///  - each item's nodes as dots of its colour, and the mesh edges joining two of them as thick
///    lines (so a selected edge reads as a line); at a node an earlier item marks too, the dot is
///    smaller and drawn over the earlier one, so every item at a shared node stays visible (rings);
///    dots and lines behind a surface show through it faintly (30 % opacity, in a layer above);
///  - each item's label in a framed box next to its anchor point, with a leader line (on a white
///    halo) to it, the boxes placed so that they overlap neither one another, nor the dots, nor
///    the title and axes (place_labels);
///  - a legend at the right (a colour swatch and the legend line of each item), the title and
///    a subtitle at the top left, x/y/z axes at the bottom left;
///  - an isometric parallel view with +z up, from (1, -1, 1) unless another of (±1, ±1, 1) shows
///    more than twice the mesh's area (a plate edge-on from there), fitted to its projected extent
///    in the area left of the legend and below the title, with room around it for the labels;
///    white background. The same picture gives the same bytes.

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "render/graphics_context.h"

namespace ff::render {

/// One coloured thing in the picture: a part, a named group, a scene's selection.
struct PictureItem {
  std::string label;   ///< written next to the anchor; "" = no label on the picture
  std::string legend;  ///< its legend line (e.g. the label and its node count); "" = not listed
  std::array<double, 3> color{0.5, 0.5, 0.5};
  std::vector<std::int32_t> quads;  ///< quads it fills with its colour (indices into MeshPicture::quads / 4)
  std::vector<std::int32_t> nodes;  ///< points it marks with dots
  std::int32_t anchor = -1;         ///< the point its label points at; -1 = no label
};

struct MeshPicture {
  std::vector<double> points;       ///< 3 coordinates per point
  std::vector<std::int32_t> quads;  ///< 4 point indices per quad
  std::vector<PictureItem> items;   ///< in drawing and legend order
  std::string title;                ///< top left, bold; "" = none
  std::string subtitle;             ///< the line below the title; "" = none
  int width = 1280, height = 960;   ///< pixels
};

/// The colour of quads no item fills.
inline constexpr std::array<double, 3> kPictureMeshColor{0.84, 0.85, 0.87};
/// The k-th colour of a palette of ten strong, well distinguished colours (k taken modulo ten),
/// mixed with white by `tint` in [0, 1]: 0 for dots and lines, lighter for filled areas (e.g. 0.3
/// for a named surface, 0.55 for the parts beneath everything).
std::array<double, 3> picture_color(int k, double tint = 0.0);

/// Draws `picture` into png_path. False, with the reason in *error (if non-null), for indices
/// out of range, non-finite points, a size below 64 x 64, no graphics, or a file that cannot be
/// written (nothing is left at png_path then).
bool write_mesh_picture(GraphicsContext& gc, const MeshPicture& picture, const std::string& png_path,
                        std::string* error);

// ---- label placement (pure, tested without GL) ------------------------------------------------

/// An axis-aligned rectangle in pixels (x right, y up).
struct PixelBox {
  double x0 = 0, y0 = 0, x1 = 0, y1 = 0;
  bool overlaps(const PixelBox& o) const { return x0 < o.x1 && o.x0 < x1 && y0 < o.y1 && o.y0 < y1; }
};

/// Where each label box goes: box i (of size sizes[i], width and height) near anchors[i], tried
/// around the anchor at growing distances, first on the side away from `centre` (the picture of
/// the mesh), and taken where it lies inside `area` and overlaps neither an earlier box, nor a box
/// of `occupied` (the title, the axes), nor another label's anchor. When no place is free, the
/// place with the least overlap. Returns the boxes, in the order of `anchors`.
std::vector<PixelBox> place_labels(const std::vector<std::array<double, 2>>& anchors,
                                   const std::vector<std::array<double, 2>>& sizes, std::array<double, 2> centre,
                                   const PixelBox& area, const std::vector<PixelBox>& occupied = {});

}  // namespace ff::render
