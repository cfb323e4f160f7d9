#include "app/mode_outputs.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <numbers>
#include <stdexcept>

#include "app/io/movie_writer.h"
#include "app/input_error.h"
#include "core/frame/text.h"
#include "render/graphics_context.h"
#include "render/image_io.h"
#include "render/mesh_export.h"
#include "render/plot.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {

std::string two_digits(int number) {
  char b[16];
  std::snprintf(b, sizeof b, "%02d", number);
  return b;
}

// "mode_02": the folder of a mode's frames and the stem of its movie (numbers past 99 keep all digits)
std::string mode_stem(int number) { return "mode_" + two_digits(number); }

std::string frame_png(int k) {
  char b[32];
  std::snprintf(b, sizeof b, "frame_%05d.png", k);
  return b;
}

const Mode* find_mode(const ModeSet& set, int number) {
  for (const Mode& m : set.modes)
    if (m.number == number) return &m;
  return nullptr;
}

// the PNGs of one cycle, `cycles` times over, as an MP4
std::string write_mode_movie(const std::vector<std::string>& pngs, const std::string& path, int fps, int cycles,
                             const std::atomic<bool>& stop) {
  if (const std::string why = io::movie_support(); !why.empty()) return why;
  std::vector<render::RgbImage> images(pngs.size());
  std::string error;
  for (std::size_t k = 0; k < pngs.size(); ++k)
    if (!render::read_png_rgb(pngs[k], &images[k], &error)) return error;
  if (images.empty()) return "no frames to make a movie of";
  std::unique_ptr<io::MovieWriter> movie =
      io::MovieWriter::create(path, images[0].width, images[0].height, fps, &error);
  if (!movie) return error;
  for (int c = 0; c < cycles && !stop; ++c)
    for (const render::RgbImage& img : images)
      if (!movie->add_frame(img.rgb.data(), &error)) return error;
  if (!movie->finish(&error)) return error;
  return stop ? "stopped" : "";
}

}  // namespace

double model_size(const std::vector<double>& points) {
  if (points.size() < 3) return 0.0;
  double lo[3] = {HUGE_VAL, HUGE_VAL, HUGE_VAL}, hi[3] = {-HUGE_VAL, -HUGE_VAL, -HUGE_VAL};
  for (std::size_t i = 0; i + 2 < points.size(); i += 3)
    for (int k = 0; k < 3; ++k) {
      if (!std::isfinite(points[i + k])) return 0.0;
      lo[k] = std::min(lo[k], points[i + k]);
      hi[k] = std::max(hi[k], points[i + k]);
    }
  return std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
}

std::string mode_value_text(const ModeSet& set, const Mode& mode) {
  std::string s;
  if (set.analysis == "buckling") s = "load multiplier " + significant(mode.value, 4);
  else s = significant(mode.value, 4) + (set.value_unit.empty() ? "" : " " + set.value_unit);
  if (mode.rigid_body) s += " (rigid body)";
  return s;
}

ModeAnimation mode_animation(const RunInfo& info, const Frame& base, const ModeSet& set, const Mode& mode,
                             int frames_per_cycle, double amplitude_fraction) {
  const std::size_t n = info.mesh.point_count();
  if (mode.displacement.size() != 3 * n)
    throw std::invalid_argument("mode " + std::to_string(mode.number) + " has " +
                                std::to_string(mode.displacement.size()) + " displacement values, the mesh needs " +
                                std::to_string(3 * n));
  if (base.points.size() != 3 * n)
    throw std::invalid_argument("the state the modes are about has " + std::to_string(base.points.size()) +
                                " coordinates, the mesh needs " + std::to_string(3 * n));
  for (std::size_t i = 0; i < 3 * n; ++i)
    if (!std::isfinite(mode.displacement[i]))
      throw std::invalid_argument("mode " + std::to_string(mode.number) + " has a non-finite displacement at point " +
                                  std::to_string(i / 3));
  ModeAnimation a;
  a.info = info;
  a.info.probes.clear();
  a.info.fields = {{kModeShapeField, "", "|u| / max |u| of the mode"}};
  // the displacement is scaled to a largest translation of 1; its drawn size is a fraction of the model
  double largest = 0.0;
  std::vector<double> magnitude(n);
  for (std::size_t i = 0; i < n; ++i) {
    magnitude[i] = std::hypot(mode.displacement[3 * i], mode.displacement[3 * i + 1], mode.displacement[3 * i + 2]);
    largest = std::max(largest, magnitude[i]);
  }
  for (double& m : magnitude) m = largest > 0 ? m / largest : 0.0;
  const double size = model_size(base.points);
  a.amplitude = largest > 0 ? amplitude_fraction * size / largest : 0.0;  // drawn largest = fraction * size
  const int count = static_cast<int>(set.modes.size());
  a.title = (info.scene_name.empty() ? std::string() : info.scene_name + ": ") + "mode " +
            std::to_string(mode.number) + " of " + std::to_string(count) + ", " + mode_value_text(set, mode);
  char line[200];
  std::snprintf(line, sizeof line, "displacement \u00d7%s, an arbitrary scale:\nlargest drawn = %g %% of the model's size",
                significant(a.amplitude, 4).c_str(), 100.0 * amplitude_fraction);
  a.caption = line;
  if (!set.about.empty()) a.caption += "\nabout the " + set.about;
  const int k_count = std::max(frames_per_cycle, 1);
  for (int k = 0; k < k_count; ++k) {
    Frame f;
    f.step = base.step;
    f.time = static_cast<double>(k) / k_count;  // the phase, in periods
    f.load_factor = base.load_factor;
    f.base_points = base.points;  // the ghost is the state the mode is about
    const double s = a.amplitude * std::sin(2.0 * std::numbers::pi * k / k_count);
    f.points.resize(3 * n);
    for (std::size_t i = 0; i < 3 * n; ++i) f.points[i] = base.points[i] + s * mode.displacement[i];
    f.fields = {magnitude};
    a.frames.push_back(std::move(f));
  }
  return a;
}

nlohmann::ordered_json modes_json(const ModeSet& set) {
  using Json = nlohmann::ordered_json;
  Json rows = Json::array();
  for (const Mode& m : set.modes)
    rows.push_back({{"number", m.number}, {"value", m.value}, {"eigenvalue", m.eigenvalue}, {"rigid_body", m.rigid_body}});
  return {{"analysis", set.analysis},   {"about", set.about},          {"value_name", set.value_name},
          {"value_unit", set.value_unit}, {"value_label", set.value_label}, {"count", set.modes.size()},
          {"modes", rows}};
}

std::vector<int> select_modes(const ModeSet& set, const std::vector<int>& wanted, int cap) {
  std::vector<int> out;
  if (wanted.empty()) {
    for (const Mode& m : set.modes)
      if (cap <= 0 || static_cast<int>(out.size()) < cap) out.push_back(m.number);
    return out;
  }
  for (int number : wanted) {
    if (!find_mode(set, number)) {
      std::string stored;
      for (const Mode& m : set.modes) stored += (stored.empty() ? "" : ", ") + std::to_string(m.number);
      throw InputError("--mode " + std::to_string(number) + ": no such mode; the " + set.analysis +
                       " analysis stored " + (stored.empty() ? std::string("none") : "modes " + stored));
    }
    if (std::find(out.begin(), out.end(), number) == out.end()) out.push_back(number);
  }
  return out;
}

ModeOutputReport write_mode_outputs(OutputFolder& folder, const RunInfo& info, const Frame& base, const ModeSet& set,
                                    const ModeOutputOptions& opt, render::GraphicsContext* given,
                                    const std::atomic<bool>& stop) {
  ModeOutputReport r;
  const auto failed = [&](const std::string& what) {
    if (r.error.empty()) r.error = what;
  };
  std::unique_ptr<render::GraphicsContext> own;
  render::GraphicsContext* gc = given;
  const bool want_pictures = (opt.frames && !opt.modes.empty()) || (opt.plot && !set.modes.empty());
  if (!gc && want_pictures) {
    std::string why;
    own = render::GraphicsContext::create(&why);
    gc = own.get();
    if (!gc) r.no_graphics = why;
  }
  try {
    // ---- each mode as a looping animation
    if (opt.frames && gc) {
      for (int number : opt.modes) {
        if (stop) break;
        const Mode* mode = find_mode(set, number);
        if (!mode) continue;
        ModeAnimation a;
        try {
          a = mode_animation(info, base, set, *mode, opt.frames_per_cycle);
        } catch (const std::invalid_argument& e) {
          failed(e.what());
          continue;
        }
        render::FrameStyle style;
        style.width = opt.width;
        style.height = opt.height;
        style.color_field = kModeShapeField;
        style.color_min = 0.0;  // the normalised magnitude, the same scale for every mode
        style.color_max = 1.0;
        style.title = a.title;
        style.caption = a.caption;
        if (opt.camera_given) {
          style.camera = opt.camera;
        } else {  // oblique: a plate seen along its normal would show its modes as colour alone
          style.camera.automatic = true;
          style.camera.view_direction = {1, -1, 1};
          style.camera.view_up = {0, 0, 1};
        }
        for (const Frame& f : a.frames) style.fit_points.insert(style.fit_points.end(), f.points.begin(), f.points.end());
        render::FrameRenderer renderer(*gc, a.info, style);
        if (!renderer.ok()) {
          failed(renderer.error());
          break;
        }
        const std::string dir = "frames/" + mode_stem(number);
        folder.sub_folder(dir);
        std::vector<std::string> pngs;
        bool complete = true;
        for (std::size_t k = 0; k < a.frames.size() && !stop; ++k) {
          const std::string rel = dir + "/" + frame_png(static_cast<int>(k));
          std::string e;
          if (!renderer.render_png(a.frames[k], folder.file(rel).string(), &e)) {
            failed(e);
            complete = false;
            break;
          }
          r.written.push_back(rel);
          pngs.push_back((folder.path() / rel).string());
          ++r.frames;
        }
        if (!complete || stop) break;
        ++r.modes_animated;
        if (opt.movie) {
          folder.sub_folder("modes");
          const std::string rel = "modes/" + mode_stem(number) + ".mp4";
          const std::string e = write_mode_movie(pngs, folder.file(rel).string(), opt.fps, kModeMovieCycles, stop);
          if (e.empty()) {
            r.movies.push_back(rel);
            r.written.push_back(rel);
          } else if (!stop) {
            failed(rel + ": " + e);
          }
        }
      }
    }
    // ---- the spectrum
    if (opt.plot && gc && !set.modes.empty() && !stop) {
      render::PlotSpec spec;
      spec.title = (set.analysis == "buckling" ? "buckling load multipliers" : "natural frequencies") +
                   std::string(info.scene_name.empty() ? "" : " — " + info.scene_name) +
                   (set.about.empty() ? "" : " — about the " + set.about);
      spec.x_label = "mode number";
      // room beside the first and last mode, whole numbers as ticks (a few dozen at most)
      const double first = set.modes.front().number, last = set.modes.back().number;
      spec.x_min = first - 0.5;
      spec.x_max = last + 0.5;
      if (last - first <= 30)
        for (const Mode& m : set.modes) spec.x_ticks.push_back(m.number);
      spec.y_label = render::axis_title({set.value_name, set.value_unit, set.value_label});
      render::PlotSeries elastic{set.analysis == "buckling" ? "buckling modes" : "elastic modes", {}, {}, true};
      elastic.marker = render::MarkerShape::circle;
      render::PlotSeries rigid{"rigid-body modes (zero frequency)", {}, {}, true};
      rigid.marker = render::MarkerShape::cross;
      const bool label_points = set.modes.size() <= 24;  // more labels would cover each other
      for (const Mode& m : set.modes) {
        render::PlotSeries& s = m.rigid_body ? rigid : elastic;
        s.x.push_back(m.number);
        s.y.push_back(m.value);
        if (label_points) s.point_labels.push_back(significant(m.value, 4));
      }
      for (render::PlotSeries* s : {&elastic, &rigid})
        if (!s->x.empty()) spec.series.push_back(std::move(*s));
      const std::string rel = "plots/spectrum.png";
      folder.sub_folder("plots");
      std::string e;
      if (render::write_plot_png(*gc, spec, folder.file(rel).string(), &e)) {
        r.plot = rel;
        r.written.push_back(rel);
      } else {
        failed("plots/spectrum.png: " + e);
      }
    }
    // ---- every mode as a point vector of the state they are about
    if (opt.vtu && !stop) {
      render::VtuExtras extras;
      std::vector<double> values, rigid;
      for (const Mode& m : set.modes) {
        extras.point_vectors.emplace_back("mode_" + std::to_string(m.number), m.displacement);
        values.push_back(m.value);
        rigid.push_back(m.rigid_body ? 1.0 : 0.0);
      }
      extras.field_arrays = {{"mode_" + (set.value_name.empty() ? std::string("value") : set.value_name), values},
                             {"mode_rigid_body", rigid}};
      folder.sub_folder("export");
      const std::string rel = "export/modes.vtu";
      std::string e;
      if (render::write_vtu(folder.file(rel).string(), info, base, &e, extras)) {
        r.vtu = rel;
        r.written.push_back(rel);
      } else {
        failed(e);
      }
    }
  } catch (const WriteError& e) {  // the manifest could not record a file
    failed(e.what());
  }
  return r;
}

}  // namespace ff::app
