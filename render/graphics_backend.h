#pragma once
/// \file graphics_backend.h
/// The window-system paths a GraphicsContext can render through (graphics_context.h).

namespace ff::render {

/// Which window-system path a GraphicsContext uses.
enum class Backend {
  automatic,        ///< EGL surfaceless when $DISPLAY is unset/empty or does not answer, else X11
  egl_surfaceless,  ///< Mesa EGL without any window system (works with or without a display)
  x11,              ///< VTK's X11 OpenGL render window, off screen (needs a working display)
};

/// "egl-surfaceless" or "x11" ("automatic" for Backend::automatic).
const char* to_string(Backend b);

}  // namespace ff::render
