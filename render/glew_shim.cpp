// Removes VTK's "GLEW could not be initialized" at its root on the EGL path
// (render/README.md, "The GLEW message").
//
// Debian's GLEW is built for GLX. glewInit() first loads the GL entry points
// (glewContextInit, which succeeds on our EGL context) and then initializes its GLX half,
// which fails with GLEW_ERROR_NO_GLX_DISPLAY because an EGL-surfaceless context has no X
// display. VTK treats any non-OK result as fatal for its context setup: it prints the message,
// skips the rest of its one-time initialization and retries on every render.
//
// This definition interposes on libGLEW's glewInit for the whole executable (the linker
// exports it because libvtkRenderingOpenGL2 references glewInit). It calls the real function
// and maps exactly GLEW_ERROR_NO_GLX_DISPLAY to GLEW_OK, and only while an EGL desktop-GL
// context is current on the calling thread, where GLX is never used. Everything else passes
// through unchanged. Set FF_RENDER_NO_GLEW_SHIM=1 to disable it (the message filter in
// vtk_messages.cpp then drops the message instead).

#include <dlfcn.h>

#include <cstdlib>

#include "render/egl_headless.h"

namespace {

constexpr unsigned int kGlewOk = 0;
constexpr unsigned int kGlewErrorNoGlVersion = 1;
constexpr unsigned int kGlewErrorNoGlxDisplay = 4;  // GLEW_ERROR_NO_GLX_DISPLAY in glew.h 2.x

using GlewInitFn = unsigned int (*)();

GlewInitFn real_glew_init() {
  static const GlewInitFn fn = reinterpret_cast<GlewInitFn>(dlsym(RTLD_NEXT, "glewInit"));
  return fn;
}

bool shim_disabled() {
  static const bool disabled = [] {
    const char* v = std::getenv("FF_RENDER_NO_GLEW_SHIM");
    return v != nullptr && v[0] != '\0' && v[0] != '0';
  }();
  return disabled;
}

}  // namespace

extern "C" __attribute__((visibility("default"))) unsigned int glewInit() {
  const GlewInitFn real = real_glew_init();
  if (real == nullptr || real == &glewInit) return kGlewErrorNoGlVersion;
  const unsigned int result = real();
  if (result == kGlewErrorNoGlxDisplay && !shim_disabled() && ff::render::egl::any_current())
    return kGlewOk;
  return result;
}

namespace ff::render::detail {
// referenced from GraphicsContext::create so the linker always pulls this object file in
bool glew_shim_linked() { return real_glew_init() != nullptr; }
}  // namespace ff::render::detail
