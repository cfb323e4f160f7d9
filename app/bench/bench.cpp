#include "app/bench/bench.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <stdlib.h>

#include "app/io/mesh_import.h"
#include "app/run_session.h"
#include "app/timed_run.h"
#include "core/frame/output_file.h"
#include "core/scene/scene.h"
#include "render/frame_renderer.h"
#include "render/graphics_context.h"

namespace fs = std::filesystem;

namespace ff::app {

namespace {
struct RenderRate {
  double frames_per_second = 0.0;
  std::size_t quads = 0;
  std::string backend;
};

// Headless PNG frames per second of `scene` at width x height: a short run captures up to
// `captured_frames` frames, the first render builds the shaders, then `renders` frames are
// rendered and written as PNG, cycling through the captured ones (the geometry changes every time).
RenderRate render_rate(const std::string& scene, const std::vector<std::string>& overrides, int width, int height,
                       int captured_frames, int renders) {
  RenderRate out;
  scene::LoadedScene s = scene::load_scene(resolve_scene(scene), overrides, io::scene_context());
  std::vector<Frame> captured;
  std::atomic<bool> stop{false};
  s.simulation->run(
      [&](Frame&& f) { if (static_cast<int>(captured.size()) < captured_frames) captured.push_back(std::move(f)); },
      stop);
  std::string err;
  auto gc = render::GraphicsContext::create(&err);
  if (!gc || captured.empty()) return out;
  out.backend = gc->backend() + " / " + gc->gl_renderer();
  out.quads = s.simulation->info().mesh.quads.size() / 4;
  render::FrameStyle style;
  style.width = width > 0 ? width : s.output.width;
  style.height = height > 0 ? height : s.output.height;
  style.color_field = s.output.color_field == "none" ? "" : s.output.color_field;
  style.title = s.name;
  render::FrameRenderer renderer(*gc, s.simulation->info(), style);
  const std::string folder = make_bench_folder("frames");
  if (folder.empty()) return out;
  const fs::path dir = folder;
  std::vector<fs::path> written;
  written.push_back(dir / "warmup.png");
  renderer.render_png(captured.front(), written.back().string(), &err);
  const auto t0 = std::chrono::steady_clock::now();
  int n = 0;
  for (int i = 0; i < renders; ++i) {
    std::string name = "f";  // appended, not summed: GCC 12 warns (-Wrestrict) on "f" + ... + ".png"
    name += std::to_string(i);
    name += ".png";
    written.push_back(dir / name);
    if (renderer.render_png(captured[i % captured.size()], written.back().string(), &err)) ++n;
  }
  const double elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  std::error_code ec;  // only what this bench wrote, then its own (now empty) folder
  for (const fs::path& f : written) fs::remove(f, ec);
  fs::remove(dir, ec);
  out.frames_per_second = n / elapsed;
  return out;
}
}  // namespace

int run_bench(const BenchOptions& opt, const std::atomic<bool>& stop) {
  std::printf("| scene | status | steps | set-up [ms] | stepping [ms] | steps/s |\n|---|---|---|---|---|---|\n");
  nlohmann::ordered_json scenes = nlohmann::ordered_json::object();
  double efg_total[2] = {0, 0}, fem_total[2] = {0, 0}, efg_run[2] = {0, 0}, fem_run[2] = {0, 0};
  for (const std::string& name : bundled_scenes()) {
    if (name.rfind("hub_beam", 0) != 0 || stop) continue;
    const TimedRun r = timed_run_median(resolve_scene(name), {}, opt.repeat, stop);
    const double sps = r.totals.steps / r.run_s;
    std::printf("| %s | %s | %lld | %.2f | %.2f | %.0f |\n", name.c_str(), to_string(r.outcome.status),
                static_cast<long long>(r.totals.steps), 1e3 * r.setup_s, 1e3 * r.run_s, sps);
    std::fflush(stdout);
    scenes[name] = {{"status", to_string(r.outcome.status)},
                    {"steps", static_cast<long long>(r.totals.steps)},
                    {"setup_s", r.setup_s},
                    {"run_s", r.run_s},
                    {"steps_per_second", sps}};
    const int k = name.find("tau7") != std::string::npos ? 1 : 0;
    if (name == "hub_beam_efg_tau1" || name == "hub_beam_efg_tau7") efg_total[k] = r.total_s(), efg_run[k] = r.run_s;
    if (name == "hub_beam_fem_tau1" || name == "hub_beam_fem_tau7") fem_total[k] = r.total_s(), fem_run[k] = r.run_s;
  }
  std::printf("\n| ratio (same run) | tau0 = 1 | tau0 = 7 |\n|---|---|---|\n");
  std::printf("| EFG / FEM wall time, set-up + stepping | %.3f | %.3f |\n", efg_total[0] / fem_total[0],
              efg_total[1] / fem_total[1]);
  std::printf("| EFG / FEM wall time, stepping only | %.3f | %.3f |\n", efg_run[0] / fem_run[0], efg_run[1] / fem_run[1]);
  // the hub-beam paper scene at its own frame size, then a shell mesh of about 10k quads (the double
  // pendulum at 71x71 elements per shell, three steps) at 1280x720
  const RenderRate hub = stop ? RenderRate{} : render_rate("hub_beam_efg_tau1", {}, 0, 0, 60, 60);
  std::printf("\nheadless frames/s at the default size (960x720, %s): %.1f\n", hub.backend.c_str(),
              hub.frames_per_second);
  const RenderRate shell =
      stop ? RenderRate{}
           : render_rate("double_pendulum_shells",
                         {"part[0].n1=71", "part[0].n2=71", "part[1].n1=71", "part[1].n2=71", "solver.end=1.5e-3",
                          "solver.output_every=1", "solver.policy=\"full\""},
                         1280, 720, 4, 30);
  std::printf("headless frames/s, %zu-quad shell mesh with PNG at 1280x720: %.1f\n", shell.quads,
              shell.frames_per_second);
  if (!opt.out_file.empty()) {
    const nlohmann::ordered_json root = {{"repeat", opt.repeat},
                                         {"scenes", scenes},
                                         {"efg_over_fem_total_tau1", efg_total[0] / fem_total[0]},
                                         {"efg_over_fem_total_tau7", efg_total[1] / fem_total[1]},
                                         {"efg_over_fem_stepping_tau1", efg_run[0] / fem_run[0]},
                                         {"efg_over_fem_stepping_tau7", efg_run[1] / fem_run[1]},
                                         {"frames_per_second", hub.frames_per_second},
                                         {"shell_quads", shell.quads},
                                         {"shell_frames_per_second_1280x720", shell.frames_per_second},
                                         {"render_backend", hub.backend}};
    if (!write_bench_json(opt.out_file, root.dump(2) + "\n")) return 1;
  }
  return stop ? 130 : 0;
}

int run_scene_bench(const BenchOptions& opt, const std::atomic<bool>& stop) {
  // every scene is found and read before the first one is timed: a typo ends the command at once
  std::vector<std::string> paths;
  for (const std::string& name : opt.scenes) {
    paths.push_back(resolve_scene(name));
    scene::load_scene(paths.back(), opt.overrides, io::scene_context());
  }
  std::printf("Whole runs, solver only (no files, no frames), median of %d; wall time on this machine\n\n", opt.repeat);
  std::printf("| scene | status | steps | corrections | matrix updates | set-up [s] | solve [s] | total [s] |\n"
              "|---|---|---|---|---|---|---|---|\n");
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  int code = 0;
  for (std::size_t i = 0; i < opt.scenes.size() && !stop; ++i) {
    const std::string &name = opt.scenes[i], &path = paths[i];
    const TimedRun r = timed_run_median(path, opt.overrides, opt.repeat, stop);
    std::printf("| %s | %s | %lld | %lld | %lld | %.3f | %.3f | %.3f |\n", name.c_str(), to_string(r.outcome.status),
                r.totals.steps, r.totals.newton_iterations, r.totals.jacobian_updates, r.setup_s, r.run_s,
                r.total_s());
    std::fflush(stdout);
    nlohmann::ordered_json row = {{"scene", name},
                                  {"path", path},
                                  {"status", to_string(r.outcome.status)},
                                  {"steps", r.totals.steps},
                                  {"newton_iterations", r.totals.newton_iterations},
                                  {"jacobian_updates", r.totals.jacobian_updates},
                                  {"setup_s", r.setup_s},
                                  {"run_s", r.run_s},
                                  {"total_s", r.total_s()}};
    if (r.outcome.status != RunStatus::completed) {
      row["reason"] = r.outcome.reason;
      std::fprintf(stderr, "%s did not complete (%s): %s\n", name.c_str(), to_string(r.outcome.status),
                   r.outcome.reason.c_str());
      if (code == 0) code = exit_code(r.outcome);
    }
    rows.push_back(std::move(row));
  }
  if (!opt.out_file.empty()) {
    const nlohmann::ordered_json root = {{"repeat", opt.repeat}, {"overrides", opt.overrides}, {"scenes", rows}};
    if (!write_bench_json(opt.out_file, root.dump(2) + "\n")) return 1;
  }
  return stop ? 130 : code;
}

std::string make_bench_folder(const std::string& name) {
  std::string pattern = (fs::temp_directory_path() / ("flexframe_bench_" + name + ".XXXXXX")).string();
  return ::mkdtemp(pattern.data()) ? pattern : std::string();
}

double median_of(std::vector<double> v) {
  if (v.empty()) return std::nan("");
  std::sort(v.begin(), v.end());
  const std::size_t m = v.size() / 2;
  return v.size() % 2 ? v[m] : 0.5 * (v[m - 1] + v[m]);
}

// the file the user named, opened as every output is (no link, hard link, FIFO or device at it)
bool write_bench_json(const std::string& path, const std::string& text) {
  std::string why;
  std::FILE* f = open_output_stream(path, &why);
  int error = 0;
  if (f) {
    if (std::fwrite(text.data(), 1, text.size(), f) != text.size() || std::fflush(f) != 0) error = errno;
    if (std::fclose(f) != 0 && error == 0) error = errno;  // a full disk may only show here
    if (error != 0) why = std::strerror(error);
  }
  if (f && error == 0) return true;
  std::fprintf(stderr, "error: cannot write %s: %s\n", path.c_str(), why.c_str());
  return false;
}

}  // namespace ff::app
