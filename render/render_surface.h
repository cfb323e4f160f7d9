#pragma once
/// \file render_surface.h
/// Internal to render/ (exposes VTK): an off-screen VTK render window bound to a
/// GraphicsContext's backend (backend_state.h), with PNG read-back. Used by frame_renderer.cpp and plot.cpp.

#include <vtkNew.h>
#include <vtkRenderWindow.h>
#include <vtkSmartPointer.h>

#include <string>
#include <vector>

#include "render/backend_state.h"

namespace ff::render {

/// An off-screen VTK render window of a fixed size on the context's backend.
///  - egl-surfaceless: a vtkGenericOpenGLRenderWindow on its own EGL context; VTK's
///    make-current / is-current requests are answered by observers, so VTK can make it
///    current whenever it needs to (render, read-back, release of GL resources).
///  - x11: VTK's own X11 window class with off-screen rendering on.
/// The caller holds vtk_mutex() around every method, constructor and destructor included.
class RenderSurface {
 public:
  /// What VTK's make-current / is-current observers act on (egl-surfaceless only).
  struct EglTarget {
    egl::Display display;
    void* context = nullptr;
  };

  RenderSurface(BackendState& backend, int width, int height);
  ~RenderSurface();
  RenderSurface(const RenderSurface&) = delete;
  RenderSurface& operator=(const RenderSurface&) = delete;

  /// False when the window could not be set up; error() says why.
  bool ok() const { return ok_; }
  const std::string& error() const { return error_; }

  vtkRenderWindow* window() { return window_; }
  void make_current();

  /// Renders the window and writes its colour buffer (RGB) as PNG. Errors raised by VTK during
  /// the render make it fail with their text in *error, as does a file that cannot be written
  /// (with the path and the system's reason).
  bool render_to_png(const std::string& path, std::string* error);
  /// Renders the window and reads its colour buffer into *rgb: 3 bytes per pixel, rows from the
  /// bottom up (OpenGL order), width x height of the window.
  bool render_to_rgb(std::vector<unsigned char>* rgb, std::string* error);

 private:
  // renders and reads the colour buffer; VTK errors and warnings raised meanwhile go to *vtk_messages
  bool render_and_read(std::vector<unsigned char>* rgb, std::string* vtk_messages, std::string* error);
  BackendState& gc_;
  EglTarget egl_;
  vtkSmartPointer<vtkRenderWindow> window_;
  std::vector<unsigned char> pixels_;  // read-back buffer, kept between frames
  unsigned long observer_tags_[2] = {0, 0};
  bool ok_ = false;
  std::string error_;
};

}  // namespace ff::render
