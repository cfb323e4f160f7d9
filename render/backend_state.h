#pragma once
/// \file backend_state.h
/// Internal to render/: what a GraphicsContext holds of its backend, shared with the render
/// targets made from it (render_surface.h). Its own header so that a render target needs
/// neither the context's interface nor the context the render targets it probes with.

#include <string>

#include "render/egl_headless.h"
#include "render/graphics_backend.h"

namespace ff::render {

struct BackendState {
  Backend backend = Backend::egl_surfaceless;
  egl::Display egl;  ///< valid for Backend::egl_surfaceless (one reference held)
  std::string gl_renderer;
  std::string gl_version;
  ~BackendState();  // graphics_context.cpp: releases the EGL display
};

}  // namespace ff::render
