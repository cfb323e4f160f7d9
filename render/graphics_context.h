#pragma once
/// \file graphics_context.h
/// The OpenGL backend every VTK render in render/ goes through. Headless first: with no display
/// it renders through Mesa's EGL surfaceless platform (llvmpipe), with a display through VTK's
/// X11 render window used off screen. No VTK or EGL types appear here.

#include <memory>
#include <mutex>
#include <string>

#include "render/graphics_backend.h"

namespace ff::render {

struct BackendState;

/// A process-wide OpenGL backend choice plus what it reported.
///
/// Threading: one GraphicsContext per thread that renders; a GraphicsContext and every
/// FrameRenderer made from it are used from that thread only, and must be destroyed before
/// it. Each renderer owns its own GL context, so several renderers may share one
/// GraphicsContext. All render entry points of render/ hold vtk_mutex() while they touch VTK,
/// so renders from different threads are serialized (VTK's text and factory singletons are
/// not thread safe); output is byte-identical whichever thread renders.
class GraphicsContext {
 public:
  /// Picks and checks the backend before any VTK window exists. For Backend::automatic:
  /// EGL surfaceless when $DISPLAY is unset or empty (or names a display that does not
  /// answer), the X11 off-screen window when a display answers. A VTK X11 window created
  /// with no display aborts the process, so none is ever created in that case.
  /// Also installs the VTK message filter (see vtk_messages.h). Returns nullptr and fills
  /// *error (if non-null) when nothing works.
  static std::unique_ptr<GraphicsContext> create(std::string* error,
                                                 Backend preferred = Backend::automatic);

  ~GraphicsContext();
  GraphicsContext(const GraphicsContext&) = delete;
  GraphicsContext& operator=(const GraphicsContext&) = delete;

  /// "egl-surfaceless" or "x11": the backend in use (store it with results).
  std::string backend() const;
  Backend backend_kind() const;
  /// GL_RENDERER of a context made by this backend, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
  std::string gl_renderer() const;
  /// GL_VERSION of that context, e.g. "4.5 (Core Profile) Mesa 22.3.6".
  std::string gl_version() const;

  /// Internal state shared with the render targets of render/ (render/backend_state.h).
  BackendState& state() { return *state_; }

 private:
  explicit GraphicsContext(std::unique_ptr<BackendState> state);
  std::unique_ptr<BackendState> state_;
};

/// Lock held by render/ around every use of VTK. Code elsewhere that drives VTK in the same
/// process (e.g. a GUI view) should hold it too while rendering.
std::recursive_mutex& vtk_mutex();

}  // namespace ff::render
