#include "app/replay.h"

#include "app/output_folder.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <tuple>

#include "app/frame_outputs.h"
#include "app/io/results.h"
#include "app/mode_outputs.h"
#include "app/plots.h"
#include "app/input_error.h"
#include "app/view_options.h"
#include "core/scene/scene.h"
#include "render/frame_layout.h"
#include "render/frame_renderer.h"
#include "render/graphics_context.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {

// a scene key as stored in /run/settings (TOML value text), quotes removed; "" if absent
std::string setting(const RunInfo& info, const std::string& key) {
  for (const auto& [k, v] : info.settings) {
    if (k != key) continue;
    if (v.size() >= 2 && v.front() == '"' && v.back() == '"') return v.substr(1, v.size() - 2);
    return v;
  }
  return "";
}

double setting_number(const RunInfo& info, const std::string& key, double fallback) {
  const std::string s = setting(info, key);
  char* end = nullptr;
  const double v = std::strtod(s.c_str(), &end);
  return !s.empty() && end == s.c_str() + s.size() && std::isfinite(v) ? v : fallback;
}

// "[0.6, 0.9, -0.6]" -> {0.6, 0.9, -0.6}; anything unreadable -> {}
std::vector<double> setting_numbers(const RunInfo& info, const std::string& key) {
  std::string s = setting(info, key);
  std::replace_if(s.begin(), s.end(), [](char c) { return c == '[' || c == ']' || c == ','; }, ' ');
  std::istringstream in(s);
  std::vector<double> out;
  for (double v; in >> v;) out.push_back(v);
  return in.eof() ? out : std::vector<double>{};
}

std::string png_name(std::size_t k) {
  char name[32];
  std::snprintf(name, sizeof name, "frame_%05zu.png", k);
  return name;
}

}  // namespace

int replay(const ReplayOptions& opt, const std::atomic<bool>& stop) {
  // ---- input, all checked before anything is written
  const std::string path = fs::is_directory(opt.results) ? (fs::path(opt.results) / "results.h5").string() : opt.results;
  std::string err;
  const std::unique_ptr<io::ResultReader> reader = io::ResultReader::open(path, &err);
  if (!reader) throw InputError(err);
  // a damaged file is bad input: found before anything is written, not midway through the frames
  if (const std::string damage = reader->verify(); !damage.empty()) throw InputError(damage);
  const RunInfo& info = reader->info();

  std::string field_name = opt.field ? *opt.field : setting(info, "output.color_field");
  if (!opt.field && field_index(info, field_name) < 0)  // the run's choice, or else the first field
    field_name = info.fields.empty() ? "none" : info.fields.front().name;
  const int field = field_name == "none" ? -1 : field_index(info, field_name);
  if (field_name != "none" && field < 0)
    throw InputError("--field '" + field_name + "': " + path + " stores no such field; available: " +
                     field_names(info) + " (or none)");
  int width = static_cast<int>(setting_number(info, "output.width", 960));
  int height = static_cast<int>(setting_number(info, "output.height", 720));
  if (!opt.size.empty()) std::tie(width, height) = parse_size(opt.size);
  const render::Camera camera = parse_camera(opt.camera);
  const ExportFormats formats = opt.export_formats.empty() ? ExportFormats{} : parse_export_formats(opt.export_formats);
  if (opt.frame_every < 1) throw InputError("--frame-every must be at least 1");
  if (opt.movie && !opt.frames) throw InputError("--movie needs the frames: drop --no-frames");
  if (opt.fps < 1 || opt.fps > 240) throw InputError("--fps must be 1..240");
  // the modes of a stored eigen-analysis: --mode picks among them
  const ModeSet* modes = reader->modes();
  if (!opt.modes.empty() && !modes)
    throw InputError("--mode: " + path + " stores no modes (it holds no modal or buckling analysis)");
  if (!opt.modes.empty() && !opt.frames) throw InputError("--mode animates modes as PNG frames: drop --no-frames");
  const std::vector<int> mode_selection = modes ? select_modes(*modes, opt.modes, 0) : std::vector<int>{};

  // ---- what the stored run is
  const RunOutcome outcome = reader->outcome();
  const std::size_t count = reader->frame_count();
  const std::vector<double> times = reader->times();
  std::printf("replay of %s (%s): %zu stored frames", info.scene_name.c_str(), path.c_str(), count);
  if (count > 0) std::printf(", t = %g .. %g %s", times.front(), times.back(), info.time_unit.c_str());
  std::printf("\n  stored run: %s at t = %g %s after %lld steps\n", to_string(outcome.status), outcome.stop_time,
              info.time_unit.c_str(), static_cast<long long>(outcome.steps));
  if (!outcome.reason.empty()) std::printf("  reason: %s\n", outcome.reason.c_str());

  // a file without a frame is bad input (exit 2), found before anything is written: replay was
  // asked for frames, plots or exports and can make none, which exit 0 would call a success
  if (count == 0)
    throw InputError(path + " holds no complete frame: nothing to replay (stored run: " + to_string(outcome.status) +
                     " after " + std::to_string(outcome.steps) + " steps)");
  const fs::path dir = opt.out_dir.empty() ? fs::absolute(path).parent_path() / "replay" : fs::path(opt.out_dir);
  const fs::path frames_dir = dir / "frames", plots_dir = dir / "plots";
  // the folder's lock before any file in it is touched; an earlier replay's recorded outputs go
  OutputFolder folder(dir, "replay");
  for (const char* earlier : {"frames/", "plots/", "export/", "modes/", "movie.mp4"}) folder.remove_earlier(earlier);
  const std::vector<std::size_t> selection = frame_selection(count, opt.frame_every, true);
  int status = 0;

  // ---- one pass over the selection: the colour range and the motion the camera must hold (the
  // policy `run` shares: frame_outputs.h)
  SequenceView sequence;
  const double deformation_scale = setting_number(info, "output.deformation_scale", 1.0);
  if (opt.frames || formats.gltf || formats.obj) {
    sequence = sequence_view(
        selection.size(), [&](std::size_t k) { return reader->frame(selection[k]); }, field, deformation_scale, stop);
    if (stop) return 130;
  }
  // ---- frames
  int rendered = 0;
  if (opt.frames) {
    folder.sub_folder("frames");
    render::FrameStyle style;
    style.width = width;
    style.height = height;
    style.deformation_scale = deformation_scale;
    style.color_field = field >= 0 ? field_name : "";
    style.color_min = sequence.color_range[0];  // one range for the whole sequence
    style.color_max = sequence.color_range[1];
    style.title = info.scene_name;
    if (outcome.status != RunStatus::completed) style.title += std::string(" (") + to_string(outcome.status) + ")";
    // the stored scene's camera path ([[timeline]] camera keys), followed unless --camera is given
    std::vector<scene::CameraKey> camera_path;
    if (opt.camera == "auto" && info.scene_text.find("timeline") != std::string::npos) {
      try {
        camera_path = scene::camera_path_from_text(info.scene_text, info.scene_path + " (as stored in " + path + ")");
      } catch (const scene::SceneError& e) {
        std::fprintf(stderr, "warning: the stored scene's timeline cannot be read, camera path ignored:\n%s\n", e.what());
      }
    }
    const std::string view = setting(info, "output.view");
    if (camera_path.empty() && opt.camera == "auto" && (view == "iso" || view == "front" || view == "top")) {
      style.camera = scene_camera(info.mesh, view, setting_numbers(info, "output.view_center"),
                                  setting_number(info, "output.view_radius", 0.0), sequence.fit_points);
    } else {
      style.camera = camera_path.empty() ? camera : *camera_on_path(camera_path, reader->frame(selection[0]).time);
      style.fit_points = sequence.fit_points;
    }
    std::unique_ptr<render::GraphicsContext> gc = render::GraphicsContext::create(&err);
    std::unique_ptr<render::FrameRenderer> renderer;
    if (gc) {
      renderer = std::make_unique<render::FrameRenderer>(*gc, info, style);
      if (!renderer->ok()) err = renderer->error();
    }
    if (gc && renderer->ok()) {
      for (std::size_t k = 0; k < selection.size() && !stop; ++k) {
        const Frame f = reader->frame(selection[k]);
        if (!camera_path.empty()) renderer->set_camera(*camera_on_path(camera_path, f.time));
        if (!renderer->render_png(f, folder.file("frames/" + png_name(k)).string(), &err)) break;
        ++rendered;
      }
      renderer.reset();
    }
    std::printf("  frames: %d of %zu PNG (%dx%d, colour: %s) in %s\n", rendered, selection.size(), width, height,
                field >= 0 ? field_name.c_str() : "none", frames_dir.string().c_str());
    if (rendered < static_cast<int>(selection.size()) && !stop) {
      std::fprintf(stderr, "error: frames not rendered: %s\n", err.c_str());
      status = 1;
    }
  }

  // ---- plots of every probe over the stored frames
  if (opt.plots && !stop) {
    folder.sub_folder("plots");
    RunInfo plot_info = info;  // the plot titles say when the stored run did not complete
    if (outcome.status != RunStatus::completed) plot_info.scene_name += std::string(" (") + to_string(outcome.status) + ")";
    PlotHistory history;
    history.time = times;
    for (const Quantity& q : info.probes) history.probes.push_back(reader->probe_series(q.name));
    std::string plot_error;
    const auto files = write_run_plots(plot_info, history, plots_dir.string(), &plot_error);
    for (const std::string& f : files) folder.record("plots/" + fs::path(f).filename().string());
    std::printf("  plots: %zu in %s\n", files.size(), plots_dir.string().c_str());
    if (!plot_error.empty()) {
      std::fprintf(stderr, "error: plots: %s\n", plot_error.c_str());
      status = 1;
    }
  }

  // ---- movie of the frames
  if (opt.movie && rendered > 0 && !stop) {
    const MovieReport m = write_movie(frames_dir.string(), folder.file("movie.mp4").string(), opt.fps, stop);
    if (m.ok) {
      std::printf("  movie: %s (%s, %d frames at %d/s)\n", m.path.c_str(), m.codec.c_str(), m.frames, opt.fps);
    } else {
      std::fprintf(stderr, "error: no movie: %s\n", m.message.c_str());
      status = 1;
    }
  }

  // ---- mesh exports
  if (formats.any() && !stop) {
    const ExportReport x =
        export_frames(*reader, selection, formats, folder.sub_folder("export").string(), field, sequence.color_range, stop);
    for (const std::string& f : x.written) folder.record("export/" + f);
    std::printf("  export: %d frames in %s", x.frames, (dir / "export").string().c_str());
    for (const std::string& f : x.files) std::printf(" %s", fs::path(f).filename().c_str());
    std::printf("%s\n", x.files.empty() ? "" : " ...");
    if (!x.error.empty()) {
      std::fprintf(stderr, "error: export: %s\n", x.error.c_str());
      status = 1;
    }
  }
  // ---- the modes: animations, spectrum, export/modes.vtu, about the last stored frame
  if (modes && !stop) {
    ModeOutputOptions mo;
    mo.modes = mode_selection;
    mo.frames = opt.frames;
    mo.plot = opt.plots;
    mo.movie = opt.movie;
    mo.vtu = formats.vtu;
    mo.fps = opt.fps;
    mo.width = width;
    mo.height = height;
    if (opt.camera != "auto") mo.camera = camera, mo.camera_given = true;
    const ModeOutputReport m = write_mode_outputs(folder, info, reader->frame(count - 1), *modes, mo, nullptr, stop);
    std::printf("  modes: %zu stored (%s analysis, about the %s); %d animated, %d PNG in %s/mode_NN/", modes->modes.size(),
                modes->analysis.c_str(), modes->about.c_str(), m.modes_animated, m.frames, frames_dir.string().c_str());
    if (!m.plot.empty()) std::printf(", %s", m.plot.c_str());
    for (const std::string& f : m.movies) std::printf(", %s", f.c_str());
    if (!m.vtu.empty()) std::printf(", %s", m.vtu.c_str());
    std::printf("\n");
    for (const Mode& mode : modes->modes)
      std::printf("    mode %2d  %s\n", mode.number, mode_value_text(*modes, mode).c_str());
    if (!m.no_graphics.empty()) {
      std::fprintf(stderr, "error: mode pictures not drawn: %s\n", m.no_graphics.c_str());
      status = 1;
    }
    if (!m.error.empty()) {
      std::fprintf(stderr, "error: modes: %s\n", m.error.c_str());
      status = 1;
    }
  }
  if (stop) {
    std::printf("  replay stopped (Ctrl-C)\n");
    return 130;
  }
  return status;
}

}  // namespace ff::app
