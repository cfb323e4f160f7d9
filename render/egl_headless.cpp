#include "render/egl_headless.h"

// keep X11's macros (None, Bool, Status ...) out: this file needs no native window types
#define EGL_NO_X11
#define MESA_EGL_NO_X11_HEADERS
#include <EGL/egl.h>
#include <EGL/eglext.h>

#include <cstdio>
#include <cstring>
#include <mutex>

namespace ff::render::egl {
namespace {

std::mutex g_display_mutex;
int g_display_refs = 0;
Display g_display;

std::string egl_error_text(const char* what) {
  char buf[96];
  std::snprintf(buf, sizeof buf, "%s failed (EGL error 0x%04x)", what,
                static_cast<unsigned>(eglGetError()));
  return buf;
}

bool has_extension(const char* list, const char* name) {
  if (list == nullptr) return false;
  const std::size_t n = std::strlen(name);
  for (const char* p = list; (p = std::strstr(p, name)) != nullptr; p += n) {
    const bool starts = (p == list) || p[-1] == ' ';
    const bool ends = p[n] == ' ' || p[n] == '\0';
    if (starts && ends) return true;
  }
  return false;
}

bool open_display(Display* d, std::string* error) {
  const char* client_ext = eglQueryString(EGL_NO_DISPLAY, EGL_EXTENSIONS);
  if (!has_extension(client_ext, "EGL_MESA_platform_surfaceless")) {
    *error = "EGL client does not offer EGL_MESA_platform_surfaceless (is Mesa's libEGL installed?)";
    return false;
  }
  auto get_platform_display = reinterpret_cast<PFNEGLGETPLATFORMDISPLAYEXTPROC>(
      eglGetProcAddress("eglGetPlatformDisplayEXT"));
  if (get_platform_display == nullptr) {
    *error = "eglGetPlatformDisplayEXT is not available";
    return false;
  }
  EGLDisplay dpy = get_platform_display(EGL_PLATFORM_SURFACELESS_MESA, EGL_DEFAULT_DISPLAY, nullptr);
  if (dpy == EGL_NO_DISPLAY) {
    *error = egl_error_text("eglGetPlatformDisplayEXT(surfaceless)");
    return false;
  }
  EGLint major = 0, minor = 0;
  if (eglInitialize(dpy, &major, &minor) != EGL_TRUE) {
    *error = egl_error_text("eglInitialize");
    return false;
  }
  // the config only matters for context creation: VTK renders into its own framebuffers
  const EGLint attribs[] = {EGL_SURFACE_TYPE, EGL_PBUFFER_BIT,  EGL_RENDERABLE_TYPE, EGL_OPENGL_BIT,
                            EGL_RED_SIZE,     8,                EGL_GREEN_SIZE,      8,
                            EGL_BLUE_SIZE,    8,                EGL_ALPHA_SIZE,      8,
                            EGL_DEPTH_SIZE,   24,               EGL_NONE};
  EGLConfig config = nullptr;
  EGLint count = 0;
  if (eglChooseConfig(dpy, attribs, &config, 1, &count) != EGL_TRUE || count < 1) {
    *error = "no EGL config with desktop OpenGL, RGBA8 and depth 24 on the surfaceless platform";
    eglTerminate(dpy);
    return false;
  }
  d->display = dpy;
  d->config = config;
  return true;
}

}  // namespace

bool acquire_display(Display* out, std::string* error) {
  std::lock_guard<std::mutex> lock(g_display_mutex);
  if (g_display_refs == 0) {
    std::string err;
    if (!open_display(&g_display, &err)) {
      if (error) *error = err;
      return false;
    }
  }
  ++g_display_refs;
  *out = g_display;
  return true;
}

void release_display() {
  std::lock_guard<std::mutex> lock(g_display_mutex);
  if (g_display_refs <= 0) return;
  if (--g_display_refs == 0) {
    eglTerminate(static_cast<EGLDisplay>(g_display.display));
    g_display = Display{};
  }
}

void* create_context(const Display& d, std::string* error) {
  // the bound API is per thread; the default is OpenGL ES
  if (eglBindAPI(EGL_OPENGL_API) != EGL_TRUE) {
    if (error) *error = egl_error_text("eglBindAPI(EGL_OPENGL_API)");
    return nullptr;
  }
  const EGLint attribs[] = {EGL_CONTEXT_MAJOR_VERSION,
                            3,
                            EGL_CONTEXT_MINOR_VERSION,
                            2,
                            EGL_CONTEXT_OPENGL_PROFILE_MASK,
                            EGL_CONTEXT_OPENGL_CORE_PROFILE_BIT,
                            EGL_NONE};
  EGLContext ctx = eglCreateContext(static_cast<EGLDisplay>(d.display),
                                    static_cast<EGLConfig>(d.config), EGL_NO_CONTEXT, attribs);
  if (ctx == EGL_NO_CONTEXT) {
    if (error) *error = egl_error_text("eglCreateContext(OpenGL 3.2 core)");
    return nullptr;
  }
  return ctx;
}

bool make_current(const Display& d, void* ctx) {
  eglBindAPI(EGL_OPENGL_API);
  EGLContext c = ctx ? static_cast<EGLContext>(ctx) : EGL_NO_CONTEXT;
  return eglMakeCurrent(static_cast<EGLDisplay>(d.display), EGL_NO_SURFACE, EGL_NO_SURFACE, c) ==
         EGL_TRUE;
}

bool is_current(void* ctx) {
  return ctx != nullptr && eglQueryAPI() == EGL_OPENGL_API &&
         eglGetCurrentContext() == static_cast<EGLContext>(ctx);
}

bool any_current() {
  return eglQueryAPI() == EGL_OPENGL_API && eglGetCurrentContext() != EGL_NO_CONTEXT;
}

void destroy_context(const Display& d, void* ctx) {
  if (ctx == nullptr) return;
  if (is_current(ctx)) make_current(d, nullptr);
  eglDestroyContext(static_cast<EGLDisplay>(d.display), static_cast<EGLContext>(ctx));
}

std::string gl_string(unsigned int name) {
  using GetString = const unsigned char* (*)(unsigned int);
  // core GL entry points through eglGetProcAddress (EGL 1.5 / EGL_KHR_get_all_proc_addresses)
  static const auto get = reinterpret_cast<GetString>(eglGetProcAddress("glGetString"));
  if (get == nullptr) return {};
  const unsigned char* s = get(name);
  return s ? std::string(reinterpret_cast<const char*>(s)) : std::string();
}

}  // namespace ff::render::egl
