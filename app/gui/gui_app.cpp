#include "app/gui/gui_app.h"

#define GL_SILENCE_DEPRECATION
#include <GLFW/glfw3.h>
#include <backends/imgui_impl_glfw.h>
#include <backends/imgui_impl_opengl3.h>
#include <imgui.h>
#include <imgui_stdlib.h>
#include <stb_image_write.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <cfloat>
#include <chrono>
#include <cerrno>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <deque>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <set>
#include <tuple>

#include "app/io/mesh_import.h"
#include "app/gui/actions.h"
#include "app/gui/param_editor.h"
#include "app/gui/scene_draft.h"
#include "app/gui/setup_panel.h"
#include "app/gui/sim_worker.h"
#include "app/mode_outputs.h"
#include "app/run_session.h"
#include "app/view_options.h"
#include "core/frame/output_file.h"
#include "core/scene/scene.h"
#include "core/scene/scene_edit.h"
#include "render/frame_renderer.h"
#include "render/graphics_context.h"

namespace ff::app::gui {
namespace {

namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;

constexpr const char* kHeadlessHint =
    "Without a display use the headless verbs: `flexframe run SCENE` (frames, plots, results.h5, "
    "summary.json) and `flexframe replay RUN` (frames again from a results.h5); or give the GUI a "
    "virtual display: `xvfb-run -a flexframe gui SCENE --actions FILE`.";

// layout (pixels at scale 1)
constexpr float kSideWidth = 390.0f;
constexpr float kPlotHeight = 250.0f;
constexpr float kStatusHeight = 30.0f;
constexpr double kViewportMinInterval = 1.0 / 20.0;  // viewport renders at most 20 times per second
constexpr double kMinFrameInterval = 1.0 / 60.0;     // the window draws at most 60 times per second
constexpr double kModePeriodSeconds = 1.2;  // a mode animation's period in the view (24 pictures at 20/s)
// Idle, the window sleeps in glfwWaitEventsTimeout until input, the solver thread's wake-up
// (glfwPostEmptyEvent) or a scripted wait's end; this timeout only bounds how late a Ctrl-C is seen.
constexpr double kIdleWake = 0.5;
// ImGui settles hover and layout changes over a frame or two after an input or a change
constexpr int kSettleFrames = 3;
constexpr std::size_t kMaxPlotPoints = 800;
// the probed node's marker in the viewport: a green none of the field colours comes near
constexpr std::array<double, 3> kProbeMarkerColor = {0.10, 0.90, 0.30};
constexpr double kProbeMarkerPx = 14.0;

std::string g_glfw_error;
void on_glfw_error(int, const char* text) { g_glfw_error = text ? text : "unknown GLFW error"; }

// Input marks the window for redrawing. Installed before ImGui's GLFW backend, which chains
// them (all are called on the main thread, inside glfwWaitEvents*).
bool g_input_seen = false;
void on_input_cursor(GLFWwindow*, double, double) { g_input_seen = true; }
void on_input_button(GLFWwindow*, int, int, int) { g_input_seen = true; }
void on_input_scroll(GLFWwindow*, double, double) { g_input_seen = true; }
void on_input_key(GLFWwindow*, int, int, int, int) { g_input_seen = true; }
void on_input_char(GLFWwindow*, unsigned int) { g_input_seen = true; }
void on_input_focus(GLFWwindow*, int) { g_input_seen = true; }
void on_input_enter(GLFWwindow*, int) { g_input_seen = true; }
void on_window_size(GLFWwindow*, int, int) { g_input_seen = true; }
void on_window_refresh(GLFWwindow*) { g_input_seen = true; }
// files dropped on the window, opened by the loop (a scene, or a mesh as a new problem's part)
std::vector<std::string> g_dropped;
void on_drop(GLFWwindow*, int count, const char** paths) {
  for (int i = 0; i < count; ++i) g_dropped.emplace_back(paths[i]);
  g_input_seen = true;
}
void install_input_callbacks(GLFWwindow* window) {
  glfwSetCursorPosCallback(window, on_input_cursor);
  glfwSetMouseButtonCallback(window, on_input_button);
  glfwSetScrollCallback(window, on_input_scroll);
  glfwSetKeyCallback(window, on_input_key);
  glfwSetCharCallback(window, on_input_char);
  glfwSetWindowFocusCallback(window, on_input_focus);
  glfwSetCursorEnterCallback(window, on_input_enter);
  glfwSetFramebufferSizeCallback(window, on_window_size);
  glfwSetWindowRefreshCallback(window, on_window_refresh);
  glfwSetDropCallback(window, on_drop);
}

/// Where a new problem's text lives until it is saved: the working folder (relative files of a
/// later Save are read from there); nothing is written there until Save.
std::string new_problem_path(const std::string& name) { return (fs::current_path() / (name + ".toml")).string(); }

/// A scene for the window to open: its text, the path naming it (relative files are read from its
/// folder) and the file it came from ("" for a new problem).
struct SceneToOpen {
  std::string text, path, from;
};

/// A new static or dynamic problem (scene_draft.h).
SceneToOpen new_problem(const std::string& analysis) {
  const std::string name = "new_" + analysis;
  return {new_scene_text(analysis, name), new_problem_path(name), ""};
}

/// A scene file or a bundled scene's name; any other file (an extension other than .toml: a mesh
/// or CAD part, which the mesh reader then reads or refuses) as the one part of a new static
/// problem. Throws as resolve_scene and read_scene_text do.
SceneToOpen scene_to_open(const std::string& name) {
  const fs::path p(name);
  std::string ext = p.extension().string();
  for (char& c : ext) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (!ext.empty() && ext != ".toml") {
    const std::string stem = p.stem().string();
    return {mesh_scene_text(fs::absolute(p).string(), stem), new_problem_path(stem), name};
  }
  const std::string path = resolve_scene(name);
  return {scene::read_scene_text(path), path, path};
}

/// The scene edit an add, remove, preset or use-edge action asks for (setup_panel.h); nullopt for
/// other actions.
std::optional<SetupRequest> scene_edit_of(const Action& a) {
  const std::string entry = a.key + "[" + std::to_string(a.count) + "]";
  switch (a.kind) {
    case Action::Kind::add: return add_entry(a.key, a.fields);
    case Action::Kind::remove: return remove_entry(a.key, static_cast<std::size_t>(a.count));
    case Action::Kind::preset: return material_preset(static_cast<std::size_t>(a.count), a.text);
    case Action::Kind::use_edge: return use_patch_edge(entry, a.patch, a.edge);
    default: return std::nullopt;
  }
}


// λ and other Greek letters: the default ImGui font (ProggyClean) has Latin-1 only, so Greek
// glyphs are merged in from a system TTF; without one the window spells the names out.
bool g_greek_glyphs = false;
const char* kGreekFonts[] = {"/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf",
                             "/usr/share/fonts/dejavu/DejaVuSans.ttf",
                             "/usr/share/fonts/TTF/DejaVuSans.ttf",
                             "/usr/share/fonts/truetype/liberation/LiberationSans-Regular.ttf",
                             "/usr/share/fonts/truetype/freefont/FreeSans.ttf"};
void load_fonts() {
  ImGuiIO& io = ImGui::GetIO();
  io.Fonts->AddFontDefault();
  for (const char* path : kGreekFonts) {
    std::error_code ec;
    if (!fs::exists(path, ec)) continue;
    ImFontConfig merge;
    merge.MergeMode = true;
    merge.PixelSnapH = true;
    static const ImWchar greek[] = {0x0370, 0x03FF, 0};  // Greek and Coptic
    if (io.Fonts->AddFontFromFileTTF(path, 13.0f, &merge, greek) != nullptr) {
      g_greek_glyphs = true;
      return;
    }
  }
  std::fprintf(stderr, "note: no font with Greek letters found (looked for DejaVu Sans); the window writes 'lambda'\n");
}
const char* lambda_text() { return g_greek_glyphs ? "\u03bb" : "lambda"; }

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string fmt(const char* format, double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, format, v);
  return buf;
}

/// A number for a plot label: 3 significant digits, the exponent without padding ("2.32e-5").
std::string short_number(double v) {
  std::string t = fmt("%.3g", v);
  const std::size_t e = t.find('e');
  if (e == std::string::npos) return t == "-0" ? "0" : t;
  std::string mantissa = t.substr(0, e), exponent = t.substr(e + 1);
  const bool negative = !exponent.empty() && exponent[0] == '-';
  exponent = exponent.substr(exponent[0] == '-' || exponent[0] == '+' ? 1 : 0);
  exponent.erase(0, std::min(exponent.find_first_not_of('0'), exponent.size() - 1));
  return mantissa + "e" + (negative ? "-" : "") + exponent;
}

/// `text` cut at the end (with "...") to fit `width` pixels of the current font.
std::string fit_text(std::string text, float width) {
  if (ImGui::CalcTextSize(text.c_str()).x <= width) return text;
  while (!text.empty() && ImGui::CalcTextSize((text + "...").c_str()).x > width) {
    // drop the last character, all of its UTF-8 bytes
    std::size_t last = text.size() - 1;
    while (last > 0 && (static_cast<unsigned char>(text[last]) & 0xC0) == 0x80) --last;
    text.erase(last);
  }
  return text + "...";
}

/// The window's readout of a probed node (the actions' `probe NODE` prints the same).
std::string node_readout(const Sample& s, const char* separator) {
  char buf[256];
  std::snprintf(buf, sizeof buf, "node %d at (%.4g, %.4g, %.4g)%s|x - X| = %.4g", s.node, s.node_position[0],
                s.node_position[1], s.node_position[2], separator, s.node_displacement);
  std::string text = buf;
  if (s.has_deflection) text += ", elastic |x - x_base| = " + fmt("%.4g", s.node_deflection);
  return text;
}

/// Writes the current framebuffer (RGB) as PNG, top row first.
bool write_window_png(const std::string& path, int w, int h, std::string* error) {
  std::vector<unsigned char> rgb(3 * static_cast<std::size_t>(w) * h), flipped(rgb.size());
  glPixelStorei(GL_PACK_ALIGNMENT, 1);
  glReadBuffer(GL_BACK);
  glReadPixels(0, 0, w, h, GL_RGB, GL_UNSIGNED_BYTE, rgb.data());
  const std::size_t row = 3 * static_cast<std::size_t>(w);
  for (int y = 0; y < h; ++y) std::copy_n(&rgb[(h - 1 - y) * row], row, &flipped[y * row]);
  if (!path.empty()) {
    std::error_code ec;
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
  }
  // opened as every output is: no link, hard link, FIFO or device at the named path
  std::string why;
  std::FILE* file = open_output_stream(path, &why);
  if (!file) {
    *error = "could not write " + path + ": " + why;
    return false;
  }
  const auto put = [](void* context, void* data, int size) {
    std::fwrite(data, 1, static_cast<std::size_t>(size), static_cast<std::FILE*>(context));
  };
  const bool encoded = stbi_write_png_to_func(put, file, w, h, 3, flipped.data(), static_cast<int>(row)) != 0;
  const bool written = std::ferror(file) == 0 && std::fflush(file) == 0;
  if (std::fclose(file) != 0 || !encoded || !written) {
    *error = "could not write " + path + (encoded ? ": " + std::string(std::strerror(errno)) : std::string());
    return false;
  }
  return true;
}

/// The VTK view of the latest frame, drawn off screen by render/ and shown as a texture.
class Viewport {
 public:
  explicit Viewport(GLFWwindow* window) : window_(window) {}
  ~Viewport() {
    mode_renderer_.reset();
    renderer_.reset();
    gc_.reset();
    glfwMakeContextCurrent(window_);
    if (texture_) glDeleteTextures(1, &texture_);
  }

  /// A new run (new mesh): the renderer is rebuilt at the next draw.
  void set_run(std::shared_ptr<const RunInfo> info, const scene::OutputSettings& out, const std::string& title) {
    const bool same_mesh = info_ && info->mesh.reference_points == info_->mesh.reference_points;
    if (!same_mesh) camera_.reset();
    else if (renderer_) camera_ = renderer_->current_camera();
    info_ = std::move(info);
    output_ = out;
    title_ = title;
    if (!same_mesh) fit_points_.clear(), user_camera_ = false;
    show_mode(std::nullopt);
    release();
  }
  /// Animates a mode (mode_outputs.h: the pictures `run` writes, looping) instead of the run's
  /// frames, until nullopt.
  void show_mode(std::optional<ModeAnimation> animation, int number = 0) {
    mode_ = std::move(animation);
    mode_number_ = number;
    mode_renderer_.reset();
    glfwMakeContextCurrent(window_);
    mode_shown_ = -1;
    mode_start_ = Clock::now();
    dirty_ = true;
  }
  /// The mode animated, 0 for none.
  int mode_number() const { return mode_ ? mode_number_ : 0; }
  void set_frame(const Frame& f) {
    frame_ = f;
    dirty_ = true;
    // the automatic view follows the deforming body: when a frame leaves the box the view was
    // fitted to, the box grows by this frame's and the view is fitted again (not after the user
    // moved the camera, nor along a scene's camera path, which sets its own view)
    if (user_camera_ || camera_ || !output_.camera_path.empty() || f.points.size() < 3) return;
    Eigen::AlignedBox3d box;
    for (std::size_t i = 0; i + 2 < f.points.size(); i += 3) box.extend(Eigen::Vector3d(f.points[i], f.points[i + 1], f.points[i + 2]));
    if (fitted_.isEmpty()) {
      for (std::size_t i = 0; info_ && i + 2 < info_->mesh.reference_points.size(); i += 3)
        fitted_.extend(Eigen::Vector3d(info_->mesh.reference_points[i], info_->mesh.reference_points[i + 1],
                                       info_->mesh.reference_points[i + 2]));
    }
    const double slack = 0.02 * fitted_.diagonal().norm();
    Eigen::AlignedBox3d grown = fitted_;
    grown.min().array() -= slack;
    grown.max().array() += slack;
    if (grown.contains(box)) return;
    fitted_.extend(box);
    for (int c = 0; c < 8; ++c) {
      const Eigen::Vector3d corner = box.corner(static_cast<Eigen::AlignedBox3d::CornerType>(c));
      fit_points_.insert(fit_points_.end(), {corner.x(), corner.y(), corner.z()});
    }
    release();
  }
  const std::optional<Frame>& frame() const { return frame_; }
  /// A frame or view waits to be rendered by update() (so the window must draw again).
  bool needs_render(int w, int h) const {
    if (mode_) return w >= 32 && h >= 32;  // an animation: the window keeps drawing (update() paces it)
    return info_ && frame_ && dirty_ && w >= 32 && h >= 32 && (renderer_ || error_.empty());
  }

  /// Re-renders if the frame or view changed (at most 20 per second unless forced).
  void update(int w, int h, bool force) {
    if (mode_) return update_mode(w, h, force);
    if (!info_ || !frame_ || w < 32 || h < 32) return;
    if (renderer_ && (renderer_->width() != w || renderer_->height() != h)) {
      camera_ = renderer_->current_camera();
      release();
    }
    if (!renderer_ && error_.empty()) build(w, h);
    if (!renderer_ || !dirty_) return;
    if (!force && seconds_since(last_render_) < kViewportMinInterval) return;
    // the scene's camera path, as `run` and `replay` follow it, until the user takes the camera
    if (!user_camera_ && !view_ && !output_.camera_path.empty()) {
      if (const std::optional<render::Camera> c = camera_on_path(output_.camera_path, frame_->time)) renderer_->set_camera(*c);
    }
    std::string err;
    if (renderer_->render_rgb(*frame_, &rgb_, &err)) {
      upload(renderer_->width(), renderer_->height());
      error_.clear();
    } else {
      error_ = err;
    }
    glfwMakeContextCurrent(window_);
    dirty_ = false;
    last_render_ = Clock::now();
  }

  /// A node under pixel (x, y) of the view (origin top left), as a click picks it; -1 for none.
  int node_at(double x, double y) {
    if (!renderer_) return -1;
    const int n = renderer_->pick_point(x, y);
    glfwMakeContextCurrent(window_);
    return n;
  }
  /// The nodes drawn inside a pixel rectangle of the view.
  std::vector<int> nodes_in(double x0, double y0, double x1, double y1) {
    if (!renderer_) return {};
    std::vector<int> nodes = renderer_->points_in_rect(x0, y0, x1, y1);
    glfwMakeContextCurrent(window_);
    return nodes;
  }
  bool ready() const { return mode_ ? mode_renderer_ != nullptr : renderer_ != nullptr; }
  /// A frame has arrived that the view has not drawn yet.
  bool needs_render_any() const { return mode_ ? mode_shown_ < 0 : info_ && frame_ && dirty_; }

  /// Draws the image into the current ImGui window and handles the mouse (orbit, pan, zoom,
  /// click to pick, shift-drag a box when `box_picking`). Returns the node clicked this frame, or
  /// -1; a box dragged this frame comes back in *boxed.
  int draw(float w, float h, bool box_picking = false, std::vector<int>* boxed = nullptr) {
    int picked = -1;
    if (!texture_) {
      ImGui::SetCursorPos(ImVec2(20, 20));
      ImGui::TextWrapped("%s", error_.empty() ? "waiting for the first frame ..." : ("viewport: " + error_).c_str());
      return picked;
    }
    const ImVec2 origin = ImGui::GetCursorScreenPos();
    ImGui::Image(reinterpret_cast<ImTextureID>(static_cast<intptr_t>(texture_)), ImVec2(w, h), ImVec2(0, 1),
                 ImVec2(1, 0));
    // a mode animation turns and zooms like the run's view; picking waits for the run's frames
    render::FrameRenderer* const view = mode_ ? mode_renderer_.get() : renderer_.get();
    if (!view) return picked;
    const ImGuiIO& io = ImGui::GetIO();
    if (ImGui::IsItemHovered()) {
      if (io.MouseWheel != 0.0f) {
        view->zoom(std::pow(1.15, io.MouseWheel));
        dirty_ = user_camera_ = true;
      }
      if (ImGui::IsMouseReleased(ImGuiMouseButton_Left) && !dragged_ && !mode_) {
        picked = renderer_->pick_point(io.MousePos.x - origin.x, io.MousePos.y - origin.y);
        glfwMakeContextCurrent(window_);
      }
      if (ImGui::IsMouseClicked(ImGuiMouseButton_Left) || ImGui::IsMouseClicked(ImGuiMouseButton_Right) ||
          ImGui::IsMouseClicked(ImGuiMouseButton_Middle))
        dragged_ = false, dragging_ = true, box_start_ = ImVec2(io.MousePos.x - origin.x, io.MousePos.y - origin.y);
    }
    if (box_picking && dragging_ && io.KeyShift && ImGui::IsMouseDragging(ImGuiMouseButton_Left, 3.0f)) {
      // shift-drag: a rubber band instead of orbiting; released, it picks what it encloses
      ImGui::GetWindowDrawList()->AddRect(ImVec2(origin.x + box_start_.x, origin.y + box_start_.y), io.MousePos,
                                          IM_COL32(230, 120, 0, 255), 0.0f, 0, 2.0f);
      dragged_ = true;
      return picked;
    }
    if (box_picking && dragging_ && dragged_ && io.KeyShift && ImGui::IsMouseReleased(ImGuiMouseButton_Left) && boxed) {
      *boxed = nodes_in(box_start_.x, box_start_.y, io.MousePos.x - origin.x, io.MousePos.y - origin.y);
      dragging_ = false;
      return picked;
    }
    if (dragging_) {
      const ImVec2 d = io.MouseDelta;
      if (d.x != 0.0f || d.y != 0.0f) {
        if (ImGui::IsMouseDragging(ImGuiMouseButton_Left, 3.0f)) {
          view->orbit(-0.4 * d.x, 0.4 * d.y);
          dragged_ = dirty_ = user_camera_ = true;
        } else if (ImGui::IsMouseDragging(ImGuiMouseButton_Right, 1.0f) ||
                   ImGui::IsMouseDragging(ImGuiMouseButton_Middle, 1.0f)) {
          view->pan(d.x, d.y);
          dragged_ = dirty_ = user_camera_ = true;
        }
      }
      if (!ImGui::IsMouseDown(ImGuiMouseButton_Left) && !ImGui::IsMouseDown(ImGuiMouseButton_Right) &&
          !ImGui::IsMouseDown(ImGuiMouseButton_Middle))
        dragging_ = false;
    }
    return picked;
  }

  /// Back to the scene's view (output.view), or with `auto` to the automatic one: fitted to the
  /// body, in its own direction (plane normal or iso).
  void reset_camera() {
    view_.reset();
    camera_.reset();
    user_camera_ = false;
    if (!renderer_) return;
    const bool scene_view = info_ && output_.view != "auto" && output_.camera_path.empty();
    renderer_->set_camera(scene_view ? scene_camera(info_->mesh, output_.view, output_.view_center, output_.view_radius,
                                                    fit_points_)
                                     : render::Camera{});
    dirty_ = true;
  }
  /// The automatic view along a named direction, as output.view and --camera name it: "iso",
  /// "top", "front", "side" (app/view_options.h, parse_camera). It stays through window resizes
  /// and refits until reset_camera().
  void set_view(const std::string& name) {
    view_ = parse_camera(name);
    camera_.reset();
    user_camera_ = false;
    if (renderer_) renderer_->set_camera(*view_), dirty_ = true;
  }
  /// Marks the probed node (-1: none), drawn over every highlighted selection.
  void set_probe_node(int node) {
    if (node == probe_node_) return;
    probe_node_ = node;
    apply_markers();
  }
  /// Highlighted node sets (e.g. a scene's selections), drawn beneath the probe marker; indices
  /// outside the current mesh are dropped. See render::FrameRenderer::set_markers.
  void set_highlights(std::vector<render::NodeMarkers> sets) {
    highlights_ = std::move(sets);
    apply_markers();
  }

  /// The latest frame as a PNG at the viewport's size and view.
  bool export_png(const std::string& path, std::string* error) {
    if (mode_ && mode_renderer_) {  // the picture of the mode on show
      std::error_code ec;
      const fs::path parent = fs::path(path).parent_path();
      if (!parent.empty()) fs::create_directories(parent, ec);
      const bool ok = mode_renderer_->render_png(mode_->frames[static_cast<std::size_t>(std::max(mode_shown_, 0))], path, error);
      glfwMakeContextCurrent(window_);
      return ok;
    }
    if (!renderer_ || !frame_) {
      *error = "nothing to export yet";
      return false;
    }
    std::error_code ec;
    const fs::path parent = fs::path(path).parent_path();
    if (!parent.empty()) fs::create_directories(parent, ec);
    const bool ok = renderer_->render_png(*frame_, path, error);
    glfwMakeContextCurrent(window_);
    return ok;
  }

  std::string backend() const { return gc_ ? gc_->backend() + ", " + gc_->gl_renderer() : ""; }

 private:
  int mode_phase() const {
    const double periods = seconds_since(mode_start_) / kModePeriodSeconds;
    const int k = static_cast<int>(mode_->frames.size());
    return static_cast<int>((periods - std::floor(periods)) * k) % k;
  }
  void update_mode(int w, int h, bool force) {
    if (w < 32 || h < 32 || mode_->frames.empty()) return;
    if (mode_renderer_ && (mode_renderer_->width() != w || mode_renderer_->height() != h)) mode_renderer_.reset();
    if (!mode_renderer_) {
      if (!ensure_graphics_context()) return;
      render::FrameStyle style;
      style.width = w;
      style.height = h;
      style.color_field = kModeShapeField;
      style.color_min = 0.0;
      style.color_max = 1.0;
      style.title = mode_->title;
      style.caption = mode_->caption;
      style.background = {0.97, 0.97, 0.98};
      style.show_triad = true;
      style.camera.view_direction = {1, -1, 1};  // as `run` draws the modes: oblique, fitted to the period
      style.camera.view_up = {0, 0, 1};
      for (const Frame& f : mode_->frames) style.fit_points.insert(style.fit_points.end(), f.points.begin(), f.points.end());
      mode_renderer_ = std::make_unique<render::FrameRenderer>(*gc_, mode_->info, style);
      glfwMakeContextCurrent(window_);
      if (!mode_renderer_->ok()) {
        error_ = mode_renderer_->error();
        mode_.reset();
        mode_renderer_.reset();
        return;
      }
    }
    const int k = mode_phase();
    if (!force && !dirty_ && k == mode_shown_) return;
    if (!force && seconds_since(last_render_) < kViewportMinInterval) return;
    std::string err;
    if (mode_renderer_->render_rgb(mode_->frames[static_cast<std::size_t>(k)], &rgb_, &err)) {
      upload(mode_renderer_->width(), mode_renderer_->height());
      error_.clear();
    } else {
      error_ = err;
    }
    glfwMakeContextCurrent(window_);
    mode_shown_ = k;
    dirty_ = false;
    last_render_ = Clock::now();
  }
  void release() {
    mode_renderer_.reset();
    renderer_.reset();
    glfwMakeContextCurrent(window_);
    error_.clear();
    dirty_ = true;
  }
  // the offscreen context both renderers draw in, made once (GLFW's context is current again after)
  bool ensure_graphics_context() {
    if (!gc_) {
      gc_ = render::GraphicsContext::create(&error_);
      glfwMakeContextCurrent(window_);
    }
    return gc_ != nullptr;
  }
  void build(int w, int h) {
    if (!ensure_graphics_context()) return;
    render::FrameStyle style;
    style.width = w;
    style.height = h;
    style.deformation_scale = output_.deformation_scale;
    style.color_field = output_.color_field == "none" ? "" : output_.color_field;
    style.title = title_;
    style.background = {0.97, 0.97, 0.98};
    style.show_triad = true;
    if (camera_) style.camera = *camera_;
    else if (view_) style.camera = *view_;
    // the scene's own view (output.view), as `run` draws it, until the user picks another
    else if (output_.view != "auto" && output_.camera_path.empty())
      style.camera = scene_camera(info_->mesh, output_.view, output_.view_center, output_.view_radius, fit_points_);
    style.fit_points = fit_points_;
    renderer_ = std::make_unique<render::FrameRenderer>(*gc_, *info_, style);
    if (!renderer_->ok()) {
      error_ = renderer_->error();
      renderer_.reset();
    }
    apply_markers();
    glfwMakeContextCurrent(window_);
    dirty_ = true;
  }
  void apply_markers() {
    dirty_ = true;
    if (!renderer_ || !info_) return;
    const auto n = static_cast<std::int32_t>(info_->mesh.point_count());
    std::vector<render::NodeMarkers> sets;
    for (render::NodeMarkers set : highlights_) {
      std::erase_if(set.nodes, [n](std::int32_t i) { return i < 0 || i >= n; });
      sets.push_back(std::move(set));
    }
    if (probe_node_ >= 0 && probe_node_ < n) sets.push_back({{probe_node_}, kProbeMarkerColor, kProbeMarkerPx});
    std::string err;
    if (!renderer_->set_markers(std::move(sets), &err)) std::fprintf(stderr, "viewport markers: %s\n", err.c_str());
  }
  void upload(int w, int h) {
    glfwMakeContextCurrent(window_);
    if (!texture_) {
      glGenTextures(1, &texture_);
      glBindTexture(GL_TEXTURE_2D, texture_);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MIN_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_MAG_FILTER, GL_LINEAR);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_S, GL_CLAMP_TO_EDGE);
      glTexParameteri(GL_TEXTURE_2D, GL_TEXTURE_WRAP_T, GL_CLAMP_TO_EDGE);
    }
    glBindTexture(GL_TEXTURE_2D, texture_);
    glPixelStorei(GL_UNPACK_ALIGNMENT, 1);
    glTexImage2D(GL_TEXTURE_2D, 0, GL_RGB, w, h, 0, GL_RGB, GL_UNSIGNED_BYTE, rgb_.data());
  }

  GLFWwindow* window_;
  std::unique_ptr<render::GraphicsContext> gc_;
  std::unique_ptr<render::FrameRenderer> renderer_;
  std::optional<ModeAnimation> mode_;                   // a mode animated instead of the run's frames
  std::unique_ptr<render::FrameRenderer> mode_renderer_;
  int mode_number_ = 0, mode_shown_ = -1;               // the picture of the period last drawn
  Clock::time_point mode_start_{};
  std::shared_ptr<const RunInfo> info_;
  scene::OutputSettings output_;
  std::string title_;
  std::optional<render::Camera> camera_;
  std::optional<render::Camera> view_;  // a named view chosen with the view buttons (automatic)
  bool user_camera_ = false;        // orbited, panned or zoomed since the last reset
  int probe_node_ = -1;
  std::vector<render::NodeMarkers> highlights_;
  std::vector<double> fit_points_;  // corners of the deformed frames the automatic view must hold
  Eigen::AlignedBox3d fitted_;      // what the automatic view was fitted to
  std::optional<Frame> frame_;
  std::vector<unsigned char> rgb_;
  GLuint texture_ = 0;
  bool dirty_ = true, dragging_ = false, dragged_ = false;
  ImVec2 box_start_{0, 0};  // where a shift-drag box began, in view pixels
  Clock::time_point last_render_{};
  std::string error_;
};

/// An action as its line reads (for messages).
std::string describe(const Action& a) {
  switch (a.kind) {
    case Action::Kind::run: return "run";
    case Action::Kind::pause: return "pause";
    case Action::Kind::step: return "step " + std::to_string(a.count);
    case Action::Kind::reset: return "reset";
    case Action::Kind::set: return "set " + a.key + " " + a.text;
    case Action::Kind::probe: return "probe " + std::to_string(a.count);
    case Action::Kind::wait: return "wait " + fmt("%g", a.seconds);
    case Action::Kind::screenshot: return "screenshot " + a.text;
    case Action::Kind::export_png: return "export " + a.text;
    case Action::Kind::save: return "save " + a.text;
    case Action::Kind::quit: return "quit";
    case Action::Kind::redraws: return "redraws";
    case Action::Kind::new_problem: return "new " + a.text;
    case Action::Kind::open: return "open " + a.text;
    case Action::Kind::add: {
      std::string s = "add " + a.key;
      for (const auto& [k, v] : a.fields) s += " " + k + "=" + v;
      return s;
    }
    case Action::Kind::remove: return "remove " + a.key + "[" + std::to_string(a.count) + "]";
    case Action::Kind::preset: return "preset " + a.key + "[" + std::to_string(a.count) + "] " + a.text;
    case Action::Kind::pick: {
      std::string s = "pick";
      for (long long n : a.nodes) s += " " + std::to_string(n);
      return s;
    }
    case Action::Kind::pick_clear: return "pick-clear";
    case Action::Kind::use_pick: return "use-pick " + a.key + "[" + std::to_string(a.count) + "]";
    case Action::Kind::use_edge: return "use-edge " + a.key + "[" + std::to_string(a.count) + "] " + a.patch + " " + a.edge;
    case Action::Kind::click: return "click " + fmt("%g", a.pixels[0]) + " " + fmt("%g", a.pixels[1]);
    case Action::Kind::pick_box:
      return "pick-box " + fmt("%g", a.pixels[0]) + " " + fmt("%g", a.pixels[1]) + " " + fmt("%g", a.pixels[2]) + " " +
             fmt("%g", a.pixels[3]);
    case Action::Kind::show: return "show " + (a.key.empty() ? a.text : a.key + "[" + std::to_string(a.count) + "]");
    case Action::Kind::metrics: return "metrics";
    case Action::Kind::view: return "view " + a.text;
    case Action::Kind::wait_end: return "wait-end";
    case Action::Kind::mode: return a.count == 0 ? std::string("mode off") : "mode " + std::to_string(a.count);
  }
  return "";
}

/// Everything the window shows and does.
class GuiApp {
 public:
  GuiApp(GLFWwindow* window, const GuiOptions& opt, std::unique_ptr<SimWorker> worker,
         std::vector<Action> actions, const std::atomic<bool>& stop)
      : window_(window), opt_(opt), worker_(std::move(worker)), viewport_(window), actions_(std::move(actions)),
        stop_(stop) {
    bundled_ = bundled_scenes();
    start_ = Clock::now();
  }

  int loop() {
    if (opt_.run) worker_->run();
    int settle = kSettleFrames;  // the first frames draw the window
    Clock::time_point last_draw{};
    while (!glfwWindowShouldClose(window_) && !quit_) {
      // Sleep until there is something to draw: input, news from the solver thread (it posts an
      // empty event), a scripted wait's end, --quit-after, or the next draw due while the solver
      // runs (at most kMinFrameInterval apart). An idle window draws nothing.
      {
        int fb_w = 0, fb_h = 0;
        glfwGetFramebufferSize(window_, &fb_w, &fb_h);
        const ImVec2 vp = viewport_size(static_cast<float>(fb_w), static_cast<float>(fb_h));
        const bool draw_wanted = settle > 0 || ImGui::GetIO().WantTextInput ||
                                 viewport_.needs_render(static_cast<int>(vp.x), static_cast<int>(vp.y));
        double timeout = draw_wanted ? kMinFrameInterval - seconds_since(last_draw) : kIdleWake;
        if (wait_until_ > Clock::now())
          timeout = std::min(timeout, std::chrono::duration<double>(wait_until_ - Clock::now()).count());
        if (opt_.quit_after > 0) timeout = std::min(timeout, opt_.quit_after - seconds_since(start_));
        if (!pending_screenshot_.empty() || !pending_export_.empty()) timeout = 0.0;
        if (timeout > 0)
          glfwWaitEventsTimeout(timeout);
        else
          glfwPollEvents();
      }
      if (pull()) settle = std::max(settle, 1);
      for (const std::string& dropped : std::exchange(g_dropped, {})) {
        try {
          open_file(dropped);
          notice("opening " + dropped);
        } catch (const std::exception& e) {
          message_ = e.what(), message_is_error_ = true;
        }
      }
      if (g_input_seen) settle = kSettleFrames, g_input_seen = false;
      run_actions();
      if (opt_.quit_after > 0 && seconds_since(start_) >= opt_.quit_after && !quit_) {
        quit_ = true;
        if (current_action_ || next_action_ < actions_.size()) {
          const Action& next = current_action_ ? *current_action_ : actions_[next_action_];
          std::fprintf(stderr, "error: --quit-after %g s reached before the actions finished (at %s)\n",
                       opt_.quit_after, next.where().c_str());
          exit_code_ = 1;
        }
      }
      if (stop_) quit_ = true;
      const bool want_capture = quit_ && !opt_.screenshot.empty();
      int fb_w = 0, fb_h = 0;
      glfwGetFramebufferSize(window_, &fb_w, &fb_h);
      const ImVec2 vp = viewport_size(static_cast<float>(fb_w), static_cast<float>(fb_h));
      const bool must_draw = want_capture || !pending_screenshot_.empty() || !pending_export_.empty();
      const bool draw_wanted = settle > 0 || ImGui::GetIO().WantTextInput ||
                               viewport_.needs_render(static_cast<int>(vp.x), static_cast<int>(vp.y));
      if (!must_draw && !(draw_wanted && seconds_since(last_draw) >= kMinFrameInterval)) continue;
      last_draw = Clock::now();
      settle = std::max(0, settle - 1);
      ++redraws_;
      draws_.push_back(last_draw);
      while (draws_.size() > 1 && seconds_since(draws_.front()) > 1.0) draws_.pop_front();
      viewport_.update(static_cast<int>(vp.x), static_cast<int>(vp.y),
                       !pending_screenshot_.empty() || !pending_export_.empty() || want_capture);
      if (!pending_export_.empty()) {
        std::string err;
        if (viewport_.export_png(pending_export_, &err))
          notice("exported " + pending_export_);
        else
          action_failed("export " + pending_export_ + ": " + err);
        pending_export_.clear();
      }

      ImGui_ImplOpenGL3_NewFrame();
      ImGui_ImplGlfw_NewFrame();
      ImGui::NewFrame();
      draw(static_cast<float>(fb_w), static_cast<float>(fb_h), vp);
      ImGui::Render();
      glViewport(0, 0, fb_w, fb_h);
      glClearColor(0.94f, 0.94f, 0.95f, 1.0f);
      glClear(GL_COLOR_BUFFER_BIT);
      ImGui_ImplOpenGL3_RenderDrawData(ImGui::GetDrawData());
      if (!pending_screenshot_.empty()) {
        std::string err;
        if (write_window_png(pending_screenshot_, fb_w, fb_h, &err))
          std::printf("screenshot %s (%dx%d)\n", pending_screenshot_.c_str(), fb_w, fb_h);
        else
          action_failed("screenshot: " + err);
        pending_screenshot_.clear();
      }
      if (want_capture) {
        std::string err;
        if (write_window_png(opt_.screenshot, fb_w, fb_h, &err))
          std::printf("screenshot %s (%dx%d)\n", opt_.screenshot.c_str(), fb_w, fb_h);
        else
          std::fprintf(stderr, "error: %s\n", err.c_str()), exit_code_ = 1;
      }
      glfwSwapBuffers(window_);
    }
    std::fflush(stdout);
    return exit_code_;
  }

 private:
  // ---- solver updates ---------------------------------------------------------------------------

  /// Takes the solver thread's news; true when there was any (the window must draw).
  bool pull() {
    WorkerUpdate u = worker_->take();
    const bool news = u.status.revision != status_.revision || u.frame || !u.samples.empty();
    if (u.status.generation != status_.generation) {
      history_.clear();
      rate_.clear();
      viewport_.set_run(u.status.info, u.status.output, u.status.scene_name);
      params_.load(u.status.scene_text, u.status.scene_path, u.status.opened_text);
      setup_.load(u.status);
      save_path_ = u.status.scene_name + "_edited.toml";
      export_path_ = u.status.scene_name + ".png";
      scene_field_ = u.status.opened_from;
      if (u.status.info && !pick_.nodes.empty() && *pick_.nodes.rbegin() >= static_cast<int>(u.status.info->mesh.point_count()))
        pick_.nodes.clear();  // picked on another mesh
    } else if ((u.status.message_seq != status_.message_seq && u.status.message_is_error) ||
               u.status.scene_text != status_.scene_text) {
      // a refused edit leaves the list as it was; a live edit adds its [[timeline]] entry
      params_.load(u.status.scene_text, u.status.scene_path, u.status.opened_text);
      setup_.load(u.status);
    }
    if (u.status.message_seq != status_.message_seq && !u.status.message.empty()) {
      message_ = u.status.message;
      message_is_error_ = u.status.message_is_error;
      if (message_is_error_) std::fprintf(stderr, "%s\n", message_.c_str());
      // a refusal, reworded for the window, under the key it refused and in the status line
      refusal_ = message_is_error_ ? readable_refusal(message_) : std::nullopt;
      if (refusal_)
        params_.show_refusal(*refusal_);
      else
        params_.clear_refusal();
    }
    if (u.status.probe_node >= 0 && u.status.probe_node != status_.probe_node) probe_input_ = u.status.probe_node;
    status_ = std::move(u.status);
    viewport_.set_probe_node(status_.probe_node);
    for (Sample& s : u.samples) {
      // a probe's answer is the state already on show, now with the new node: it takes the place
      // of that state's sample, so the plots get no duplicate point
      if (s.probe_answer && !history_.empty() && history_.back().step == s.step) {
        history_.back() = std::move(s);
        continue;
      }
      rate_.push_back({Clock::now(), s.step, s.time});
      history_.push_back(std::move(s));
    }
    while (rate_.size() > 2 && seconds_since(rate_.front().at) > 2.0) rate_.pop_front();
    if (u.frame) {
      last_stats_ = u.frame->stats;
      viewport_.set_frame(*u.frame);
    }
    return news;
  }

  double steps_per_second() const {
    // a rate only while the solver runs: after the end the window holds the last burst of steps
    if (rate_.size() < 2 || status_.state != WorkerState::running) return 0.0;
    const double dt = std::chrono::duration<double>(rate_.back().at - rate_.front().at).count();
    return dt > 0 ? (rate_.back().step - rate_.front().step) / dt : 0.0;
  }
  /// Simulated time (or load factor) per wall second over the last two seconds; nullopt unless running.
  std::optional<double> solver_pace() const {
    if (rate_.size() < 2 || status_.state != WorkerState::running) return std::nullopt;
    const double dt = std::chrono::duration<double>(rate_.back().at - rate_.front().at).count();
    if (dt <= 0) return std::nullopt;
    return (rate_.back().time - rate_.front().time) / dt;
  }
  /// " | 0.25x real time" (simulated seconds per wall second) while a time-stepped run runs;
  /// " | λ +0.03/s" (load factor per wall second) for a load-controlled one; "" otherwise.
  std::string pace_text() const {
    const std::optional<double> rate = solver_pace();
    if (!rate || !status_.info) return "";
    if (status_.info->time_unit.empty()) return std::string(" | ") + lambda_text() + " " + fmt("%+.3g", *rate) + "/s";
    if (status_.info->time_unit != "s") return " | " + fmt("%.3g", *rate) + " " + status_.info->time_unit + "/s";
    return " | " + fmt("%.3g", *rate) + "\u00d7 real time";
  }
  /// Window frames drawn in the last second (an idle window draws none, so it reads what it drew last).
  int frames_per_second() const {
    return static_cast<int>(std::count_if(draws_.begin(), draws_.end(),
                                          [](Clock::time_point t) { return seconds_since(t) <= 1.0; }));
  }

  /// The newest sample of the probed node, or null (none probed, or its state not here yet).
  const Sample* probed_sample() const {
    if (status_.probe_node < 0 || history_.empty() || history_.back().node != status_.probe_node) return nullptr;
    return &history_.back();
  }
  /// Where the probed node's history starts: the samples since it was placed (a new node, a new history).
  std::size_t probe_history_start() const {
    std::size_t i = history_.size();
    while (i > 0 && status_.probe_node >= 0 && history_[i - 1].node == status_.probe_node) --i;
    return i;
  }

  void notice(const std::string& text) {
    message_ = text;
    message_is_error_ = false;
  }

  // ---- scripted actions -------------------------------------------------------------------------

  void action_failed(const std::string& text) {
    const std::string where = current_action_ ? current_action_->where() + ": " : "";
    std::fprintf(stderr, "error: %s%s\n", where.c_str(), text.c_str());
    message_ = text;
    message_is_error_ = true;
    if (current_action_) {
      exit_code_ = 2;
      quit_ = true;
    }
  }

  void run_actions() {
    while (pending_screenshot_.empty() && pending_export_.empty() && !quit_) {
      if (waiting_seq_ != 0) {
        if (status_.settled_seq < waiting_seq_) return;
        waiting_seq_ = 0;
        if (current_action_ && current_action_->kind == Action::Kind::probe) {
          // what the window's "Probe a node" readout shows now
          const Sample* s = probed_sample();
          std::printf("probe %s\n", s ? node_readout(*s, ", ").c_str() : "none");
          std::fflush(stdout);
        }
        if (current_action_ && edits_scene(*current_action_) && status_.message_is_error &&
            status_.message_seq != message_seq_at_issue_) {
          action_failed(describe(*current_action_) + " was refused:\n" + status_.message);
          return;
        }
      }
      if (Clock::now() < wait_until_) return;
      if (waiting_end_) {
        if (!status_.outcome) return;
        waiting_end_ = false;
      }
      if (next_action_ >= actions_.size()) {
        current_action_ = nullptr;  // the script is done; later failures are the user's clicks
        return;
      }
      const Action& a = actions_[next_action_++];
      current_action_ = &a;
      if (announced_ != next_action_) {  // once, also for an action that waits for the view
        std::printf("action %s: %s\n", a.where().c_str(), describe(a).c_str());
        std::fflush(stdout);
        announced_ = next_action_;
      }
      message_seq_at_issue_ = status_.message_seq;
      switch (a.kind) {
        case Action::Kind::run: waiting_seq_ = worker_->run(); break;
        case Action::Kind::pause: waiting_seq_ = worker_->pause(); break;
        case Action::Kind::step: waiting_seq_ = worker_->step(a.count); break;
        case Action::Kind::reset: waiting_seq_ = worker_->reset(); break;
        case Action::Kind::set: waiting_seq_ = worker_->set(a.key, a.text); break;
        case Action::Kind::probe: waiting_seq_ = worker_->probe(static_cast<int>(a.count)); break;
        case Action::Kind::wait:
          wait_until_ = Clock::now() + std::chrono::duration_cast<Clock::duration>(std::chrono::duration<double>(a.seconds));
          break;
        case Action::Kind::screenshot:
        case Action::Kind::export_png:
          // a picture shows the current frame: wait until the view has drawn one (a new scene
          // builds its renderer at the next draw)
          if (!viewport_.ready() || viewport_.needs_render_any()) {
            --next_action_;
            current_action_ = nullptr;
            return;
          }
          (a.kind == Action::Kind::screenshot ? pending_screenshot_ : pending_export_) = a.text;
          break;
        case Action::Kind::save: save_scene(a.text); break;
        case Action::Kind::quit: quit_ = true; break;
        case Action::Kind::redraws:
          std::printf("redraws %lld\n", redraws_);
          std::fflush(stdout);
          break;
        case Action::Kind::new_problem: waiting_seq_ = request({a.text, {}, a.text}); break;
        case Action::Kind::open:
          try {
            waiting_seq_ = open_file(a.text);
          } catch (const std::exception& e) {
            action_failed(e.what());
          }
          break;
        case Action::Kind::add:
        case Action::Kind::remove:
        case Action::Kind::preset:
        case Action::Kind::use_edge: waiting_seq_ = request(*scene_edit_of(a)); break;
        case Action::Kind::pick: {
          const long long n = status_.info ? static_cast<long long>(status_.info->mesh.point_count()) : 0;
          for (long long node : a.nodes) {
            if (node >= n) {
              action_failed("pick " + std::to_string(node) + ": the mesh has nodes 0 to " + std::to_string(n - 1));
              break;
            }
            pick_.nodes.insert(static_cast<int>(node));
          }
          break;
        }
        case Action::Kind::pick_clear: pick_.nodes.clear(); break;
        case Action::Kind::use_pick:
          if (pick_.nodes.empty()) {
            action_failed("use-pick: no nodes are picked (pick NODE..., click X Y with picking on, or pick-box)");
            break;
          }
          waiting_seq_ = request(use_picked_nodes(a.key + "[" + std::to_string(a.count) + "]", pick_.nodes));
          break;
        case Action::Kind::click:
        case Action::Kind::pick_box:
          // as the mouse would: the view must have drawn the current frame first
          if (!viewport_.ready()) {
            --next_action_;  // try again after the next draw
            current_action_ = nullptr;
            return;
          }
          if (a.kind == Action::Kind::click) {
            const int node = viewport_.node_at(a.pixels[0], a.pixels[1]);
            if (node < 0) {
              action_failed("click " + fmt("%g", a.pixels[0]) + " " + fmt("%g", a.pixels[1]) + ": no node there");
              break;
            }
            clicked(node);
            std::printf("clicked node %d\n", node);
          } else {
            const std::vector<int> nodes = viewport_.nodes_in(a.pixels[0], a.pixels[1], a.pixels[2], a.pixels[3]);
            pick_.nodes.insert(nodes.begin(), nodes.end());
            std::printf("picked %zu nodes in the box\n", nodes.size());
          }
          std::fflush(stdout);
          break;
        case Action::Kind::wait_end: waiting_end_ = true; break;
        case Action::Kind::view:
          if (a.text == "scene")
            viewport_.reset_camera();
          else
            viewport_.set_view(a.text);
          break;
        case Action::Kind::metrics:
          if (!status_.outcome) {
            action_failed("metrics: the run has not ended (run, then wait until it has)");
            break;
          }
          for (const auto& [name, value] : status_.metrics) std::printf("metric %s = %.17g\n", name.c_str(), value);
          std::fflush(stdout);
          break;
        case Action::Kind::show:
          pick_.shown = a.key.empty() ? a.text : a.key + "[" + std::to_string(a.count) + "]";
          break;
        case Action::Kind::mode:
          if (a.count == 0) {
            viewport_.show_mode(std::nullopt);
            break;
          }
          if (const std::string why = animate_mode(static_cast<int>(a.count)); !why.empty()) {
            action_failed("mode " + std::to_string(a.count) + ": " + why);
            break;
          }
          std::printf("mode %lld: %s\n", a.count, mode_value_text(*status_.modes, *find_mode(static_cast<int>(a.count))).c_str());
          std::fflush(stdout);
          break;
      }
    }
  }

  /// Actions whose refusal by the solver thread fails the script.
  static bool edits_scene(const Action& a) {
    switch (a.kind) {
      case Action::Kind::set:
      case Action::Kind::new_problem:
      case Action::Kind::open:
      case Action::Kind::add:
      case Action::Kind::remove:
      case Action::Kind::preset:
      case Action::Kind::use_pick:
      case Action::Kind::use_edge: return true;
      default: return false;
    }
  }



  const Mode* find_mode(int number) const {
    if (!status_.modes) return nullptr;
    for (const Mode& m : status_.modes->modes)
      if (m.number == number) return &m;
    return nullptr;
  }
  /// Animates mode `number` about the state on show (the run's last frame); "" or why not.
  std::string animate_mode(int number) {
    if (!status_.modes) return status_.outcome ? "the run computed no modes (scene.analysis = modal or buckling does)"
                                               : "no modes yet: the run has not ended";
    const Mode* mode = find_mode(number);
    if (!mode) return "no such mode; the analysis found " + std::to_string(status_.modes->modes.size());
    if (!viewport_.frame() || !status_.info) return "no state to animate about";
    try {
      viewport_.show_mode(mode_animation(*status_.info, *viewport_.frame(), *status_.modes, *mode), number);
    } catch (const std::exception& e) {
      return e.what();
    }
    return "";
  }

  void save_scene(const std::string& path) {
    try {
      const std::string text =
          text_to_save(status_.scene_text, status_.scene_path, path, status_.opened_text, status_.opened_from);
      std::string why;  // opened as every output is: no link, hard link, FIFO or device at the path
      std::FILE* out = open_output_stream(path, &why);
      if (!out) throw std::runtime_error("cannot write " + path + ": " + why);
      const bool written = std::fwrite(text.data(), 1, text.size(), out) == text.size() && std::fflush(out) == 0;
      if (std::fclose(out) != 0 || !written) throw std::runtime_error("cannot write " + path + ": " + std::strerror(errno));
      notice("saved " + path);
      std::printf("saved %s\n", path.c_str());
    } catch (const std::exception& e) {
      action_failed(std::string("save: ") + e.what());
    }
  }

  // ---- layout -----------------------------------------------------------------------------------

  static ImVec2 viewport_size(float w, float h) {
    return ImVec2(std::max(0.0f, w - kSideWidth), std::max(0.0f, h - kPlotHeight - kStatusHeight));
  }

  static constexpr ImGuiWindowFlags kPanel =
      ImGuiWindowFlags_NoMove | ImGuiWindowFlags_NoResize | ImGuiWindowFlags_NoCollapse |
      ImGuiWindowFlags_NoSavedSettings | ImGuiWindowFlags_NoBringToFrontOnFocus;

  /// Marks on the body the nodes the shown selections act on (yellow) and the picked nodes
  /// (magenta, over them); redone only when one of them changed.
  void update_highlights() {
    auto key = std::make_tuple(static_cast<const void*>(status_.selections.get()), pick_.shown, pick_.nodes);
    if (key == highlighted_) return;
    highlighted_ = key;
    std::vector<render::NodeMarkers> sets;
    render::NodeMarkers shown;
    for (int n : shown_nodes(status_, pick_.shown)) shown.nodes.push_back(n);
    shown.color = {1.0, 0.80, 0.0};
    shown.size_px = 6.0;
    if (!shown.nodes.empty()) sets.push_back(std::move(shown));
    render::NodeMarkers picked;
    picked.nodes.assign(pick_.nodes.begin(), pick_.nodes.end());
    picked.color = {0.85, 0.10, 0.75};
    picked.size_px = 9.0;
    if (!picked.nodes.empty()) sets.push_back(std::move(picked));
    viewport_.set_highlights(std::move(sets));
  }

  void draw(float w, float h, ImVec2 vp) {
    update_highlights();
    // viewport: top left, no padding, the image fills it
    ImGui::SetNextWindowPos(ImVec2(0, 0));
    ImGui::SetNextWindowSize(vp);
    ImGui::PushStyleVar(ImGuiStyleVar_WindowPadding, ImVec2(0, 0));
    ImGui::PushStyleVar(ImGuiStyleVar_WindowBorderSize, 0.0f);
    ImGui::Begin("viewport", nullptr, kPanel | ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoScrollbar |
                                          ImGuiWindowFlags_NoScrollWithMouse);
    std::vector<int> boxed;
    const int picked = viewport_.draw(vp.x, vp.y, pick_.picking, &boxed);
    if (picked >= 0) clicked(picked);
    if (!boxed.empty()) {
      pick_.nodes.insert(boxed.begin(), boxed.end());
      notice("picked " + std::to_string(boxed.size()) + " nodes in the box (" + std::to_string(pick_.nodes.size()) + " in all)");
    }
    ImGui::End();
    ImGui::PopStyleVar(2);

    ImGui::SetNextWindowPos(ImVec2(vp.x, 0));
    ImGui::SetNextWindowSize(ImVec2(w - vp.x, h - kStatusHeight));
    ImGui::Begin("FlexFrame", nullptr, kPanel);
    draw_side_panel();
    ImGui::End();

    ImGui::SetNextWindowPos(ImVec2(0, vp.y));
    ImGui::SetNextWindowSize(ImVec2(vp.x, kPlotHeight));
    ImGui::Begin("Plots", nullptr, kPanel | ImGuiWindowFlags_NoTitleBar);
    draw_plots(vp.x);
    ImGui::End();

    ImGui::SetNextWindowPos(ImVec2(0, h - kStatusHeight));
    ImGui::SetNextWindowSize(ImVec2(w, kStatusHeight));
    ImGui::Begin("status", nullptr, kPanel | ImGuiWindowFlags_NoTitleBar | ImGuiWindowFlags_NoScrollbar);
    draw_status();
    ImGui::End();
  }

  void draw_side_panel() {
    // run controls first: what a person reaches for most
    const bool finished = status_.state == WorkerState::finished || status_.state == WorkerState::failed;
    const bool running = status_.state == WorkerState::running;
    const ImVec2 button(80, 0);
    if (running) {
      if (ImGui::Button("Pause", button)) worker_->pause();
    } else {
      if (ImGui::Button(finished ? "Run again" : "Run", button)) worker_->run();
    }
    ImGui::SameLine();
    if (ImGui::Button("Reset", button)) worker_->reset();
    // Step advances solver steps (as the status line counts them), not output frames
    const std::string step_label = "Step " + std::to_string(step_count_) +
                                   (step_count_ == 1 ? " solver step" : " solver steps") + "###step";
    if (ImGui::Button(step_label.c_str(), ImVec2(170, 0))) worker_->step(step_count_);
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("advance the solver by this many time (or load) steps, then pause; frames are drawn at "
                        "each step reached");
    ImGui::SameLine();
    ImGui::SetNextItemWidth(60);
    ImGui::InputInt("##steps", &step_count_, 0);
    step_count_ = std::max(1, step_count_);
    if (status_.steps_per_frame > 1) {
      // output frames are a separate control: up to the next frame of the output cadence
      ImGui::SameLine();
      if (ImGui::Button("Next frame")) {
        const long long at = history_.empty() ? 0 : history_.back().step;
        worker_->step(status_.steps_per_frame - at % status_.steps_per_frame);
      }
      if (ImGui::IsItemHovered())
        ImGui::SetTooltip("advance to the next output frame (every %lld solver steps)", status_.steps_per_frame);
    }
    ImGui::SetNextItemWidth(150);
    if (ImGui::InputDouble("max steps/s", &pace_, 0, 0, "%.0f", ImGuiInputTextFlags_EnterReturnsTrue))
      worker_->pace(pace_);
    if (ImGui::IsItemHovered()) ImGui::SetTooltip("slow the solver down to watch it; 0 = as fast as it goes");
    // the camera: reset, then the named views of output.view and --camera
    if (ImGui::Button("View")) viewport_.reset_camera();
    if (ImGui::IsItemHovered())
      ImGui::SetTooltip("back to the scene's view, output.view (drag: orbit, right drag: pan, wheel: zoom, click: "
                        "probe a node)");
    static constexpr std::array<std::array<const char*, 3>, 4> kViews = {{{"Iso", "iso", "isometric: from (1, -1, 1), z up"},
                                                                         {"Top", "top", "from +z, looking down, y up"},
                                                                         {"Front", "front", "from -y, z up"},
                                                                         {"Side", "side", "from +x, z up"}}};
    for (const auto& [label, name, tip] : kViews) {
      ImGui::SameLine();
      if (ImGui::Button(label)) viewport_.set_view(name);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s (output.view / --camera = %s)", tip, name);
    }
    ImGui::Separator();

    if (ImGui::CollapsingHeader("Scene", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::SetNextItemWidth(-70);
      if (ImGui::BeginCombo("bundled", status_.scene_name.c_str())) {
        for (const std::string& s : bundled_) {
          if (ImGui::Selectable(s.c_str(), s == status_.scene_name)) open_scene(s);
        }
        ImGui::EndCombo();
      }
      ImGui::SetNextItemWidth(-70);
      ImGui::InputText("##path", &scene_field_);
      ImGui::SameLine();
      if (ImGui::Button("Open", ImVec2(-1, 0))) open_scene(scene_field_);
      ImGui::SetNextItemWidth(-70);
      ImGui::InputText("##save", &save_path_);
      ImGui::SameLine();
      if (ImGui::Button("Save", ImVec2(-1, 0))) save_scene(save_path_);
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("write the scene with your edits as TOML");
      ImGui::SetNextItemWidth(-70);
      ImGui::InputText("##png", &export_path_);
      ImGui::SameLine();
      if (ImGui::Button("PNG", ImVec2(-1, 0))) pending_export_ = export_path_;
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("export the current frame as PNG");
    }
    if (ImGui::CollapsingHeader("Probe a node", ImGuiTreeNodeFlags_DefaultOpen)) {
      ImGui::SetNextItemWidth(120);
      ImGui::InputInt("node", &probe_input_);
      ImGui::SameLine();
      if (ImGui::Button("Probe")) worker_->probe(probe_input_);
      if (const Sample* s = probed_sample()) {
        ImGui::TextUnformatted(node_readout(*s, "\n").c_str());
      } else if (status_.probe_node >= 0) {
        ImGui::TextDisabled("node %d: waiting for the solver's state", status_.probe_node);
      } else {
        ImGui::TextDisabled("click the body or enter a node index");
      }
    }
    if (status_.modes && ImGui::CollapsingHeader("Modes", ImGuiTreeNodeFlags_DefaultOpen)) {
      const ModeSet& set = *status_.modes;
      ImGui::TextDisabled("%s, about the %s: click one to animate it", set.analysis.c_str(), set.about.c_str());
      const int shown = viewport_.mode_number();
      if (ImGui::Selectable("the run's frames", shown == 0)) viewport_.show_mode(std::nullopt);
      for (const Mode& m : set.modes) {
        const std::string label = "mode " + std::to_string(m.number) + "   " + mode_value_text(set, m);
        if (ImGui::Selectable(label.c_str(), shown == m.number)) {
          if (const std::string why = animate_mode(m.number); !why.empty()) message_ = why, message_is_error_ = true;
        }
      }
    }
    if (ImGui::CollapsingHeader("Set up", ImGuiTreeNodeFlags_DefaultOpen))
      for (SetupRequest& r : setup_.draw(status_, pick_)) request(std::move(r));
    if (ImGui::CollapsingHeader("Parameters", ImGuiTreeNodeFlags_DefaultOpen)) {
      // the live keys are the schema's, so a model that declares more shows them here too; the
      // header wraps to the panel (it used to run off its edge)
      const std::vector<std::string> live = params_.live_keys();
      ImGui::PushStyleColor(ImGuiCol_Text, ImGui::GetStyleColorVec4(ImGuiCol_TextDisabled));
      ImGui::TextWrapped("An edit rebuilds the model and restarts at t = 0.");
      if (!live.empty()) {
        std::string keys;
        for (const std::string& k : live) keys += (keys.empty() ? "" : ", ") + k;
        draw_live_tag();
        ImGui::SameLine();
        ImGui::TextWrapped("keys change the running model from its next step: %s", keys.c_str());
      }
      ImGui::PopStyleColor();
      ImGui::BeginChild("params", ImVec2(0, 0), false);
      for (const auto& [key, value] : params_.draw()) worker_->set(key, value);
      ImGui::EndChild();
    }
  }

  /// A click on node `node`: picked or unpicked while picking, else probed.
  void clicked(int node) {
    if (pick_.picking) {
      const bool had = pick_.nodes.erase(node) > 0;
      if (!had) pick_.nodes.insert(node);
      notice((had ? "unpicked node " : "picked node ") + std::to_string(node) + " (" + std::to_string(pick_.nodes.size()) +
             " picked)");
      return;
    }
    probe_input_ = node;
    worker_->probe(node);
    notice("probing node " + std::to_string(node));
  }

  /// Sends a set-up edit to the solver thread; returns its sequence number.
  std::uint64_t request(SetupRequest r) {
    if (r.new_problem) return open(new_problem(*r.new_problem));
    return worker_->edit(r.what, std::move(r.op));
  }

  std::uint64_t open(const SceneToOpen& s) { return worker_->load_text(s.text, s.path, s.from); }
  /// Opens a scene file, or a mesh file as a new problem's part (scene_to_open).
  std::uint64_t open_file(const std::string& name) { return open(scene_to_open(name)); }

  void open_scene(const std::string& name) {
    try {
      open_file(name);
    } catch (const std::exception& e) {
      message_ = e.what();
      message_is_error_ = true;
    }
  }

  /// One plot per probe (and the probed node, and the Newton iterations), laid out in columns.
  void draw_plots(float width) {
    if (!status_.info) return;
    const RunInfo& info = *status_.info;
    std::vector<PlotSeries> series;
    // x is the time (or load factor) while it only goes forward; along a path that turns back
    // (arc length through a limit point) it is the solver step, so no curve folds over itself
    const bool by_time = std::is_sorted(history_.begin(), history_.end(),
                                        [](const Sample& a, const Sample& b) { return a.time < b.time; });
    auto x_of = [by_time](const Sample& s) { return by_time ? s.time : static_cast<double>(s.step); };
    // the samples of [from, end), thinned to about kMaxPlotPoints, the last one always
    auto collect = [&](std::size_t from, auto&& value) {
      const std::size_t n = history_.size() - from;
      const std::size_t stride = std::max<std::size_t>(1, (n + kMaxPlotPoints - 1) / kMaxPlotPoints);
      std::vector<double> t, y;
      for (std::size_t i = from; i < history_.size(); i += stride) {
        t.push_back(x_of(history_[i]));
        y.push_back(value(history_[i]));
      }
      if (n > 0 && (n - 1) % stride != 0) {
        t.push_back(x_of(history_.back()));
        y.push_back(value(history_.back()));
      }
      return std::pair{std::move(t), std::move(y)};
    };
    auto add = [&](std::string title, std::size_t from, auto&& value) {
      auto [t, y] = collect(from, value);
      series.push_back({std::move(title), std::move(t), std::move(y)});
    };
    if (status_.probe_node >= 0) {
      // the node's history starts where it was placed: nothing is drawn for the time before
      const std::size_t from = probe_history_start();
      const bool elastic = from < history_.size() && history_[from].has_deflection;
      add("node " + std::to_string(status_.probe_node) + (elastic ? " elastic |x - x_base|" : " |x - X|"), from,
          [elastic](const Sample& s) { return elastic ? s.node_deflection : s.node_displacement; });
    }
    for (std::size_t p = 0; p < info.probes.size(); ++p) {
      const Quantity& q = info.probes[p];
      std::string t = q.label.empty() ? q.name : q.label;
      if (!q.unit.empty()) t += " [" + q.unit + "]";
      add(t, 0, [p](const Sample& s) { return p < s.probes.size() ? s.probes[p] : 0.0; });
    }
    add("Newton iterations per step", 0, [](const Sample& s) { return s.stats.iterations; });

    const int columns = std::max(1, static_cast<int>(width / 290.0f));
    constexpr float kCellPadY = 3.0f;
    ImGui::PushStyleVar(ImGuiStyleVar_CellPadding, ImVec2(8.0f, kCellPadY));
    // two rows of plots fill the panel exactly (more scroll): a row is its padding, the title
    // line, the plot and the x labels (draw_plot's extent)
    const float row_h = std::floor(ImGui::GetContentRegionAvail().y / 2.0f);
    const float plot_h = std::max(24.0f, row_h - 2.0f * kCellPadY - 2.0f * ImGui::GetTextLineHeight() - 6.0f);
    if (ImGui::BeginTable("plots", columns, ImGuiTableFlags_ScrollY | ImGuiTableFlags_SizingStretchSame)) {
      const std::string x_name = !by_time ? "step" : info.time_unit.empty() ? lambda_text() : "t";
      const std::string x_unit = by_time ? info.time_unit : "";
      for (const PlotSeries& ps : series) {
        ImGui::TableNextColumn();
        ImGui::PushID(ps.title.c_str());
        draw_plot(ps, plot_h, x_name, x_unit);
        ImGui::PopID();
      }
      ImGui::EndTable();
    }
    ImGui::PopStyleVar();
  }

  struct PlotSeries {
    std::string title;
    std::vector<double> t, y;  ///< x (time, load factor or step) and value
  };

  /// One plot in the current cell: the title cut to the cell with the latest value at its right;
  /// the curve over its own time span; the y range at its left (max at the top, min at the bottom);
  /// the time span below. Hovering shows the value under the mouse.
  static void draw_plot(const PlotSeries& ps, float plot_h, const std::string& x_name, const std::string& x_unit) {
    const float width = ImGui::GetContentRegionAvail().x;
    const float line = ImGui::GetTextLineHeight();
    const ImU32 text_col = ImGui::GetColorU32(ImGuiCol_Text), faint_col = ImGui::GetColorU32(ImGuiCol_TextDisabled);
    const std::string value = ps.y.empty() ? "-" : short_number(ps.y.back());
    const float value_w = ImGui::CalcTextSize(value.c_str()).x;
    ImDrawList* dl = ImGui::GetWindowDrawList();

    // title line
    const ImVec2 top = ImGui::GetCursorScreenPos();
    const std::string title = fit_text(ps.title, std::max(10.0f, width - value_w - 12.0f));
    dl->AddText(top, text_col, title.c_str());
    dl->AddText(ImVec2(top.x + width - value_w, top.y), text_col, value.c_str());

    // y range, over the finite values (a diverged run's last values may not be)
    double lo = DBL_MAX, hi = -DBL_MAX;
    for (double y : ps.y)
      if (std::isfinite(y)) lo = std::min(lo, y), hi = std::max(hi, y);
    if (lo > hi) lo = hi = 0.0;
    const bool flat = !(hi > lo);
    const std::string hi_text = short_number(hi), lo_text = short_number(lo);
    const float gutter = std::max(ImGui::CalcTextSize(hi_text.c_str()).x, ImGui::CalcTextSize(lo_text.c_str()).x) + 6.0f;
    const ImVec2 a(top.x + gutter, top.y + line + 4.0f), b(top.x + width, a.y + plot_h);
    dl->AddRectFilled(a, b, ImGui::GetColorU32(ImGuiCol_FrameBg));
    if (flat) {
      // one value: its line through the middle, labelled once
      dl->AddText(ImVec2(a.x - 4.0f - ImGui::CalcTextSize(hi_text.c_str()).x, 0.5f * (a.y + b.y - line)), faint_col,
                  hi_text.c_str());
    } else {
      dl->AddText(ImVec2(a.x - 4.0f - ImGui::CalcTextSize(hi_text.c_str()).x, a.y), faint_col, hi_text.c_str());
      dl->AddText(ImVec2(a.x - 4.0f - ImGui::CalcTextSize(lo_text.c_str()).x, b.y - line), faint_col, lo_text.c_str());
    }
    const double t0 = ps.t.empty() ? 0.0 : ps.t.front(), t1 = ps.t.empty() ? 0.0 : ps.t.back();
    auto to_screen = [&](double t, double y) {
      const float fx = t1 > t0 ? static_cast<float>((t - t0) / (t1 - t0)) : 1.0f;
      const float fy = flat ? 0.5f : static_cast<float>((y - lo) / (hi - lo));
      return ImVec2(a.x + 1.0f + fx * (b.x - a.x - 2.0f), b.y - 1.0f - fy * (b.y - a.y - 2.0f));
    };
    if (!flat && lo < 0.0 && hi > 0.0) {
      const float y0 = to_screen(t0, 0.0).y;
      dl->AddLine(ImVec2(a.x, y0), ImVec2(b.x, y0), faint_col);
    }
    const ImU32 curve_col = ImGui::GetColorU32(ImGuiCol_PlotLines);
    // the curve, broken where a value is not finite; a lone point as a dot
    std::vector<ImVec2> pts;
    auto flush = [&] {
      if (pts.size() == 1) dl->AddCircleFilled(pts[0], 2.5f, curve_col);
      if (pts.size() > 1) dl->AddPolyline(pts.data(), static_cast<int>(pts.size()), curve_col, ImDrawFlags_None, 1.2f);
      pts.clear();
    };
    for (std::size_t i = 0; i < ps.t.size(); ++i) {
      if (std::isfinite(ps.y[i]))
        pts.push_back(to_screen(ps.t[i], ps.y[i]));
      else
        flush();
    }
    flush();

    // x span below: the start at the left, the end and unit at the right (the end alone when narrow)
    const std::string unit = x_unit.empty() ? "" : " " + x_unit;
    const std::string left = x_name + " " + short_number(t0), right = short_number(t1) + unit;
    const float right_w = ImGui::CalcTextSize(right.c_str()).x;
    if (!ps.t.empty()) {
      if (ImGui::CalcTextSize(left.c_str()).x + right_w + 12.0f < b.x - a.x)
        dl->AddText(ImVec2(a.x, b.y + 2.0f), faint_col, left.c_str());
      dl->AddText(ImVec2(b.x - right_w, b.y + 2.0f), faint_col, right.c_str());
    }

    // the cell's extent for the layout, and the hover read-out
    ImGui::InvisibleButton("##plot", ImVec2(width, b.y + 2.0f + line - top.y));
    if (ImGui::IsItemHovered() && !ps.t.empty()) {
      const float mx = ImGui::GetIO().MousePos.x;
      std::size_t k = 0;
      float best = FLT_MAX;
      for (std::size_t i = 0; i < ps.t.size(); ++i) {
        const float d = std::fabs(to_screen(ps.t[i], 0.0).x - mx);
        if (d < best) best = d, k = i;
      }
      const ImVec2 at = to_screen(ps.t[k], std::isfinite(ps.y[k]) ? ps.y[k] : lo);
      dl->AddLine(ImVec2(at.x, a.y), ImVec2(at.x, b.y), faint_col);
      if (std::isfinite(ps.y[k])) dl->AddCircleFilled(at, 3.0f, curve_col);
      ImGui::SetTooltip("%s\n%s = %.6g%s: %.6g", ps.title.c_str(), x_name.c_str(), ps.t[k], unit.c_str(), ps.y[k]);
    }
  }

  void draw_status() {
    const char* unit = status_.info ? status_.info->time_unit.c_str() : "";
    const double t = history_.empty() ? 0.0 : history_.back().time;
    const long long step = history_.empty() ? 0 : history_.back().step;
    // a load-controlled run (no time unit) counts the load factor
    const std::string t_name = status_.info && status_.info->time_unit.empty() ? lambda_text() : "t";
    std::string line = std::string(to_string(status_.state)) + " | " + t_name + " = " + fmt("%.4g", t) + " / " +
                       fmt("%.4g", status_.end_time) + (unit[0] ? " " : "") + unit + " | step " + std::to_string(step) + " | " +
                       fmt("%.0f", steps_per_second()) + " steps/s" + pace_text() + " | " +
                       std::to_string(frames_per_second()) + " fps | last frame: " +
                       std::to_string(last_stats_.iterations) + " Newton it., " +
                       std::to_string(last_stats_.jacobian_updates) + " matrix updates, |R| " +
                       fmt("%.2e", last_stats_.residual_norm) + (last_stats_.converged ? "" : " (not converged)");
    if (status_.outcome && status_.outcome->status != RunStatus::completed)
      line += " | " + std::string(ff::to_string(status_.outcome->status)) + ": " + status_.outcome->reason;
    ImGui::TextUnformatted(line.c_str());
    if (!message_.empty()) {
      ImGui::SameLine();
      const std::string first = refusal_ ? refusal_->text : message_.substr(0, message_.find('\n'));
      ImGui::TextColored(message_is_error_ ? ImVec4(0.8f, 0.1f, 0.1f, 1) : ImVec4(0.2f, 0.45f, 0.2f, 1), "| %s",
                         first.c_str());
      if (ImGui::IsItemHovered()) ImGui::SetTooltip("%s", message_.c_str());
    }
  }

  GLFWwindow* window_;
  GuiOptions opt_;
  std::unique_ptr<SimWorker> worker_;
  Viewport viewport_;
  ParamEditor params_;
  SetupPanel setup_;
  PickState pick_;
  std::tuple<const void*, std::string, std::set<int>> highlighted_{nullptr, "", {}};  // what update_highlights drew
  WorkerStatus status_;
  std::vector<Sample> history_;
  struct RatePoint {
    Clock::time_point at;
    long long step = 0;
    double time = 0.0;
  };
  std::deque<RatePoint> rate_;          // samples of the last two seconds: steps/s, real-time factor
  std::deque<Clock::time_point> draws_;  // window frames of the last second: fps
  StepStats last_stats_;
  std::vector<std::string> bundled_;
  std::string scene_field_, save_path_, export_path_;
  std::string message_;
  bool message_is_error_ = false;
  std::optional<Refusal> refusal_;  // the last message, when it is a refusal, in the window's words
  long long redraws_ = 0;           // window frames drawn (the `redraws` action prints it)
  int step_count_ = 1, probe_input_ = 0;
  double pace_ = 0.0;

  std::vector<Action> actions_;
  std::size_t next_action_ = 0;
  const Action* current_action_ = nullptr;
  std::uint64_t waiting_seq_ = 0, message_seq_at_issue_ = 0;
  Clock::time_point wait_until_{};
  bool waiting_end_ = false;  // a wait-end action waits for the run's outcome
  std::size_t announced_ = 0;  // the last action whose line was printed (1-based)
  std::string pending_screenshot_, pending_export_;
  Clock::time_point start_;
  const std::atomic<bool>& stop_;
  bool quit_ = false;
  int exit_code_ = 0;
};

/// Checks a script's edits before any window opens, by making them on the scene text in order
/// (the picks of use-pick come from clicks and are left to the run): a bad one is FILE:LINE.
void check_actions(const std::vector<Action>& actions, std::string text, std::string path) {
  for (const Action& a : actions) {
    try {
      switch (a.kind) {
        case Action::Kind::set: text = with_key_set(text, path, a.key, a.text).text; break;
        case Action::Kind::new_problem:
        case Action::Kind::open: {
          const SceneToOpen s = a.kind == Action::Kind::open ? scene_to_open(a.text) : new_problem(a.text);
          text = s.text, path = s.path;
          break;
        }
        default:
          if (const std::optional<SetupRequest> r = scene_edit_of(a)) text = r->op(text, path).text;
      }
    } catch (const std::exception& e) {
      throw ActionError(a.where() + ": " + describe(a) + ": " + e.what());
    }
  }
}

}  // namespace

int run_gui(const GuiOptions& opt, const std::atomic<bool>& stop) {
  std::vector<Action> actions;
  try {
    if (!opt.actions_file.empty()) {
      actions = read_actions(opt.actions_file);
    }
  } catch (const ActionError& e) {
    std::fprintf(stderr, "error: bad actions file: %s\n", e.what());
    return 2;
  }
  // the scene as a text: a file with its --set edits folded in, or a new problem
  const SceneToOpen opened = opt.new_problem.empty() ? scene_to_open(opt.scene_path) : new_problem(opt.new_problem);
  const std::string& path = opened.path;
  const std::string text = scene::edited_scene_text(opened.text, path, opt.overrides);
  try {
    check_actions(actions, text, path);
  } catch (const ActionError& e) {
    std::fprintf(stderr, "error: bad actions file: %s\n", e.what());
    return 2;
  }

  const char* display = std::getenv("DISPLAY");
  const char* wayland = std::getenv("WAYLAND_DISPLAY");
  if ((display == nullptr || display[0] == '\0') && (wayland == nullptr || wayland[0] == '\0')) {
    std::fprintf(stderr, "error: flexframe gui needs a display, and DISPLAY is not set.\n%s\n", kHeadlessHint);
    return kNoDisplayExitCode;
  }
  glfwSetErrorCallback(on_glfw_error);
  if (!glfwInit()) {
    std::fprintf(stderr, "error: flexframe gui cannot open the display '%s' (%s).\n%s\n", display ? display : "",
                 g_glfw_error.c_str(), kHeadlessHint);
    return kNoDisplayExitCode;
  }

  // the scene is read before the window opens: bad input is reported like `flexframe run` does
  scene::LoadedScene scene;
  try {
    scene = scene::load_scene_text(text, path, {}, io::scene_context());
  } catch (...) {
    glfwTerminate();
    throw;
  }

  glfwWindowHint(GLFW_CONTEXT_VERSION_MAJOR, 3);
  glfwWindowHint(GLFW_CONTEXT_VERSION_MINOR, 3);
  glfwWindowHint(GLFW_OPENGL_PROFILE, GLFW_OPENGL_CORE_PROFILE);
  const std::string title = "FlexFrame - " + scene.name;
  GLFWwindow* window = glfwCreateWindow(opt.width, opt.height, title.c_str(), nullptr, nullptr);
  if (window == nullptr) {
    std::fprintf(stderr, "error: flexframe gui could not open an OpenGL 3.3 window (%s).\n%s\n", g_glfw_error.c_str(),
                 kHeadlessHint);
    glfwTerminate();
    return kNoDisplayExitCode;
  }
  glfwMakeContextCurrent(window);
  glfwSwapInterval(0);
  install_input_callbacks(window);

  IMGUI_CHECKVERSION();
  ImGui::CreateContext();
  ImGui::GetIO().IniFilename = nullptr;  // no imgui.ini in the working folder
  load_fonts();
  ImGui::StyleColorsLight();
  ImGuiStyle& style = ImGui::GetStyle();
  style.WindowRounding = 0.0f;
  style.FrameRounding = 3.0f;
  style.WindowBorderSize = 1.0f;
  ImGui_ImplGlfw_InitForOpenGL(window, true);
  ImGui_ImplOpenGL3_Init("#version 330 core");

  int code = 0;
  {
    // the solver thread wakes the sleeping window when it has news
    auto worker = std::make_unique<SimWorker>(std::move(scene), text, opened.text, opened.from,
                                              [] { glfwPostEmptyEvent(); });
    GuiApp app(window, opt, std::move(worker), std::move(actions), stop);
    code = app.loop();
  }

  ImGui_ImplOpenGL3_Shutdown();
  ImGui_ImplGlfw_Shutdown();
  ImGui::DestroyContext();
  glfwDestroyWindow(window);
  glfwTerminate();
  return code;
}

}  // namespace ff::app::gui
