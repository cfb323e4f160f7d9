#include "render/graphics_context.h"

#include <X11/Xlib.h>
// Xlib's macros collide with VTK and the standard library
#undef None
#undef Bool
#undef Status
#undef Success
#undef Always

#include <vtkNew.h>
#include <vtkRenderer.h>

#include <cstdlib>
#include <sstream>

#include "render/backend_state.h"
#include "render/render_surface.h"
#include "render/vtk_messages.h"

namespace ff::render {

namespace detail {
bool glew_shim_linked();  // glew_shim.cpp
}

namespace {

constexpr unsigned int kGlRenderer = 0x1F01;  // GL_RENDERER
constexpr unsigned int kGlVersion = 0x1F02;   // GL_VERSION

bool display_env_set() {
  const char* d = std::getenv("DISPLAY");
  return d != nullptr && d[0] != '\0';
}

// true when $DISPLAY names an X server that answers and offers GLX; VTK's X window would
// abort the process otherwise, so this is checked before any VTK window exists
bool x_display_usable(std::string* why) {
  if (!display_env_set()) {
    *why = "DISPLAY is unset";
    return false;
  }
  ::Display* dpy = XOpenDisplay(nullptr);
  if (dpy == nullptr) {
    *why = std::string("cannot open X display '") + std::getenv("DISPLAY") + "'";
    return false;
  }
  int opcode = 0, event = 0, error = 0;
  const bool glx = XQueryExtension(dpy, "GLX", &opcode, &event, &error) != 0;
  XCloseDisplay(dpy);
  if (!glx) *why = "X display has no GLX extension";
  return glx;
}

// "OpenGL renderer string:  llvmpipe (...)" -> "llvmpipe (...)"
std::string capability_line(const std::string& report, const std::string& key) {
  std::istringstream in(report);
  std::string line;
  while (std::getline(in, line)) {
    const auto at = line.find(key);
    if (at == std::string::npos) continue;
    std::string value = line.substr(at + key.size());
    const auto first = value.find_first_not_of(" :\t");
    return first == std::string::npos ? std::string() : value.substr(first);
  }
  return {};
}

bool probe_egl(BackendState* impl, std::string* error) {
  if (!egl::acquire_display(&impl->egl, error)) return false;
  void* ctx = egl::create_context(impl->egl, error);
  if (ctx == nullptr) return false;  // ~Impl releases the display
  if (!egl::make_current(impl->egl, ctx)) {
    egl::destroy_context(impl->egl, ctx);
    *error = "eglMakeCurrent failed on the surfaceless display";
    return false;
  }
  impl->gl_renderer = egl::gl_string(kGlRenderer);
  impl->gl_version = egl::gl_string(kGlVersion);
  egl::destroy_context(impl->egl, ctx);
  if (impl->gl_renderer.empty()) {
    *error = "EGL context made but glGetString(GL_RENDERER) returned nothing";
    return false;
  }
  return true;
}

// the X11 window reports its renderer only once it has a context: render one tiny frame
bool probe_x11(GraphicsContext& gc, std::string* error) {
  RenderSurface surface(gc.state(), 32, 32);
  if (!surface.ok()) {
    *error = surface.error();
    return false;
  }
  vtkNew<vtkRenderer> renderer;
  surface.window()->AddRenderer(renderer);
  MessageCapture vtk_errors;
  surface.window()->Render();
  const std::string report = surface.window()->ReportCapabilities();
  surface.window()->RemoveRenderer(renderer);
  BackendState& impl = gc.state();
  impl.gl_renderer = capability_line(report, "OpenGL renderer string");
  impl.gl_version = capability_line(report, "OpenGL version string");
  if (impl.gl_renderer.empty()) {
    *error = "the X11 render window gave no GL renderer string";
    if (!vtk_errors.empty()) *error += ": " + vtk_errors.text();
    return false;
  }
  return true;
}

}  // namespace

const char* to_string(Backend b) {
  switch (b) {
    case Backend::automatic: return "automatic";
    case Backend::egl_surfaceless: return "egl-surfaceless";
    case Backend::x11: return "x11";
  }
  return "automatic";
}

std::recursive_mutex& vtk_mutex() {
  static std::recursive_mutex m;
  return m;
}

BackendState::~BackendState() {
  if (backend == Backend::egl_surfaceless && egl.display != nullptr) egl::release_display();
}

GraphicsContext::GraphicsContext(std::unique_ptr<BackendState> state) : state_(std::move(state)) {}

GraphicsContext::~GraphicsContext() {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  state_.reset();
}

std::unique_ptr<GraphicsContext> GraphicsContext::create(std::string* error, Backend preferred) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  install_vtk_message_filter();
  detail::glew_shim_linked();

  std::string why_not_x;
  Backend chosen = preferred;
  if (preferred == Backend::automatic)
    chosen = x_display_usable(&why_not_x) ? Backend::x11 : Backend::egl_surfaceless;
  else if (preferred == Backend::x11 && !x_display_usable(&why_not_x)) {
    if (error) *error = "X11 backend requested but " + why_not_x;
    return nullptr;
  }

  auto impl = std::make_unique<BackendState>();
  impl->backend = chosen;
  std::string err;
  if (chosen == Backend::egl_surfaceless) {
    if (!probe_egl(impl.get(), &err)) {
      if (error) {
        *error = "EGL surfaceless backend failed: " + err;
        if (!why_not_x.empty() && display_env_set()) *error += " (and X11: " + why_not_x + ")";
      }
      return nullptr;
    }
    return std::unique_ptr<GraphicsContext>(new GraphicsContext(std::move(impl)));
  }
  std::unique_ptr<GraphicsContext> gc(new GraphicsContext(std::move(impl)));
  if (probe_x11(*gc, &err)) return gc;
  gc.reset();
  if (preferred == Backend::automatic) {
    // the display answered but VTK's X window did not work: the headless path still may
    std::string egl_err;
    if (auto fallback = create(&egl_err, Backend::egl_surfaceless)) return fallback;
    if (error) *error = "X11 backend failed: " + err + "; EGL surfaceless failed: " + egl_err;
    return nullptr;
  }
  if (error) *error = "X11 backend failed: " + err;
  return nullptr;
}

std::string GraphicsContext::backend() const { return to_string(state_->backend); }
Backend GraphicsContext::backend_kind() const { return state_->backend; }
std::string GraphicsContext::gl_renderer() const { return state_->gl_renderer; }
std::string GraphicsContext::gl_version() const { return state_->gl_version; }

}  // namespace ff::render
