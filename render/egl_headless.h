#pragma once
/// \file egl_headless.h
/// Internal to render/: Mesa EGL on the surfaceless platform (no window system at all).
/// Handles are opaque pointers so this header pulls in neither EGL nor X11 headers.
/// Recipe and pitfalls: render/README.md, "Backend choice".

#include <string>

namespace ff::render::egl {

/// The process-wide surfaceless EGLDisplay, initialized on first acquire and terminated when
/// the last holder releases it (EGL returns the same display handle to every thread, so a
/// per-object eglTerminate would pull it from under other threads).
struct Display {
  void* display = nullptr;  ///< EGLDisplay
  void* config = nullptr;   ///< EGLConfig: RGBA8, depth 24, desktop OpenGL
};

/// Acquires the display (reference counted). Returns false and fills *error on failure.
bool acquire_display(Display* out, std::string* error);
/// Releases one reference taken by acquire_display.
void release_display();

/// Creates a desktop-OpenGL 3.2+ core context (VTK 9.1 needs 3.2) with no surface.
/// Binds EGL_OPENGL_API on the calling thread. Returns nullptr and fills *error on failure.
void* create_context(const Display& d, std::string* error);
/// Makes ctx current on the calling thread with no surface (ctx == nullptr releases).
bool make_current(const Display& d, void* ctx);
/// True when ctx is the calling thread's current desktop-GL context.
bool is_current(void* ctx);
/// True when the calling thread has any current EGL desktop-GL context.
bool any_current();
/// Releases ctx from the calling thread if current, then destroys it.
void destroy_context(const Display& d, void* ctx);

/// glGetString(name) for the context current on this thread ("" if unavailable).
std::string gl_string(unsigned int name);

}  // namespace ff::render::egl
