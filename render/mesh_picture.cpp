#include "render/mesh_picture.h"

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkMath.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <set>
#include <utility>

#include "render/render_surface.h"
#include "render/text_style.h"

namespace ff::render {

namespace {

using Vec2 = std::array<double, 2>;
using Rgb = std::array<double, 3>;

constexpr double kInk[3] = {0.10, 0.10, 0.12};
constexpr double kEdgeColor[3] = {0.42, 0.43, 0.47};
constexpr double kMinEdgePixels = 7.0;  // element edges when elements are at least this large on screen
// dots and lines of a selection; smaller for each earlier selection sharing its nodes
constexpr double kDotPixels = 14.0, kDotStepPixels = 4.5, kMinDotPixels = 4.0;
constexpr double kLinePixels = 5.0, kMinLinePixels = 2.0;
constexpr double kHiddenOpacity = 0.3;  // dots and lines behind a surface show through it this faintly

// Tableau's ten colours with its grey (the mesh's colour here) replaced by a dark teal
constexpr Rgb kPalette[10] = {{0.122, 0.467, 0.706}, {1.000, 0.498, 0.055}, {0.173, 0.627, 0.173},
                              {0.839, 0.153, 0.157}, {0.580, 0.404, 0.741}, {0.549, 0.337, 0.294},
                              {0.890, 0.467, 0.761}, {0.737, 0.741, 0.133}, {0.090, 0.745, 0.812},
                              {0.000, 0.420, 0.420}};

std::string invalid(const MeshPicture& p) {
  if (p.width < 64 || p.height < 64 || p.width > 16384 || p.height > 16384)
    return "picture size must be between 64 and 16384 pixels a side, got " + std::to_string(p.width) + "x" +
           std::to_string(p.height);
  if (p.points.size() % 3 != 0 || p.points.empty()) return "picture points: a non-empty multiple of 3 coordinates needed";
  if (p.quads.size() % 4 != 0) return "picture quads: a multiple of 4 point indices needed";
  const std::int64_t n = static_cast<std::int64_t>(p.points.size() / 3), nq = static_cast<std::int64_t>(p.quads.size() / 4);
  for (double x : p.points)
    if (!std::isfinite(x)) return "picture points: a coordinate is not finite";
  for (std::int32_t v : p.quads)
    if (v < 0 || v >= n) return "picture quads refer to point " + std::to_string(v) + " of " + std::to_string(n);
  for (const PictureItem& item : p.items) {
    for (std::int32_t q : item.quads)
      if (q < 0 || q >= nq) return "item '" + item.legend + "' refers to quad " + std::to_string(q) + " of " + std::to_string(nq);
    for (std::int32_t v : item.nodes)
      if (v < 0 || v >= n) return "item '" + item.legend + "' refers to point " + std::to_string(v) + " of " + std::to_string(n);
    if (item.anchor < -1 || item.anchor >= n)
      return "item '" + item.legend + "' has its anchor at point " + std::to_string(item.anchor) + " of " + std::to_string(n);
  }
  return "";
}

Rgb darker(const Rgb& c, double f) { return {c[0] * f, c[1] * f, c[2] * f}; }

// a deep shade of c for lines and frames: its lightest channel brought to 0.55 (the tinted colours
// of filled areas would vanish against their own fill)
Rgb deep(const Rgb& c) {
  const double top = std::max({c[0], c[1], c[2], 1e-9});
  return darker(c, std::min(1.0, 0.55 / top));
}

// 2D geometry in pixels (vtkPolyDataMapper2D without a transform coordinate draws viewport pixels)
vtkSmartPointer<vtkActor2D> actor_2d(vtkPolyData* data, const Rgb& color, double opacity = 1.0, double line_px = 1.0) {
  vtkNew<vtkPolyDataMapper2D> mapper;
  mapper->SetInputData(data);
  auto actor = vtkSmartPointer<vtkActor2D>::New();
  actor->SetMapper(mapper);
  actor->GetProperty()->SetColor(color[0], color[1], color[2]);
  actor->GetProperty()->SetOpacity(opacity);
  actor->GetProperty()->SetLineWidth(static_cast<float>(line_px));
  return actor;
}

vtkSmartPointer<vtkPolyData> polygon_2d(const std::vector<Vec2>& corners, bool filled) {
  auto data = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> cells;
  for (const Vec2& c : corners) pts->InsertNextPoint(c[0], c[1], 0.0);
  cells->InsertNextCell(static_cast<vtkIdType>(corners.size() + (filled ? 0 : 1)));
  for (std::size_t i = 0; i < corners.size(); ++i) cells->InsertCellPoint(static_cast<vtkIdType>(i));
  if (!filled) cells->InsertCellPoint(0);  // closed outline
  data->SetPoints(pts);
  if (filled)
    data->SetPolys(cells);
  else
    data->SetLines(cells);
  return data;
}

vtkSmartPointer<vtkPolyData> polyline_2d(const std::vector<Vec2>& points) {
  auto data = vtkSmartPointer<vtkPolyData>::New();
  vtkNew<vtkPoints> pts;
  vtkNew<vtkCellArray> cells;
  cells->InsertNextCell(static_cast<vtkIdType>(points.size()));
  for (const Vec2& p : points) cells->InsertCellPoint(pts->InsertNextPoint(p[0], p[1], 0.0));
  data->SetPoints(pts);
  data->SetLines(cells);
  return data;
}

// a band of half width hw along p-q (a thick line as a polygon)
std::vector<Vec2> band(Vec2 p, Vec2 q, double hw) {
  const double dx = q[0] - p[0], dy = q[1] - p[1], len = std::max(std::hypot(dx, dy), 1e-9);
  const double nx = -dy / len * hw, ny = dx / len * hw;
  return {{p[0] + nx, p[1] + ny}, {p[0] - nx, p[1] - ny}, {q[0] - nx, q[1] - ny}, {q[0] + nx, q[1] + ny}};
}

std::vector<Vec2> box_corners(const PixelBox& b) { return {{b.x0, b.y0}, {b.x1, b.y0}, {b.x1, b.y1}, {b.x0, b.y1}}; }

std::vector<Vec2> circle_corners(Vec2 c, double r) {
  std::vector<Vec2> out;
  for (int k = 0; k < 16; ++k) {
    const double a = 2 * M_PI * k / 16;
    out.push_back({c[0] + r * std::cos(a), c[1] + r * std::sin(a)});
  }
  return out;
}

double overlap_area(const PixelBox& a, const PixelBox& b) {
  const double w = std::min(a.x1, b.x1) - std::max(a.x0, b.x0), h = std::min(a.y1, b.y1) - std::max(a.y0, b.y0);
  return w > 0 && h > 0 ? w * h : 0.0;
}

// the segment p-q passes through box b (Liang-Barsky clipping)
bool segment_hits(const PixelBox& b, Vec2 p, Vec2 q) {
  double t0 = 0, t1 = 1;
  const double d[2] = {q[0] - p[0], q[1] - p[1]};
  const double lo[2] = {b.x0, b.y0}, hi[2] = {b.x1, b.y1};
  for (int k = 0; k < 2; ++k) {
    if (std::fabs(d[k]) < 1e-12) {
      if (p[k] < lo[k] || p[k] > hi[k]) return false;
      continue;
    }
    double a = (lo[k] - p[k]) / d[k], c = (hi[k] - p[k]) / d[k];
    if (a > c) std::swap(a, c);
    t0 = std::max(t0, a);
    t1 = std::min(t1, c);
    if (t0 > t1) return false;
  }
  return true;
}

// the point of box b nearest to p
Vec2 nearest_on(const PixelBox& b, Vec2 p) { return {std::clamp(p[0], b.x0, b.x1), std::clamp(p[1], b.y0, b.y1)}; }

struct Picture {
  const MeshPicture& in;
  // Layers, each drawn over the one below. Within one layer VTK does not draw 2D props in the order
  // they were added (text came out beneath a polygon added before it), so whatever must lie over
  // something else goes into a layer above it.
  vtkNew<vtkRenderer> renderer;  // 0: the mesh and the dots where seen; legend, title, axes
  vtkNew<vtkRenderer> xray;      // 1: the dots again, faint, seen through the surfaces
  vtkNew<vtkRenderer> halos;     // 2: white halos of the leader lines
  vtkNew<vtkRenderer> leaders;   // 3: the leader lines
  vtkNew<vtkRenderer> boxes;     // 4: label boxes
  vtkNew<vtkRenderer> labels;    // 5: label frames and text
  std::unique_ptr<RenderSurface> surface;  // declared after the renderers: destroyed first (frees GL objects)
  std::string error;

  double margin = 0, text_px = 0, title_px = 0;
  double legend_width = 0, title_height = 0;
  struct {
    std::array<double, 3> focal_point{}, position{}, view_up{};
    double parallel_scale = 1;
  } camera;
  std::array<double, 3> mesh_centre{};  // the middle of the mesh as the picture shows it
  double pixel = 0;             // world length of one pixel
  std::array<double, 3> toward_eye{};  // unit vector from the mesh towards the eye
  std::vector<PixelBox> occupied;     // title and axes: no label there

  Picture(GraphicsContext& gc, const MeshPicture& p) : in(p) {
    surface = std::make_unique<RenderSurface>(gc.state(), p.width, p.height);
    if (!surface->ok()) error = surface->error();
  }
  ~Picture() { surface.reset(); }

  std::array<double, 3> point(std::int32_t i) const {
    return {in.points[3 * i], in.points[3 * i + 1], in.points[3 * i + 2]};
  }
  Vec2 to_display(const std::array<double, 3>& x) {
    renderer->SetWorldPoint(x[0], x[1], x[2], 1.0);
    renderer->WorldToDisplay();
    double d[3];
    renderer->GetDisplayPoint(d);
    return {d[0], d[1]};
  }
  vtkSmartPointer<vtkTextActor> text(const std::string& s, double size_px, bool bold) {
    auto t = vtkSmartPointer<vtkTextActor>::New();
    t->SetInput(s.c_str());
    set_text_style(t->GetTextProperty(), size_px, kInk, bold);
    t->GetPositionCoordinate()->SetCoordinateSystemToViewport();
    return t;
  }
  Vec2 text_size(vtkTextActor* t) {
    double size[2] = {0, 0};
    t->GetSize(renderer, size);
    return {size[0], size[1]};
  }

  void build_legend();
  std::array<double, 3> view_direction() const;  // from the mesh towards the eye, unit
  void build_camera();
  void build_surface();
  std::vector<std::vector<int>> depth;  // per item and node: how many earlier items mark the node
  static double dot_pixels(int d) { return std::max(kMinDotPixels, kDotPixels - kDotStepPixels * d); }
  // where a dot at depth d is drawn: moved towards the eye by more than the dots beneath
  std::array<double, 3> shifted(std::int32_t v, int d) const {
    auto x = point(v);
    const double s = pixel * (d + 1) * (0.5 * kDotPixels + 2.0);
    for (int c = 0; c < 3; ++c) x[c] += s * toward_eye[c];
    return x;
  }
  void build_markers();
  void build_labels();
  void build_title_and_axes();
};

void Picture::build_legend() {
  std::vector<const PictureItem*> rows;
  for (const PictureItem& item : in.items)
    if (!item.legend.empty()) rows.push_back(&item);
  legend_width = 0;
  if (rows.empty()) return;
  const double w = in.width, h = in.height;
  // the font shrinks (to 9 px) before the legend takes more than 40 % of the width or the height
  std::vector<vtkSmartPointer<vtkTextActor>> texts;
  double font = text_px, widest = 0;
  for (const PictureItem* item : rows) {
    texts.push_back(text(item->legend, font, false));
    widest = std::max(widest, text_size(texts.back())[0]);
  }
  const double room = 0.40 * w - 2 * margin - 1.6 * font;
  const double tall = 1.45 * font * static_cast<double>(rows.size()), room_h = h - 2 * margin;
  const double shrink = std::min({1.0, room / std::max(widest, 1.0), room_h / tall});
  if (shrink < 1.0) {
    font = std::max(9.0, std::floor(font * shrink));
    widest = 0;
    for (auto& t : texts) {
      set_text_style(t->GetTextProperty(), font, kInk, false);
      widest = std::max(widest, text_size(t)[0]);
    }
  }
  const double row = std::round(1.45 * font), swatch = std::round(0.8 * font);
  std::size_t shown = rows.size();
  if (row * static_cast<double>(shown) > room_h) {  // the rest summed up on the last line
    shown = static_cast<std::size_t>(std::max(1.0, std::floor(room_h / row) - 1));
    texts.resize(shown);
    texts.push_back(text("… and " + std::to_string(rows.size() - shown) + " more", font, false));
  }
  legend_width = std::min(0.45 * w, std::ceil(margin + swatch + 0.6 * font + widest + margin));
  const double x = w - legend_width + 0.5 * margin;
  double y = h - margin;
  for (std::size_t i = 0; i < texts.size(); ++i, y -= row) {
    const double mid = y - 0.5 * row;
    if (i < shown) {
      const PictureItem& item = *rows[i];
      // a square for what fills quads, a dot for what marks nodes
      const bool dot = item.quads.empty();
      const auto corners = dot ? circle_corners({x + 0.5 * swatch, mid}, 0.5 * swatch)
                               : box_corners({x, mid - 0.5 * swatch, x + swatch, mid + 0.5 * swatch});
      renderer->AddActor2D(actor_2d(polygon_2d(corners, true), item.color));
      renderer->AddActor2D(actor_2d(polygon_2d(corners, false), darker(item.color, 0.6)));
    }
    texts[i]->GetTextProperty()->SetVerticalJustificationToCentered();
    texts[i]->GetPositionCoordinate()->SetValue(x + swatch + 0.6 * font, mid);
    renderer->AddActor2D(texts[i]);
  }
}

std::array<double, 3> Picture::view_direction() const {
  const double r = 1 / std::sqrt(3.0);
  const std::array<std::array<double, 3>, 4> candidates = {{{r, -r, r}, {r, r, r}, {-r, -r, r}, {-r, r, r}}};
  std::array<double, 4> shown{};  // projected area of the quads, seen from each candidate
  for (std::size_t q = 0; q + 3 < in.quads.size(); q += 4) {
    const auto a = point(in.quads[q]), b = point(in.quads[q + 1]), c = point(in.quads[q + 2]), e = point(in.quads[q + 3]);
    const double u[3] = {c[0] - a[0], c[1] - a[1], c[2] - a[2]}, v[3] = {e[0] - b[0], e[1] - b[1], e[2] - b[2]};
    const double area[3] = {0.5 * (u[1] * v[2] - u[2] * v[1]), 0.5 * (u[2] * v[0] - u[0] * v[2]),
                            0.5 * (u[0] * v[1] - u[1] * v[0])};  // vector area of the quad
    for (std::size_t k = 0; k < candidates.size(); ++k)
      shown[k] += std::fabs(area[0] * candidates[k][0] + area[1] * candidates[k][1] + area[2] * candidates[k][2]);
  }
  const std::size_t best = static_cast<std::size_t>(std::max_element(shown.begin(), shown.end()) - shown.begin());
  return shown[0] >= 0.5 * shown[best] ? candidates[0] : candidates[best];
}

void Picture::build_camera() {
  // isometric, +z up: from (1, -1, 1), unless the mesh shows less than half the area there that it
  // shows from another of (±1, ±1, 1) (a plate in the plane x = -y is a line from (1, -1, 1)).
  // Fitted to the mesh as the picture shows it (its projected extent, not a sphere round it:
  // nothing moves here), in the area left of the legend and below the title, with room around it
  // for the labels.
  const std::array<double, 3> d = view_direction();
  double up[3] = {-d[2] * d[0], -d[2] * d[1], 1.0 - d[2] * d[2]};  // z made normal to d
  const double up_len = std::sqrt(up[0] * up[0] + up[1] * up[1] + up[2] * up[2]);
  for (double& c : up) c /= up_len;
  const double right[3] = {up[1] * d[2] - up[2] * d[1], up[2] * d[0] - up[0] * d[2], up[0] * d[1] - up[1] * d[0]};
  const std::size_t n = in.points.size() / 3;
  double lo[3] = {1e300, 1e300, 1e300}, hi[3] = {-1e300, -1e300, -1e300};  // along right, up, d
  for (std::size_t i = 0; i < n; ++i) {
    const double* x = &in.points[3 * i];
    const double c[3] = {x[0] * right[0] + x[1] * right[1] + x[2] * right[2], x[0] * up[0] + x[1] * up[1] + x[2] * up[2],
                         x[0] * d[0] + x[1] * d[1] + x[2] * d[2]};
    for (int k = 0; k < 3; ++k) lo[k] = std::min(lo[k], c[k]), hi[k] = std::max(hi[k], c[k]);
  }
  const double size = std::max({hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]});
  const double du = std::max(hi[0] - lo[0], 1e-9 * std::max(size, 1e-300)), dv = std::max(hi[1] - lo[1], 1e-9 * std::max(size, 1e-300));
  // the area in pixels (x right, y up) the mesh is fitted into
  const double x0 = margin, x1 = in.width - legend_width - margin;
  const double y0 = margin, y1 = in.height - title_height - margin;
  constexpr double kLabelRoom = 1.3;  // the mesh spans 1/1.3 of the area: labels fit around it
  const double scale = std::min((x1 - x0) / du, (y1 - y0) / dv) / kLabelRoom;  // pixels per world unit
  const double shift_u = (0.5 * (x0 + x1) - 0.5 * in.width) / scale, shift_v = (0.5 * (y0 + y1) - 0.5 * in.height) / scale;
  const double mid[3] = {0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1]), 0.5 * (lo[2] + hi[2])};
  const double distance = 2.0 * std::max(size, 1e-300) + 1.0;
  for (int k = 0; k < 3; ++k) {
    mesh_centre[k] = mid[0] * right[k] + mid[1] * up[k] + mid[2] * d[k];
    camera.focal_point[k] = mesh_centre[k] - shift_u * right[k] - shift_v * up[k];
    camera.position[k] = camera.focal_point[k] + distance * d[k];
    camera.view_up[k] = up[k];
    toward_eye[k] = d[k];
  }
  camera.parallel_scale = 0.5 * in.height / scale;
  pixel = 1.0 / scale;
  vtkCamera* cam = renderer->GetActiveCamera();
  cam->SetFocalPoint(camera.focal_point.data());
  cam->SetPosition(camera.position.data());
  cam->SetViewUp(camera.view_up.data());
  cam->SetParallelProjection(true);
  cam->SetParallelScale(camera.parallel_scale);
}

void Picture::build_surface() {
  const std::size_t n = in.points.size() / 3, nq = in.quads.size() / 4;
  if (nq == 0) return;
  // each quad's colour: the last item that fills it, else the mesh's grey
  std::vector<Rgb> color(nq, kPictureMeshColor);
  for (const PictureItem& item : in.items)
    for (std::int32_t q : item.quads) color[q] = item.color;
  vtkNew<vtkPoints> pts;
  pts->SetDataTypeToDouble();
  pts->SetNumberOfPoints(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i) pts->SetPoint(static_cast<vtkIdType>(i), &in.points[3 * i]);
  vtkNew<vtkCellArray> cells;
  vtkNew<vtkUnsignedCharArray> rgb;
  rgb->SetNumberOfComponents(3);
  rgb->SetName("colour");
  double edge_sum = 0;
  for (std::size_t q = 0; q < nq; ++q) {
    const vtkIdType ids[4] = {in.quads[4 * q], in.quads[4 * q + 1], in.quads[4 * q + 2], in.quads[4 * q + 3]};
    cells->InsertNextCell(4, ids);
    unsigned char c[3];
    for (int k = 0; k < 3; ++k) c[k] = static_cast<unsigned char>(std::lround(255.0 * std::clamp(color[q][k], 0.0, 1.0)));
    rgb->InsertNextTypedTuple(c);
    for (int k = 0; k < 4; ++k) {
      double a[3], b[3];
      pts->GetPoint(ids[k], a);
      pts->GetPoint(ids[(k + 1) % 4], b);
      edge_sum += std::sqrt(vtkMath::Distance2BetweenPoints(a, b));
    }
  }
  vtkNew<vtkPolyData> quads;
  quads->SetPoints(pts);
  quads->SetPolys(cells);
  quads->GetCellData()->SetScalars(rgb);
  vtkNew<vtkPolyDataNormals> normals;
  normals->SetInputData(quads);
  normals->ComputePointNormalsOn();
  normals->SplittingOn();  // folds and junction lines stay sharp
  normals->SetFeatureAngle(40.0);
  normals->ConsistencyOn();
  vtkNew<vtkPolyDataMapper> mapper;
  mapper->SetInputConnection(normals->GetOutputPort());
  mapper->SetScalarModeToUseCellData();
  mapper->SetColorModeToDirectScalars();
  vtkNew<vtkActor> actor;
  actor->SetMapper(mapper);
  vtkProperty* p = actor->GetProperty();
  p->SetAmbient(0.50);
  p->SetDiffuse(0.50);
  p->SetSpecular(0.0);
  if (edge_sum / (4.0 * static_cast<double>(nq)) >= kMinEdgePixels * pixel) {
    p->EdgeVisibilityOn();
    p->SetEdgeColor(kEdgeColor[0], kEdgeColor[1], kEdgeColor[2]);
  }
  renderer->AddActor(actor);
}

void Picture::build_markers() {
  const std::size_t n = in.points.size() / 3;
  // depth of a node in an item: how many earlier items mark it. Dots and lines at depth d are
  // smaller, and moved towards the eye (the view is parallel: the picture does not move) by more
  // than the dots beneath them: no dot is cut by its own surface, and a later item's dot lies on
  // an earlier one's as a smaller dot of its own colour
  std::vector<int> marked(n, 0);
  depth.assign(in.items.size(), {});
  for (std::size_t k = 0; k < in.items.size(); ++k) {
    std::vector<std::int32_t> nodes = in.items[k].nodes;
    std::sort(nodes.begin(), nodes.end());
    nodes.erase(std::unique(nodes.begin(), nodes.end()), nodes.end());
    for (std::int32_t v : in.items[k].nodes) depth[k].push_back(marked[v]);
    for (std::int32_t v : nodes) ++marked[v];
  }
  // mesh edges, once each, to find those joining two nodes of an item
  std::set<std::pair<std::int32_t, std::int32_t>> edges;
  for (std::size_t q = 0; q + 3 < in.quads.size(); q += 4)
    for (int k = 0; k < 4; ++k) {
      const std::int32_t a = in.quads[q + k], b = in.quads[q + (k + 1) % 4];
      edges.insert({std::min(a, b), std::max(a, b)});
    }
  for (std::size_t k = 0; k < in.items.size(); ++k) {
    const PictureItem& item = in.items[k];
    if (item.nodes.empty()) continue;
    std::vector<int> node_depth(n, -1);
    int deepest = 0;
    for (std::size_t j = 0; j < item.nodes.size(); ++j) {
      node_depth[item.nodes[j]] = depth[k][j];
      deepest = std::max(deepest, depth[k][j]);
    }
    for (int d = 0; d <= deepest; ++d) {
      // the item's dots at depth d, and its edges whose deeper end is at depth d
      vtkNew<vtkPoints> pts;
      pts->SetDataTypeToDouble();
      std::vector<vtkIdType> id(n, -1);
      auto id_of = [&](std::int32_t v) {
        if (id[v] < 0) {
          const auto x = shifted(v, d);
          id[v] = pts->InsertNextPoint(x.data());
        }
        return id[v];
      };
      vtkNew<vtkCellArray> verts, lines;
      for (std::size_t v = 0; v < n; ++v)
        if (node_depth[v] == d) {
          const vtkIdType i = id_of(static_cast<std::int32_t>(v));
          verts->InsertNextCell(1, &i);
        }
      for (const auto& [a, b] : edges)
        if (node_depth[a] >= 0 && node_depth[b] >= 0 && std::max(node_depth[a], node_depth[b]) == d) {
          const vtkIdType ab[2] = {id_of(a), id_of(b)};
          lines->InsertNextCell(2, ab);
        }
      auto add = [&](vtkCellArray* cells, bool as_lines) {
        if (cells->GetNumberOfCells() == 0) return;
        vtkNew<vtkPolyData> data;
        data->SetPoints(pts);
        (as_lines ? data->SetLines(cells) : data->SetVerts(cells));
        vtkNew<vtkPolyDataMapper> mapper;
        mapper->SetInputData(data);
        mapper->ScalarVisibilityOff();
        // drawn twice: solid where it is seen, and faint through the surfaces in the layer above
        for (const bool faint : {false, true}) {
          vtkNew<vtkActor> actor;
          actor->SetMapper(mapper);
          vtkProperty* p = actor->GetProperty();
          p->SetColor(item.color[0], item.color[1], item.color[2]);
          p->SetAmbient(0.45);
          p->SetDiffuse(0.55);
          p->SetOpacity(faint ? kHiddenOpacity : 1.0);
          if (as_lines) {
            p->SetLineWidth(static_cast<float>(std::max(kMinLinePixels, kLinePixels - 2.0 * d)));
            p->RenderLinesAsTubesOn();
          } else {
            p->SetPointSize(static_cast<float>(dot_pixels(d)));
            p->RenderPointsAsSpheresOn();
          }
          (faint ? xray : renderer)->AddActor(actor);
        }
      };
      add(lines, true);
      add(verts, false);
    }
  }
}

void Picture::build_labels() {
  std::vector<std::size_t> which;
  std::vector<Vec2> anchors, sizes;
  std::vector<vtkSmartPointer<vtkTextActor>> texts;
  const double pad = std::round(0.35 * text_px);
  for (std::size_t k = 0; k < in.items.size(); ++k) {
    const PictureItem& item = in.items[k];
    if (item.label.empty() || item.anchor < 0) continue;
    which.push_back(k);
    anchors.push_back(to_display(point(item.anchor)));
    texts.push_back(text(item.label, text_px, false));
    const Vec2 s = text_size(texts.back());
    sizes.push_back({s[0] + 2 * pad, s[1] + 2 * pad});
  }
  if (which.empty()) return;
  const Vec2 centre = to_display(mesh_centre);
  const PixelBox area{margin, margin, in.width - legend_width - 0.5 * margin, in.height - margin};
  // the dots stay uncovered too (every one up to 4000, then every k-th)
  std::vector<PixelBox> keep_free = occupied;
  std::size_t dots = 0;
  for (const PictureItem& item : in.items) dots += item.nodes.size();
  const std::size_t stride = std::max<std::size_t>(1, dots / 4000);
  const double r = 0.5 * kDotPixels;
  std::size_t count = 0;
  for (std::size_t k = 0; k < in.items.size(); ++k)
    for (std::int32_t v : in.items[k].nodes)
      if (count++ % stride == 0) {
        const Vec2 p = to_display(point(v));
        keep_free.push_back({p[0] - r, p[1] - r, p[0] + r, p[1] + r});
      }
  const std::vector<PixelBox> placed = place_labels(anchors, sizes, centre, area, keep_free);
  // leader lines, then the boxes over them; frames and text in the layer above (VTK draws a layer's
  // 2D polygons after its text, which would hide the text)
  for (std::size_t i = 0; i < which.size(); ++i) {
    const PictureItem& item = in.items[which[i]];
    // a deep shade of the item's colour on a white halo: it reads over its own filled quads too
    // (polygons: VTK draws 2D lines wider than a pixel as several thin ones)
    // from the rim of the anchor's dot (which stays visible) to the box
    const Vec2 end = nearest_on(placed[i], anchors[i]);
    const double length = std::hypot(end[0] - anchors[i][0], end[1] - anchors[i][1]);
    const double rim = item.nodes.empty() ? 0.0 : std::min(0.5 * kDotPixels + 1.0, length);
    const Vec2 start{anchors[i][0] + (end[0] - anchors[i][0]) * rim / std::max(length, 1e-9),
                     anchors[i][1] + (end[1] - anchors[i][1]) * rim / std::max(length, 1e-9)};
    halos->AddActor2D(actor_2d(polygon_2d(band(start, end, 2.5), true), {1.0, 1.0, 1.0}));
    leaders->AddActor2D(actor_2d(polygon_2d(band(start, end, 1.0), true), deep(item.color)));
  }
  for (std::size_t i = 0; i < which.size(); ++i) {
    const PictureItem& item = in.items[which[i]];
    boxes->AddActor2D(actor_2d(polygon_2d(box_corners(placed[i]), true), {1.0, 1.0, 1.0}));
    // a frame two pixels wide: two outlines of one pixel
    for (double inset : {0.5, 1.5}) {
      const PixelBox f{placed[i].x0 + inset, placed[i].y0 + inset, placed[i].x1 - inset, placed[i].y1 - inset};
      labels->AddActor2D(actor_2d(polygon_2d(box_corners(f), false), deep(item.color)));
    }
    texts[i]->GetTextProperty()->SetJustificationToLeft();
    texts[i]->GetTextProperty()->SetVerticalJustificationToBottom();
    texts[i]->GetPositionCoordinate()->SetValue(placed[i].x0 + pad, placed[i].y0 + pad);
    labels->AddActor2D(texts[i]);
  }
}

void Picture::build_title_and_axes() {
  double y = in.height - margin;
  auto line = [&](const std::string& s, double size, bool bold) {
    if (s.empty()) return;
    auto t = text(s, size, bold);
    t->GetTextProperty()->SetVerticalJustificationToTop();
    t->GetPositionCoordinate()->SetValue(margin, y);
    const Vec2 sz = text_size(t);
    occupied.push_back({margin, y - sz[1], margin + sz[0], y});
    renderer->AddActor2D(t);
    y -= std::round(1.4 * size);
  };
  line(in.title, title_px, true);
  line(in.subtitle, text_px, false);

  // x, y, z as they point in the picture (the camera's right and up directions)
  vtkCamera* cam = renderer->GetActiveCamera();
  double up[3], dop[3];
  cam->GetViewUp(up);
  cam->GetDirectionOfProjection(dop);
  const double right[3] = {dop[1] * up[2] - dop[2] * up[1], dop[2] * up[0] - dop[0] * up[2], dop[0] * up[1] - dop[1] * up[0]};
  const double length = std::round(2.6 * text_px);
  const Vec2 origin{margin + length + 0.6 * text_px, margin + length + 0.6 * text_px};
  // in ink, not red-green-blue: no axis may be taken for a selection of that colour
  const Rgb axis_colors[3] = {{0.30, 0.30, 0.33}, {0.30, 0.30, 0.33}, {0.30, 0.30, 0.33}};
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    const Vec2 tip{origin[0] + length * right[k], origin[1] + length * up[k]};
    renderer->AddActor2D(actor_2d(polyline_2d({origin, tip}), axis_colors[k], 1.0, 2.5));
    auto t = text(names[k], text_px, true);
    t->GetTextProperty()->SetColor(axis_colors[k][0], axis_colors[k][1], axis_colors[k][2]);
    t->GetTextProperty()->SetJustificationToCentered();
    t->GetTextProperty()->SetVerticalJustificationToCentered();
    t->GetPositionCoordinate()->SetValue(origin[0] + (length + 0.6 * text_px) * right[k],
                                         origin[1] + (length + 0.6 * text_px) * up[k]);
    renderer->AddActor2D(t);
  }
  const double reach = length + 1.2 * text_px;
  occupied.push_back({origin[0] - reach, origin[1] - reach, origin[0] + reach, origin[1] + reach});
}

}  // namespace

std::array<double, 3> picture_color(int k, double tint) {
  const Rgb& c = kPalette[((k % 10) + 10) % 10];
  const double t = std::clamp(tint, 0.0, 1.0);
  return {(1 - t) * c[0] + t, (1 - t) * c[1] + t, (1 - t) * c[2] + t};
}

std::vector<PixelBox> place_labels(const std::vector<std::array<double, 2>>& anchors,
                                   const std::vector<std::array<double, 2>>& sizes, std::array<double, 2> centre,
                                   const PixelBox& area, const std::vector<PixelBox>& occupied) {
  constexpr double kGap = 4.0;     // pixels kept between boxes
  constexpr double kAnchorR = 6.0;  // half the square kept free around every anchor
  const double distances[] = {24, 48, 80, 120, 170, 240, 330};
  const double turns[] = {0, 30, -30, 60, -60, 90, -90, 120, -120, 150, -150, 180};
  constexpr double kCrossing = 400.0;  // the cost of a leader line crossing a box, in square pixels
  constexpr double kOutside = 1e6;     // and of a box reaching out of the area
  std::vector<PixelBox> placed;
  std::vector<std::array<Vec2, 2>> leaders;  // of the boxes placed
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    const Vec2 a = anchors[i], s = sizes[i];
    const double dx = a[0] - centre[0], dy = a[1] - centre[1];
    const double outward = std::hypot(dx, dy) > 1.0 ? std::atan2(dy, dx) : M_PI / 4;
    auto cost = [&](const PixelBox& b) {  // 0 = free
      double c = 0;
      if (b.x0 < area.x0 || b.y0 < area.y0 || b.x1 > area.x1 || b.y1 > area.y1) {
        const PixelBox inside{std::max(b.x0, area.x0), std::max(b.y0, area.y0), std::min(b.x1, area.x1),
                              std::min(b.y1, area.y1)};
        c += kOutside + 10.0 * ((b.x1 - b.x0) * (b.y1 - b.y0) - overlap_area(b, inside));  // a cut label is worst
      }
      const PixelBox grown{b.x0 - kGap, b.y0 - kGap, b.x1 + kGap, b.y1 + kGap};
      for (const PixelBox& p : placed) c += overlap_area(grown, p) + (grown.overlaps(p) ? 1.0 : 0.0);
      for (const PixelBox& p : occupied) c += overlap_area(grown, p) + (grown.overlaps(p) ? 1.0 : 0.0);
      for (std::size_t j = 0; j < anchors.size(); ++j) {
        const PixelBox around{anchors[j][0] - kAnchorR, anchors[j][1] - kAnchorR, anchors[j][0] + kAnchorR,
                              anchors[j][1] + kAnchorR};
        if (b.overlaps(around)) c += 4 * kAnchorR * kAnchorR;
      }
      // leader lines: earlier ones through this box, this one through earlier boxes
      const Vec2 end = nearest_on(b, a);
      for (const auto& [p, q] : leaders)
        if (segment_hits(grown, p, q)) c += kCrossing;
      for (const PixelBox& p : placed)
        if (segment_hits(p, a, end)) c += kCrossing;
      return c;
    };
    PixelBox best;
    double best_cost = -1;
    for (double d : distances) {
      for (double turn : turns) {
        const double angle = outward + turn * M_PI / 180.0;
        const double ux = std::cos(angle), uy = std::sin(angle);
        // the box's centre far enough along the direction that its near side is d from the anchor
        const double reach = d + 0.5 * (std::fabs(ux) * s[0] + std::fabs(uy) * s[1]);
        const double cx = a[0] + reach * ux, cy = a[1] + reach * uy;
        const PixelBox b{std::round(cx - 0.5 * s[0]), std::round(cy - 0.5 * s[1]), std::round(cx - 0.5 * s[0]) + s[0],
                         std::round(cy - 0.5 * s[1]) + s[1]};
        const double c = cost(b);
        if (best_cost < 0 || c < best_cost) best = b, best_cost = c;
        if (c == 0) break;
      }
      if (best_cost == 0) break;
    }
    placed.push_back(best);
    leaders.push_back({a, nearest_on(best, a)});
  }
  return placed;
}

bool write_mesh_picture(GraphicsContext& gc, const MeshPicture& picture, const std::string& png_path,
                        std::string* error) {
  if (const std::string why = invalid(picture); !why.empty()) {
    if (error) *error = why;
    return false;
  }
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  Picture p(gc, picture);
  if (!p.error.empty()) {
    if (error) *error = p.error;
    return false;
  }
  p.renderer->SetBackground(1.0, 1.0, 1.0);
  vtkRenderer* layers[] = {p.renderer, p.xray, p.halos, p.leaders, p.boxes, p.labels};
  p.surface->window()->SetNumberOfLayers(6);
  for (int k = 0; k < 6; ++k) {
    layers[k]->SetLayer(k);
    if (k > 0) layers[k]->SetActiveCamera(p.renderer->GetActiveCamera());
    p.surface->window()->AddRenderer(layers[k]);
  }
  p.margin = std::round(0.018 * picture.height);
  p.text_px = std::max(11.0, std::round(picture.height / 56.0));
  p.title_px = std::max(13.0, std::round(picture.height / 38.0));
  p.build_legend();
  p.title_height = (picture.title.empty() ? 0.0 : 1.4 * p.title_px) + (picture.subtitle.empty() ? 0.0 : 1.4 * p.text_px);
  p.build_camera();
  p.build_surface();
  p.build_markers();
  p.build_title_and_axes();
  p.build_labels();
  p.renderer->ResetCameraClippingRange();
  return p.surface->render_to_png(png_path, error);
}

}  // namespace ff::render
