#include "app/refine_picture.h"

#include <algorithm>
#include <atomic>
#include <cmath>

#include "app/frame_outputs.h"
#include "app/view_options.h"
#include "core/shell/error_indicator.h"
#include "render/frame_renderer.h"

namespace ff::app {

bool draw_refine_picture(render::GraphicsContext& gc, const RunInfo& info, const scene::OutputSettings& out,
                         const std::string& scene_name, const Frame& frame, const std::string& png_path,
                         std::string* error) {
  const int field = field_index(info, shell::kErrorIndicatorField);
  if (field < 0 || static_cast<std::size_t>(field) >= frame.fields.size()) {
    if (error) *error = "the run recorded no error indicator";
    return false;
  }
  double top = 0.0;
  for (double v : frame.fields[field])
    if (std::isfinite(v)) top = std::max(top, v);
  render::FrameStyle style;
  style.width = out.width;
  style.height = out.height;
  style.deformation_scale = out.deformation_scale;
  style.color_field = shell::kErrorIndicatorField;
  style.color_min = 0.0;
  style.color_max = top > 0 ? top : 1.0;
  style.title = scene_name + ": where to refine";
  style.caption = "each element's energy-norm error;\nits RMS is the global relative error";
  // the drawn (scaled) positions frame the picture, as the run's frames are framed
  const std::atomic<bool> never{false};
  const std::vector<double> drawn =
      sequence_view(1, [&](std::size_t) { return frame; }, -1, out.deformation_scale, never).fit_points;
  if (out.view != "auto") style.camera = scene_camera(info.mesh, out.view, out.view_center, out.view_radius, drawn);
  else style.fit_points = drawn;
  render::FrameRenderer renderer(gc, info, style);
  if (!renderer.ok()) {
    if (error) *error = renderer.error();
    return false;
  }
  return renderer.render_png(frame, png_path, error);
}

}  // namespace ff::app
