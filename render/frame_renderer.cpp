#include "render/frame_renderer.h"

#include <vtkActor.h>
#include <vtkActor2D.h>
#include <vtkArrowSource.h>
#include <vtkCamera.h>
#include <vtkCellPicker.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkColorTransferFunction.h>
#include <vtkDoubleArray.h>
#include <vtkLightKit.h>
#include <vtkLookupTable.h>
#include <vtkMath.h>
#include <vtkMatrix4x4.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkPolyDataMapper.h>
#include <vtkPolyDataMapper2D.h>
#include <vtkPolyDataNormals.h>
#include <vtkProperty.h>
#include <vtkProperty2D.h>
#include <vtkRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkSmartPointer.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>
#include <vtkTransform.h>
#include <vtkTransformPolyDataFilter.h>
#include <vtkTubeFilter.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <cmath>

#include "render/frame_layout.h"
#include "render/render_surface.h"
#include "render/text_style.h"

namespace ff::render {
namespace {

// colours (RGB in [0, 1])
constexpr double kBodyColor[3] = {0.22, 0.42, 0.69};   // uniform colour without a field
constexpr double kGhostColor[3] = {0.74, 0.74, 0.76};  // undeformed body
constexpr double kEdgeColor[3] = {0.20, 0.22, 0.26};
// the ghost surface looks like this opacity over the background (drawn opaque beneath the body:
// a translucent actor sends llvmpipe through VTK's order-independent translucency passes, which
// cost 43 % of a replay of the main job; docs/performance.md)
constexpr double kGhostSurfaceOpacity = 0.20;
constexpr double kGhostTubeFraction = 0.55;  // ghost tube radius / body tube radius
constexpr int kTubeSides = 20;
constexpr double kMinEdgePixels = 14.0;  // draw element edges when elements are this large
// orientation triad: axis colours (x, y, z) and the half width of its square in axis lengths
constexpr double kAxisColor[3][3] = {{0.84, 0.15, 0.15}, {0.13, 0.60, 0.18}, {0.16, 0.33, 0.85}};
constexpr double kTriadHalfWidth = 1.5;
constexpr double kTriadLabelAt = 1.22;  // label centres, in axis lengths from the origin
// node markers: rim colour, rim width as a fraction of the diameter; dots smaller than
// kMarkerDiscMinPx are squares (GL points: one vertex each, cheap for tens of thousands), larger
// ones discs (polygons, a dozen triangles each)
constexpr double kMarkerRimColor[3] = {0.08, 0.08, 0.10};
constexpr double kMarkerRimFraction = 0.15;
constexpr double kMarkerDiscMinPx = 8.0;

// One layer of the marker overlay: a set's rims or its fills, discs or squares, in one colour on
// a renderer of its own. Every renderer above layer 0 starts with a cleared depth buffer, so a
// higher layer lies over a lower one however the backend settles depth ties (2D actors all sit at
// one depth; observed: on the EGL path the first drawn stayed, on X11 the last).
struct MarkerLayer {
  std::size_t set = 0;  // index into the marker sets
  bool rims = false;    // the dark rims (drawn first, the fills over them)
  bool discs = false;   // discs (polygons) rather than squares (GL points)
  vtkSmartPointer<vtkPolyData> dots;
  vtkSmartPointer<vtkActor2D> actor;
  vtkSmartPointer<vtkRenderer> renderer;
};
constexpr int kFirstMarkerLayer = 3;  // over the underlay (0), the body (1) and the triad (2)

// 'cool to warm' (Moreland's end colours, blue 0.230 0.299 0.754 -> red 0.706 0.016 0.150)
// with a mid grey of lightness ~0.8 instead of the usual near-white, so the middle of the range
// stays visible on a white background; interpolated in CIELAB for even steps
void fill_cool_to_warm(vtkLookupTable* lut) {
  vtkNew<vtkColorTransferFunction> ctf;
  ctf->SetColorSpaceToLab();
  ctf->AddRGBPoint(0.0, 0.230, 0.299, 0.754);
  ctf->AddRGBPoint(0.5, 0.780, 0.780, 0.800);
  ctf->AddRGBPoint(1.0, 0.706, 0.016, 0.150);
  constexpr int n = 256;
  lut->SetNumberOfTableValues(n);
  for (int i = 0; i < n; ++i) {
    double rgb[3];
    ctf->GetColor(static_cast<double>(i) / (n - 1), rgb);
    lut->SetTableValue(i, rgb[0], rgb[1], rgb[2], 1.0);
  }
  lut->Build();
}

void style_body(vtkProperty* p) {
  p->SetColor(kBodyColor[0], kBodyColor[1], kBodyColor[2]);
  p->SetAmbient(0.2);
  p->SetDiffuse(0.8);
  p->SetSpecular(0.25);
  p->SetSpecularPower(30.0);
}

// The body's lights move with the camera: a key light from above and slightly left of the eye,
// a weaker fill from below, a headlight and two back lights (VTK's light kit, its lights made
// white so they do not tint the field colours). A lone headlight lights only what faces the eye:
// a plate in the isometric view got cos 55° of the light, and whatever a deformation turns
// edge-on (a lifted lip, a crushed wall) fell to the ambient 15 % and was drawn near black.
void light_body(vtkRenderer* r) {
  vtkNew<vtkLightKit> kit;
  // balanced so that a face-on surface shows its true colour (0.2 ambient + 0.8 of ~1.0) and no
  // orientation gets darker than under the former headlight by more than ~6 % (a wall facing
  // 35° below the eye) while oblique ones gain up to 50 % (55° above: 0.64 -> 0.96)
  kit->SetKeyLightIntensity(0.7);
  kit->SetKeyToFillRatio(1.6);
  kit->SetKeyToHeadRatio(1.6);
  kit->SetKeyToBackRatio(3.5);
  kit->SetKeyLightWarmth(0.5);
  kit->SetFillLightWarmth(0.5);
  kit->SetHeadLightWarmth(0.5);
  kit->SetBackLightWarmth(0.5);
  r->RemoveAllLights();
  r->AutomaticLightCreationOff();
  kit->AddLightsToRenderer(r);
  r->TwoSidedLightingOn();
}

}  // namespace

struct FrameRenderer::Impl {
  GraphicsContext& gc;
  FrameStyle style;
  RunInfo status_info;  // only time_unit: what the status line needs
  std::size_t n = 0;
  int field = -1;
  std::string error;

  ViewFit fit;
  FrameMesh fit_mesh;  // what an automatic camera frames: the reference mesh plus style.fit_points
  Camera camera;
  double tube_radius = 0;
  bool have_lines = false, have_surfaces = false;
  bool range_fixed = false;  // a caller range or an automatic range has been chosen
  std::array<double, 2> range{0, 0};

  std::unique_ptr<RenderSurface> surface;
  vtkNew<vtkRenderer> renderer;  // layer 1: the body, overlay text and colour bar
  vtkNew<vtkRenderer> underlay;  // layer 0: background and ghost surface, beneath the body
  vtkNew<vtkPoints> points, base_points;
  vtkNew<vtkDoubleArray> scalars;
  vtkNew<vtkPolyData> lines, surfaces, ghost_lines, ghost_surfaces;
  vtkNew<vtkTubeFilter> tubes, ghost_tubes;
  vtkNew<vtkPolyDataNormals> normals;
  vtkNew<vtkPolyDataMapper> line_mapper, surface_mapper, ghost_line_mapper, ghost_surface_mapper;
  vtkNew<vtkActor> line_actor, surface_actor, ghost_line_actor, ghost_surface_actor;
  vtkNew<vtkLookupTable> lut;
  vtkNew<vtkScalarBarActor> bar;
  vtkNew<vtkTextActor> bar_title, title, status;
  // orientation triad: its own renderer in the bottom-left corner (layer 2), turned with the camera
  vtkNew<vtkRenderer> triad;
  std::array<vtkNew<vtkActor>, 3> triad_axes;
  std::array<vtkNew<vtkTextActor>, 3> triad_labels;
  // node markers: 2D actors of dots in pixel coordinates, their geometry rebuilt for every
  // frame; layers bottom first
  std::vector<NodeMarkers> marker_sets;
  std::vector<MarkerLayer> marker_layers;

  Impl(GraphicsContext& g, FrameStyle s) : gc(g), style(std::move(s)) {}
  bool build(const RunInfo& info);
  bool check_mesh(const RunInfo& info);  // sizes, indices and the colour field; sets n, field
  void build_surface_actor(const FrameMesh& mesh);
  void build_ghost();
  void build_overlay(const RunInfo& info);
  void build_triad();
  void turn_triad();     // the triad's camera looks along the body's camera
  void place_markers();  // dots at the marked nodes' drawn positions, for the current camera
  void build_marker_layers();  // actors for marker_sets
  bool update(const Frame& frame, std::string* why);
  void update_range(const std::vector<double>& values);
  void apply_camera(const Camera& c);
  void reset_clipping_range();  // near and far planes around what both layers draw
  void set_bar_labels();
  // layout of the overlay, in pixels
  double margin_px() const { return std::round(0.018 * style.height); }
  double title_px() const { return std::max(12.0, std::round(style.height / 28.0)); }
  double text_px() const { return std::max(10.0, std::round(style.height / 36.0)); }
  int bar_strip_px() const { return static_cast<int>(std::lround(0.15 * style.width)); }
  int triad_side_px() const {
    return std::max(56, static_cast<int>(std::lround(0.16 * std::min(style.width, style.height))));
  }
  ~Impl() {
    // the window goes first: it frees the GL objects of everything drawn while its context
    // exists, then the VTK objects below are destroyed without touching GL
    surface.reset();
  }
};

bool FrameRenderer::Impl::build(const RunInfo& info) {
  const FrameMesh& mesh = info.mesh;
  if (!check_mesh(info)) return false;
  if (style.color_max > style.color_min) {
    range = {style.color_min, style.color_max};
    range_fixed = true;
  }

  surface = std::make_unique<RenderSurface>(gc.state(), style.width, style.height);
  if (!surface->ok()) {
    error = surface->error();
    return false;
  }

  // camera: fitted to the reference mesh once, so motion shows between frames
  fit_mesh.reference_points = mesh.reference_points;  // plus the caller's extra points
  if (!style.fit_points.empty()) {
    const std::size_t m = style.fit_points.size() / 3 * 3;
    fit_mesh.reference_points.insert(fit_mesh.reference_points.end(), style.fit_points.begin(),
                                     style.fit_points.begin() + static_cast<std::ptrdiff_t>(m));
  }
  fit = fit_view(fit_mesh, style.width, style.height, style.camera.parallel,
                 field >= 0 ? bar_strip_px() : 0, style.camera.view_direction,
                 style.camera.view_up, style.camera.zoom);
  camera = style.camera.automatic ? fit.camera : style.camera;
  if (!(camera.parallel_scale > 0)) camera.parallel_scale = fit.camera.parallel_scale;
  tube_radius = style.line_radius > 0 ? style.line_radius : automatic_line_radius(camera, fit.radius);

  // geometry: bodies share `points`, ghosts share `base_points`; topology is set once
  points->SetDataTypeToDouble();
  base_points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(n));
  base_points->SetNumberOfPoints(static_cast<vtkIdType>(n));
  for (std::size_t i = 0; i < n; ++i) {
    points->SetPoint(static_cast<vtkIdType>(i), &mesh.reference_points[3 * i]);
    base_points->SetPoint(static_cast<vtkIdType>(i), &mesh.reference_points[3 * i]);
  }
  scalars->SetName("field");
  scalars->SetNumberOfTuples(static_cast<vtkIdType>(n));
  scalars->FillValue(0.0);

  vtkNew<vtkCellArray> line_cells, surface_cells;
  for (const auto& chain : chain_polylines(mesh.lines)) {
    line_cells->InsertNextCell(static_cast<vtkIdType>(chain.size()));
    for (std::int32_t v : chain) line_cells->InsertCellPoint(v);
  }
  for (std::size_t t = 0; t + 2 < mesh.triangles.size(); t += 3) {
    const vtkIdType ids[3] = {mesh.triangles[t], mesh.triangles[t + 1], mesh.triangles[t + 2]};
    surface_cells->InsertNextCell(3, ids);
  }
  for (std::size_t q = 0; q + 3 < mesh.quads.size(); q += 4) {
    const vtkIdType ids[4] = {mesh.quads[q], mesh.quads[q + 1], mesh.quads[q + 2],
                              mesh.quads[q + 3]};
    surface_cells->InsertNextCell(4, ids);
  }
  have_lines = line_cells->GetNumberOfCells() > 0;
  have_surfaces = surface_cells->GetNumberOfCells() > 0;

  lines->SetPoints(points);
  lines->SetLines(line_cells);
  surfaces->SetPoints(points);
  surfaces->SetPolys(surface_cells);
  ghost_lines->SetPoints(base_points);
  ghost_lines->SetLines(line_cells);
  ghost_surfaces->SetPoints(base_points);
  ghost_surfaces->SetPolys(surface_cells);
  if (field >= 0) {
    lines->GetPointData()->SetScalars(scalars);
    surfaces->GetPointData()->SetScalars(scalars);
  }

  fill_cool_to_warm(lut);
  lut->SetTableRange(range_fixed ? range[0] : 0.0, range_fixed ? range[1] : 1.0);
  for (vtkPolyDataMapper* m : {line_mapper.Get(), surface_mapper.Get()}) {
    m->SetLookupTable(lut);
    m->UseLookupTableScalarRangeOn();
    m->SetScalarModeToUsePointData();
    m->SetScalarVisibility(field >= 0);
    m->InterpolateScalarsBeforeMappingOn();
  }

  if (have_lines) {
    tubes->SetInputData(lines);
    tubes->SetRadius(tube_radius);
    tubes->SetNumberOfSides(kTubeSides);
    tubes->CappingOn();
    line_mapper->SetInputConnection(tubes->GetOutputPort());
    line_actor->SetMapper(line_mapper);
    style_body(line_actor->GetProperty());
    renderer->AddActor(line_actor);
  }
  if (have_surfaces) build_surface_actor(mesh);
  if (style.show_base) build_ghost();
  light_body(renderer);
  apply_camera(camera);

  // two layers on one camera: the body's layer keeps the colour the underlay drew and clears only
  // depth, so the body is always drawn over the ghost (VTK's default for layers above 0)
  underlay->SetLayer(0);
  renderer->SetLayer(1);
  underlay->SetActiveCamera(renderer->GetActiveCamera());
  underlay->SetBackground(style.background[0], style.background[1], style.background[2]);
  renderer->SetUseFXAA(style.antialias);
  underlay->SetUseFXAA(style.antialias);
  build_overlay(info);
  surface->window()->SetNumberOfLayers(kFirstMarkerLayer);
  surface->window()->AddRenderer(underlay);
  surface->window()->AddRenderer(renderer);
  if (style.show_triad) {
    build_triad();
    surface->window()->AddRenderer(triad);
  }
  reset_clipping_range();
  return true;
}

bool FrameRenderer::Impl::check_mesh(const RunInfo& info) {
  const FrameMesh& mesh = info.mesh;
  n = mesh.point_count();
  status_info.time_unit = info.time_unit;
  if (mesh.reference_points.size() != 3 * n) {
    error = "mesh reference_points size is not a multiple of 3";
    return false;
  }
  if (style.width < 16 || style.height < 16) {
    error = "image size must be at least 16x16 pixels";
    return false;
  }
  auto check_cells = [&](const std::vector<std::int32_t>& c, std::size_t per, const char* what) {
    if (c.size() % per != 0) {
      error = std::string("mesh ") + what + " size is not a multiple of " + std::to_string(per);
      return false;
    }
    for (std::int32_t v : c) {
      if (v < 0 || static_cast<std::size_t>(v) >= n) {
        error = std::string("mesh ") + what + " refer to point " + std::to_string(v) + " of " +
                std::to_string(n);
        return false;
      }
    }
    return true;
  };
  if (!check_cells(mesh.lines, 2, "lines") || !check_cells(mesh.triangles, 3, "triangles") ||
      !check_cells(mesh.quads, 4, "quads"))
    return false;
  if (!style.color_field.empty()) {
    for (std::size_t i = 0; i < info.fields.size(); ++i)
      if (info.fields[i].name == style.color_field) field = static_cast<int>(i);
    if (field < 0) {
      error = "color_field '" + style.color_field + "' is not one of the run's fields";
      return false;
    }
  }
  return true;
}

// the body's surfaces: lit, no highlights, element edges when elements are large on screen
void FrameRenderer::Impl::build_surface_actor(const FrameMesh& mesh) {
  normals->SetInputData(surfaces);
  normals->ComputePointNormalsOn();
  // a crease sharper than 45° (a fold, a crushed wall, a coarse mesh's edge) keeps a normal
  // per side: averaged across it, the two nearly opposite normals of a fold cancel and the
  // elements beside it were shaded as if seen edge-on, a dark band
  normals->SplittingOn();
  normals->SetFeatureAngle(45.0);
  normals->ConsistencyOn();
  surface_mapper->SetInputConnection(normals->GetOutputPort());
  surface_actor->SetMapper(surface_mapper);
  style_body(surface_actor->GetProperty());
  // no highlights on surfaces: they wash out the field colours, and with more than a headlight
  // VTK takes the view vector from the vertex even in a parallel view, so a flat plate would
  // not be one colour
  surface_actor->GetProperty()->SetSpecular(0.0);
  // element edges only when elements are large enough on screen to read them
  double edge_sum = 0;
  std::size_t edge_count = 0;
  auto add_edges = [&](const std::vector<std::int32_t>& c, std::size_t per) {
    for (std::size_t e = 0; e + per - 1 < c.size(); e += per) {
      for (std::size_t k = 0; k < per; ++k) {
        const double* a = &mesh.reference_points[3 * c[e + k]];
        const double* b = &mesh.reference_points[3 * c[e + (k + 1) % per]];
        edge_sum += std::sqrt((a[0] - b[0]) * (a[0] - b[0]) + (a[1] - b[1]) * (a[1] - b[1]) +
                              (a[2] - b[2]) * (a[2] - b[2]));
        ++edge_count;
      }
    }
  };
  add_edges(mesh.triangles, 3);
  add_edges(mesh.quads, 4);
  const double pixel = 2.0 * camera.parallel_scale / style.height;
  if (edge_count > 0 && edge_sum / edge_count > kMinEdgePixels * pixel) {
    surface_actor->GetProperty()->EdgeVisibilityOn();
    surface_actor->GetProperty()->SetEdgeColor(kEdgeColor[0], kEdgeColor[1], kEdgeColor[2]);
  }
  renderer->AddActor(surface_actor);
}

// the faint grey ghost of the base points: thin tubes, and surfaces beneath the body
void FrameRenderer::Impl::build_ghost() {
  if (have_lines) {
    ghost_tubes->SetInputData(ghost_lines);
    ghost_tubes->SetRadius(kGhostTubeFraction * tube_radius);
    ghost_tubes->SetNumberOfSides(kTubeSides / 2);
    ghost_tubes->CappingOn();
    ghost_line_mapper->SetInputConnection(ghost_tubes->GetOutputPort());
    ghost_line_mapper->ScalarVisibilityOff();
    ghost_line_actor->SetMapper(ghost_line_mapper);
    ghost_line_actor->GetProperty()->SetColor(kGhostColor[0], kGhostColor[1], kGhostColor[2]);
    ghost_line_actor->GetProperty()->SetAmbient(0.4);
    ghost_line_actor->GetProperty()->SetDiffuse(0.6);
    renderer->AddActor(ghost_line_actor);
  }
  if (have_surfaces) {
    ghost_surface_mapper->SetInputData(ghost_surfaces);
    ghost_surface_mapper->ScalarVisibilityOff();
    ghost_surface_actor->SetMapper(ghost_surface_mapper);
    // opaque, beneath the body, lit as a = kGhostSurfaceOpacity of the ghost over the background
    // would be: (1 − a) background + a ghost cos θ, by the ambient and diffuse colours
    vtkProperty* ghost = ghost_surface_actor->GetProperty();
    const double a = kGhostSurfaceOpacity;
    ghost->SetAmbientColor((1 - a) * style.background[0], (1 - a) * style.background[1], (1 - a) * style.background[2]);
    ghost->SetDiffuseColor(a * kGhostColor[0], a * kGhostColor[1], a * kGhostColor[2]);
    ghost->SetAmbient(1.0);
    ghost->SetDiffuse(1.0);
    ghost->SetSpecular(0.0);
    underlay->AddActor(ghost_surface_actor);
  }
}

void FrameRenderer::Impl::reset_clipping_range() {
  double body[6], both[6];
  renderer->ComputeVisiblePropBounds(body);
  underlay->ComputeVisiblePropBounds(both);
  if (!vtkMath::AreBoundsInitialized(both)) return renderer->ResetCameraClippingRange();  // no ghost shown
  if (vtkMath::AreBoundsInitialized(body))
    for (int k = 0; k < 3; ++k) {
      both[2 * k] = std::min(both[2 * k], body[2 * k]);
      both[2 * k + 1] = std::max(both[2 * k + 1], body[2 * k + 1]);
    }
  renderer->ResetCameraClippingRange(both);
}

void FrameRenderer::Impl::apply_camera(const Camera& c) {
  vtkCamera* cam = renderer->GetActiveCamera();
  cam->SetFocalPoint(c.focal_point.data());
  cam->SetPosition(c.position.data());
  cam->SetViewUp(c.view_up.data());
  cam->SetParallelProjection(c.parallel);
  cam->SetParallelScale(c.parallel_scale);
  cam->SetViewAngle(30.0);
  reset_clipping_range();
}

void FrameRenderer::Impl::build_overlay(const RunInfo& info) {
  const double w = style.width, h = style.height;
  const double ink[3] = {0.10, 0.10, 0.12};
  const double m = margin_px();

  // top left: title, then time / load factor / deformation scale, one per line
  double y = h - m;
  if (!style.title.empty()) {
    title->SetInput(style.title.c_str());
    set_text_style(title->GetTextProperty(), title_px(), ink, true);
    title->GetTextProperty()->SetVerticalJustificationToTop();
    title->GetPositionCoordinate()->SetCoordinateSystemToViewport();
    title->GetPositionCoordinate()->SetValue(m, y);
    renderer->AddActor2D(title);
    y -= std::round(1.5 * title_px());
  }
  set_text_style(status->GetTextProperty(), text_px(), ink, false);
  status->GetTextProperty()->SetVerticalJustificationToTop();
  status->GetTextProperty()->SetLineSpacing(1.15);
  status->GetPositionCoordinate()->SetCoordinateSystemToViewport();
  status->GetPositionCoordinate()->SetValue(m, y);
  renderer->AddActor2D(status);

  if (field < 0) return;
  // right strip: the field title (right-aligned; the bar's own title would be squeezed to
  // the bar width), the bar below it with its labels to the right
  set_text_style(bar_title->GetTextProperty(), text_px(), ink, true);
  {
    // a label too long to stand beside the title on the top line (a stress field's one-line
    // description) gives way to the field's name
    const Quantity& q = info.fields[static_cast<std::size_t>(field)];
    const int dpi = surface->window()->GetDPI();
    auto width = [&](const std::string& text, vtkTextProperty* p) {
      int box[4] = {0, 0, 0, 0};
      return vtkTextRenderer::GetInstance()->GetBoundingBox(p, text, box, dpi) ? box[1] - box[0] : 0;
    };
    const double room = w - 3 * m - (style.title.empty() ? 0.0 : width(style.title, title->GetTextProperty()));
    std::string text = quantity_title(q);
    if (width(text, bar_title->GetTextProperty()) > room) text = quantity_title({q.name, q.unit, ""});
    bar_title->SetInput(text.c_str());
  }
  bar_title->GetTextProperty()->SetJustificationToRight();
  bar_title->GetTextProperty()->SetVerticalJustificationToTop();
  bar_title->GetPositionCoordinate()->SetCoordinateSystemToViewport();
  bar_title->GetPositionCoordinate()->SetValue(w - m, h - m);
  renderer->AddActor2D(bar_title);

  const double strip = bar_strip_px();
  const double x0 = w - strip + m, y0 = 0.12 * h;
  const double top = h - m - 1.8 * text_px();
  bar->SetLookupTable(lut);
  bar->SetMaximumNumberOfColors(256);
  bar->SetOrientationToVertical();
  bar->UseCustomLabelsOn();
  set_bar_labels();
  bar->SetTextPositionToSucceedScalarBar();
  bar->UnconstrainedFontSizeOn();
  bar->SetBarRatio(std::min(0.5, 0.045 * h / (strip - 2 * m)));
  set_text_style(bar->GetLabelTextProperty(), std::round(0.85 * text_px()), ink, false);
  bar->GetPositionCoordinate()->SetCoordinateSystemToViewport();
  bar->GetPositionCoordinate()->SetValue(x0, y0);
  bar->GetPosition2Coordinate()->SetCoordinateSystemToViewport();
  bar->GetPosition2Coordinate()->SetValue(strip - 2 * m, top - y0);
  renderer->AddActor2D(bar);
}

void FrameRenderer::Impl::build_triad() {
  const double w = style.width, h = style.height, m = margin_px(), side = triad_side_px();
  triad->SetLayer(2);  // over the body's layer; clears only depth, inside its own viewport
  triad->SetViewport(m / w, m / h, (m + side) / w, (m + side) / h);
  triad->InteractiveOff();
  const char* names[3] = {"x", "y", "z"};
  for (int k = 0; k < 3; ++k) {
    // vtkArrowSource points along +x from the origin, length 1
    vtkNew<vtkArrowSource> arrow;
    arrow->SetShaftRadius(0.045);
    arrow->SetTipRadius(0.12);
    arrow->SetTipLength(0.3);
    arrow->SetShaftResolution(12);
    arrow->SetTipResolution(16);
    vtkNew<vtkTransform> turn;
    if (k == 1) turn->RotateZ(90.0);
    if (k == 2) turn->RotateY(-90.0);
    vtkNew<vtkTransformPolyDataFilter> placed;
    placed->SetInputConnection(arrow->GetOutputPort());
    placed->SetTransform(turn);
    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputConnection(placed->GetOutputPort());
    triad_axes[k]->SetMapper(mapper);
    vtkProperty* p = triad_axes[k]->GetProperty();
    p->SetColor(kAxisColor[k][0], kAxisColor[k][1], kAxisColor[k][2]);
    p->SetAmbient(0.45);  // readable whichever way an axis points
    p->SetDiffuse(0.55);
    p->SetSpecular(0.0);
    triad->AddActor(triad_axes[k]);
    triad_labels[k]->SetInput(names[k]);
    const double ink[3] = {0.75 * kAxisColor[k][0], 0.75 * kAxisColor[k][1], 0.75 * kAxisColor[k][2]};
    set_text_style(triad_labels[k]->GetTextProperty(), std::max(10.0, std::round(0.17 * side)), ink, true);
    triad_labels[k]->GetTextProperty()->SetJustificationToCentered();
    triad_labels[k]->GetTextProperty()->SetVerticalJustificationToCentered();
    triad_labels[k]->GetPositionCoordinate()->SetCoordinateSystemToDisplay();
    triad->AddActor2D(triad_labels[k]);
  }
  vtkCamera* c = triad->GetActiveCamera();
  c->SetFocalPoint(0, 0, 0);
  c->SetParallelProjection(1);
  c->SetParallelScale(kTriadHalfWidth);
}

void FrameRenderer::Impl::turn_triad() {
  if (!style.show_triad) return;
  vtkCamera* body = renderer->GetActiveCamera();
  double dir[3], up[3];
  body->GetDirectionOfProjection(dir);
  body->GetViewUp(up);
  vtkCamera* c = triad->GetActiveCamera();
  c->SetPosition(-10 * dir[0], -10 * dir[1], -10 * dir[2]);
  c->SetViewUp(up);
  c->SetClippingRange(10 - 2 * kTriadHalfWidth, 10 + 2 * kTriadHalfWidth);
  for (int k = 0; k < 3; ++k) {
    double tip[3] = {0, 0, 0}, d[3];
    tip[k] = kTriadLabelAt;
    triad->SetWorldPoint(tip[0], tip[1], tip[2], 1.0);
    triad->WorldToDisplay();
    triad->GetDisplayPoint(d);
    triad_labels[k]->GetPositionCoordinate()->SetValue(d[0], d[1]);
  }
}

void FrameRenderer::Impl::build_marker_layers() {
  vtkRenderWindow* window = surface->window();
  for (const MarkerLayer& layer : marker_layers) window->RemoveRenderer(layer.renderer);
  marker_layers.clear();
  for (std::size_t k = 0; k < marker_sets.size(); ++k) {
    const NodeMarkers& set = marker_sets[k];
    if (set.nodes.empty()) continue;
    const double rim = std::max(1.0, std::round(kMarkerRimFraction * set.size_px));
    for (bool rims : {true, false}) {
      MarkerLayer layer{k, rims, set.size_px >= kMarkerDiscMinPx, vtkSmartPointer<vtkPolyData>::New(),
                        vtkSmartPointer<vtkActor2D>::New(), vtkSmartPointer<vtkRenderer>::New()};
      vtkNew<vtkPolyDataMapper2D> mapper;
      mapper->SetInputData(layer.dots);
      mapper->ScalarVisibilityOff();
      layer.actor->SetMapper(mapper);
      layer.actor->GetProperty()->SetColor(rims ? kMarkerRimColor : set.color.data());
      layer.actor->GetProperty()->SetPointSize(static_cast<float>(rims ? set.size_px : std::max(1.0, set.size_px - 2 * rim)));
      layer.renderer->SetLayer(kFirstMarkerLayer + static_cast<int>(marker_layers.size()));
      layer.renderer->InteractiveOff();
      layer.renderer->AddActor2D(layer.actor);
      marker_layers.push_back(std::move(layer));
    }
  }
  window->SetNumberOfLayers(kFirstMarkerLayer + static_cast<int>(marker_layers.size()));
  for (const MarkerLayer& layer : marker_layers) window->AddRenderer(layer.renderer);
}

void FrameRenderer::Impl::place_markers() {
  if (marker_layers.empty()) return;
  const double w = style.width, h = style.height;
  // world -> normalized device coordinates, as VTK projects the body (aspect = the window's)
  vtkMatrix4x4* to_ndc = renderer->GetActiveCamera()->GetCompositeProjectionTransformMatrix(w / h, -1, 1);
  std::vector<std::array<double, 2>> at;
  std::size_t projected = marker_sets.size();  // the set `at` holds
  for (const MarkerLayer& layer : marker_layers) {
    const NodeMarkers& set = marker_sets[layer.set];
    if (projected != layer.set) {
      at.clear();
      for (std::int32_t node : set.nodes) {
        double p[4] = {0, 0, 0, 1}, q[4];
        points->GetPoint(node, p);
        to_ndc->MultiplyPoint(p, q);
        if (!(q[3] > 0)) continue;  // behind the eye (perspective)
        at.push_back({(q[0] / q[3] + 1.0) * 0.5 * w, (q[1] / q[3] + 1.0) * 0.5 * h});
      }
      projected = layer.set;
    }
    vtkNew<vtkPoints> dot_points;
    vtkNew<vtkCellArray> cells;
    if (!layer.discs) {
      for (const auto& c : at) {
        const vtkIdType id = dot_points->InsertNextPoint(c[0], c[1], 0.0);
        cells->InsertNextCell(1, &id);
      }
      layer.dots->SetPoints(dot_points);
      layer.dots->SetVerts(cells);
      continue;
    }
    const int segments = set.size_px < 12 ? 8 : set.size_px < 24 ? 12 : 20;  // round enough, few triangles
    const double rim = std::max(1.0, std::round(kMarkerRimFraction * set.size_px));
    const double radius = 0.5 * set.size_px - (layer.rims ? 0.0 : rim);
    for (const auto& c : at) {
      cells->InsertNextCell(segments);
      for (int j = 0; j < segments; ++j) {
        const double a = 2.0 * M_PI * (j + 0.5) / segments;
        cells->InsertCellPoint(dot_points->InsertNextPoint(c[0] + radius * std::cos(a), c[1] + radius * std::sin(a), 0.0));
      }
    }
    layer.dots->SetPoints(dot_points);
    layer.dots->SetPolys(cells);
  }
}

void FrameRenderer::Impl::update_range(const std::vector<double>& values) {
  double lo = 0, hi = 0;
  bool any = false;
  for (double v : values) {
    if (!std::isfinite(v)) continue;
    lo = any ? std::min(lo, v) : v;
    hi = any ? std::max(hi, v) : v;
    any = true;
  }
  if (!any) return;
  if (range_fixed) {
    if (style.color_max > style.color_min) return;  // the caller's range is kept as given
    if (lo >= range[0] && hi <= range[1]) return;
    range = color_range_for(std::min(lo, range[0]), std::max(hi, range[1]));
  } else {
    // a constant field (often the all-zero initial state) gets a provisional range from 0 to
    // its value (never below 0 for a magnitude), replaced by the first varying frame's
    range = color_range_for(lo, hi);
    range_fixed = hi > lo;
  }
  lut->SetTableRange(range[0], range[1]);
  set_bar_labels();
}

void FrameRenderer::Impl::set_bar_labels() {
  const double lo = lut->GetTableRange()[0], hi = lut->GetTableRange()[1];
  const Ticks ticks = color_bar_ticks(lo, hi);
  vtkNew<vtkDoubleArray> values;
  for (double v : ticks.values) values->InsertNextValue(v);
  bar->SetCustomLabels(values);
  bar->SetLabelFormat(ticks.format.c_str());
}

bool FrameRenderer::Impl::update(const Frame& frame, std::string* why) {
  if (frame.points.size() != 3 * n) {
    *why = "frame has " + std::to_string(frame.points.size()) + " point coordinates, mesh needs " +
           std::to_string(3 * n);
    return false;
  }
  const bool have_base = !frame.base_points.empty();
  if (have_base && frame.base_points.size() != 3 * n) {
    *why = "frame base_points size does not match the mesh";
    return false;
  }
  const std::vector<double>* values = nullptr;
  if (field >= 0) {
    if (frame.fields.size() <= static_cast<std::size_t>(field) ||
        frame.fields[static_cast<std::size_t>(field)].size() != n) {
      *why = "frame lacks per-point values of field '" + style.color_field + "'";
      return false;
    }
    values = &frame.fields[static_cast<std::size_t>(field)];
  }
  const double s = style.deformation_scale;
  for (std::size_t i = 0; i < n; ++i) {
    double p[3], b[3];
    for (int k = 0; k < 3; ++k) {
      const double x = frame.points[3 * i + k];
      b[k] = have_base ? frame.base_points[3 * i + k] : x;
      p[k] = b[k] + s * (x - b[k]);
      if (!std::isfinite(p[k]) || !std::isfinite(b[k])) {
        *why = "frame has a non-finite position at point " + std::to_string(i);
        return false;
      }
    }
    points->SetPoint(static_cast<vtkIdType>(i), p);
    base_points->SetPoint(static_cast<vtkIdType>(i), b);
  }
  points->Modified();
  base_points->Modified();
  if (values != nullptr) {
    for (std::size_t i = 0; i < n; ++i) scalars->SetValue(static_cast<vtkIdType>(i), (*values)[i]);
    scalars->Modified();
    update_range(*values);
  }
  for (vtkPolyData* pd : {lines.Get(), surfaces.Get(), ghost_lines.Get(), ghost_surfaces.Get()})
    pd->Modified();
  ghost_line_actor->SetVisibility(have_base);
  ghost_surface_actor->SetVisibility(have_base);

  status->SetInput(style.caption.empty() ? status_line(status_info, frame, s).c_str() : style.caption.c_str());
  reset_clipping_range();
  // what follows the camera: every render comes through here after the last orbit, zoom or pan
  turn_triad();
  place_markers();
  return true;
}

FrameRenderer::FrameRenderer(GraphicsContext& gc, const RunInfo& info, FrameStyle style) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  impl_ = std::make_unique<Impl>(gc, std::move(style));
  if (!impl_->build(info) && impl_->error.empty()) impl_->error = "renderer setup failed";
}

FrameRenderer::~FrameRenderer() {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  impl_.reset();
}

bool FrameRenderer::ok() const { return impl_->error.empty(); }
const std::string& FrameRenderer::error() const { return impl_->error; }

bool FrameRenderer::render_png(const Frame& frame, const std::string& png_path,
                               std::string* error) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  std::string why;
  if (!impl_->error.empty()) {
    why = impl_->error;
  } else if (impl_->update(frame, &why) && impl_->surface->render_to_png(png_path, &why)) {
    return true;
  }
  if (error) *error = why;
  return false;
}

bool FrameRenderer::render_rgb(const Frame& frame, std::vector<unsigned char>* rgb, std::string* error) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  std::string why;
  if (!impl_->error.empty()) {
    why = impl_->error;
  } else if (impl_->update(frame, &why) && impl_->surface->render_to_rgb(rgb, &why)) {
    return true;
  }
  if (error) *error = why;
  return false;
}

void FrameRenderer::orbit(double azimuth_deg, double elevation_deg) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  vtkCamera* cam = impl_->renderer->GetActiveCamera();
  cam->Azimuth(azimuth_deg);
  cam->Elevation(elevation_deg);
  cam->OrthogonalizeViewUp();
  impl_->reset_clipping_range();
}

void FrameRenderer::zoom(double factor) {
  if (!(factor > 0)) return;
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  vtkCamera* cam = impl_->renderer->GetActiveCamera();
  if (cam->GetParallelProjection())
    cam->SetParallelScale(cam->GetParallelScale() / factor);
  else
    cam->Dolly(factor);
  impl_->reset_clipping_range();
}

void FrameRenderer::pan(double dx_px, double dy_px) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  vtkCamera* cam = impl_->renderer->GetActiveCamera();
  double f[3], p[3], up[3], dir[3];
  cam->GetFocalPoint(f);
  cam->GetPosition(p);
  cam->GetViewUp(up);
  cam->GetDirectionOfProjection(dir);
  // world length of one pixel at the focal point
  const double half_h = cam->GetParallelProjection()
                            ? cam->GetParallelScale()
                            : cam->GetDistance() * std::tan(0.5 * cam->GetViewAngle() * M_PI / 180.0);
  const double w = 2.0 * half_h / impl_->style.height;
  const double right[3] = {dir[1] * up[2] - dir[2] * up[1], dir[2] * up[0] - dir[0] * up[2],
                           dir[0] * up[1] - dir[1] * up[0]};
  double shift[3];
  for (int k = 0; k < 3; ++k) shift[k] = w * (-dx_px * right[k] + dy_px * up[k]);
  cam->SetFocalPoint(f[0] + shift[0], f[1] + shift[1], f[2] + shift[2]);
  cam->SetPosition(p[0] + shift[0], p[1] + shift[1], p[2] + shift[2]);
  impl_->reset_clipping_range();
}

void FrameRenderer::reset_camera() {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  impl_->apply_camera(impl_->camera);
}

void FrameRenderer::set_camera(const Camera& c) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  Impl& m = *impl_;
  if (!m.surface) return;  // not built (see ok())
  if (c.automatic) {
    const ViewFit f = fit_view(m.fit_mesh, m.style.width, m.style.height, c.parallel,
                               m.field >= 0 ? m.bar_strip_px() : 0, c.view_direction, c.view_up, c.zoom);
    m.camera = f.camera;
  } else {
    m.camera = c;
    if (!(m.camera.parallel_scale > 0)) m.camera.parallel_scale = m.fit.camera.parallel_scale;
  }
  m.apply_camera(m.camera);
}

Camera FrameRenderer::current_camera() const {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  vtkCamera* cam = impl_->renderer->GetActiveCamera();
  Camera c;
  c.automatic = false;
  cam->GetFocalPoint(c.focal_point.data());
  cam->GetPosition(c.position.data());
  cam->GetViewUp(c.view_up.data());
  c.parallel = cam->GetParallelProjection() != 0;
  c.parallel_scale = cam->GetParallelScale();
  return c;
}

int FrameRenderer::pick_point(double x_px, double y_px, double max_px) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  Impl& m = *impl_;
  if (!m.error.empty() || m.n == 0) return -1;
  const double yd = m.style.height - 1 - y_px;  // VTK's display y grows upwards
  auto nearest = [&](auto&& dist2) {
    int best = -1;
    double best_d = 0;
    for (std::size_t i = 0; i < m.n; ++i) {
      double p[3];
      m.points->GetPoint(static_cast<vtkIdType>(i), p);
      const double d = dist2(p);
      if (best < 0 || d < best_d) best = static_cast<int>(i), best_d = d;
    }
    return std::make_pair(best, best_d);
  };
  // the body under the cursor: the mesh point closest to the hit
  vtkNew<vtkCellPicker> picker;
  picker->SetTolerance(0.002);
  picker->PickFromListOn();
  if (m.have_lines) picker->AddPickList(m.line_actor);
  if (m.have_surfaces) picker->AddPickList(m.surface_actor);
  if (picker->Pick(x_px, yd, 0.0, m.renderer)) {
    double hit[3];
    picker->GetPickPosition(hit);
    return nearest([&](const double* p) {
             return (p[0] - hit[0]) * (p[0] - hit[0]) + (p[1] - hit[1]) * (p[1] - hit[1]) +
                    (p[2] - hit[2]) * (p[2] - hit[2]);
           }).first;
  }
  // nothing hit: the point drawn nearest on screen, if close enough
  const auto [best, d2] = nearest([&](const double* p) {
    m.renderer->SetWorldPoint(p[0], p[1], p[2], 1.0);
    m.renderer->WorldToDisplay();
    double d[3];
    m.renderer->GetDisplayPoint(d);
    return (d[0] - x_px) * (d[0] - x_px) + (d[1] - yd) * (d[1] - yd);
  });
  return d2 <= max_px * max_px ? best : -1;
}

bool FrameRenderer::set_markers(std::vector<NodeMarkers> sets, std::string* error) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  const std::size_t n = impl_->n;
  std::string why;
  for (std::size_t k = 0; k < sets.size() && why.empty(); ++k) {
    const NodeMarkers& set = sets[k];
    const std::string which = "marker set " + std::to_string(k) + ": ";
    if (!(set.size_px >= 1.0 && set.size_px <= 200.0))
      why = which + "size_px " + std::to_string(set.size_px) + " is not in [1, 200]";
    for (double c : set.color)
      if (why.empty() && !(c >= 0.0 && c <= 1.0)) why = which + "colour channel " + std::to_string(c) + " is not in [0, 1]";
    for (std::int32_t node : set.nodes)
      if (why.empty() && (node < 0 || static_cast<std::size_t>(node) >= n))
        why = which + "node " + std::to_string(node) + " is not a point of the mesh (" + std::to_string(n) + " points)";
  }
  if (!why.empty()) {
    if (error) *error = why;
    return false;
  }
  impl_->marker_sets = std::move(sets);
  if (impl_->surface) impl_->build_marker_layers();
  return true;
}

const std::vector<NodeMarkers>& FrameRenderer::markers() const { return impl_->marker_sets; }

int FrameRenderer::width() const { return impl_->style.width; }
int FrameRenderer::height() const { return impl_->style.height; }

std::array<double, 2> FrameRenderer::color_range() const {
  return impl_->field >= 0 ? impl_->range : std::array<double, 2>{0, 0};
}

Camera FrameRenderer::camera() const { return impl_->camera; }

// every mesh point whose drawn position projects into the rectangle (box picking in the window)
std::vector<int> FrameRenderer::points_in_rect(double x0_px, double y0_px, double x1_px, double y1_px) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  Impl& m = *impl_;
  std::vector<int> inside;
  if (!m.error.empty() || m.n == 0) return inside;
  const double xlo = std::min(x0_px, x1_px), xhi = std::max(x0_px, x1_px);
  // VTK's display y grows upwards
  const double ylo = m.style.height - 1 - std::max(y0_px, y1_px), yhi = m.style.height - 1 - std::min(y0_px, y1_px);
  for (std::size_t i = 0; i < m.n; ++i) {
    double p[3], d[3];
    m.points->GetPoint(static_cast<vtkIdType>(i), p);
    m.renderer->SetWorldPoint(p[0], p[1], p[2], 1.0);
    m.renderer->WorldToDisplay();
    m.renderer->GetDisplayPoint(d);
    if (d[0] >= xlo && d[0] <= xhi && d[1] >= ylo && d[1] <= yhi) inside.push_back(static_cast<int>(i));
  }
  return inside;
}

}  // namespace ff::render
