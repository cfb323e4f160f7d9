#include "render/render_surface.h"

#include <vtkCallbackCommand.h>
#include <vtkCommand.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkOpenGLRenderWindow.h>
#include <vtkRenderer.h>
#include <vtkRendererCollection.h>
#include <vtkUnsignedCharArray.h>

#include "render/png_file.h"
#include "render/vtk_messages.h"

namespace ff::render {

namespace {

void on_make_current(vtkObject*, unsigned long, void* client, void*) {
  auto* b = static_cast<RenderSurface::EglTarget*>(client);
  if (!egl::is_current(b->context)) egl::make_current(b->display, b->context);
}

void on_is_current(vtkObject*, unsigned long, void* client, void* call) {
  auto* b = static_cast<RenderSurface::EglTarget*>(client);
  *static_cast<bool*>(call) = egl::is_current(b->context);
}

void on_answer_yes(vtkObject*, unsigned long, void*, void* call) { *static_cast<int*>(call) = 1; }

}  // namespace

RenderSurface::RenderSurface(BackendState& backend, int width, int height) : gc_(backend) {
  if (width < 16 || height < 16 || width > 16384 || height > 16384) {
    error_ = "image size " + std::to_string(width) + "x" + std::to_string(height) +
             " is outside 16..16384";
    return;
  }
  if (gc_.backend == Backend::egl_surfaceless) {
    egl_.display = gc_.egl;
    egl_.context = egl::create_context(gc_.egl, &error_);
    if (egl_.context == nullptr) return;
    if (!egl::make_current(gc_.egl, egl_.context)) {
      error_ = "eglMakeCurrent failed for a new render context";
      return;
    }
    auto win = vtkSmartPointer<vtkGenericOpenGLRenderWindow>::New();
    vtkNew<vtkCallbackCommand> make_current_cb;
    make_current_cb->SetCallback(on_make_current);
    make_current_cb->SetClientData(&egl_);
    vtkNew<vtkCallbackCommand> is_current_cb;
    is_current_cb->SetCallback(on_is_current);
    is_current_cb->SetClientData(&egl_);
    vtkNew<vtkCallbackCommand> yes_cb;
    yes_cb->SetCallback(on_answer_yes);
    win->AddObserver(vtkCommand::WindowMakeCurrentEvent, make_current_cb);
    win->AddObserver(vtkCommand::WindowIsCurrentEvent, is_current_cb);
    win->AddObserver(vtkCommand::WindowSupportsOpenGLEvent, yes_cb);
    win->AddObserver(vtkCommand::WindowIsDirectEvent, yes_cb);
    win->SetOwnContext(false);
    win->SetReadyForRendering(true);
    win->SetIsCurrent(true);
    win->SetOffScreenRendering(1);
    // render into VTK's own framebuffer and read back from it; nothing to show on screen
    win->SetFrameBlitModeToNoBlit();
    window_ = win;
  } else {
    // the X11 window class from VTK's factory; only reached after $DISPLAY answered
    window_ = vtkSmartPointer<vtkRenderWindow>::New();
    window_->SetOffScreenRendering(1);
  }
  // no multisampling: on llvmpipe resolving it costs more than the whole frame
  window_->SetMultiSamples(0);
  window_->SetSize(width, height);
  window_->SetAlphaBitPlanes(0);

  ok_ = true;
}

RenderSurface::~RenderSurface() {
  if (window_ != nullptr) {
    // free VTK's GL objects while their context can still be made current (the observers
    // hold &egl_, which outlives the window), then drop the window
    window_->MakeCurrent();
    window_->Finalize();
    // detach renderers so none keeps a pointer to the destroyed window
    while (vtkRenderer* r = window_->GetRenderers()->GetFirstRenderer()) window_->RemoveRenderer(r);
    window_ = nullptr;
  }
  if (egl_.context != nullptr) egl::destroy_context(gc_.egl, egl_.context);
}

void RenderSurface::make_current() {
  if (window_ != nullptr) window_->MakeCurrent();
}

bool RenderSurface::render_to_png(const std::string& path, std::string* error) {
  // read back and encode here rather than through vtkWindowToImageFilter + vtkPNGWriter: two
  // image copies fewer, and libpng with one fixed filter (png_file.h)
  std::string vtk_messages;
  if (!render_and_read(&pixels_, &vtk_messages, error)) return false;
  if (!vtk_messages.empty()) {  // a frame VTK complained about is not written as if it were fine
    if (error) *error = "VTK reported: " + vtk_messages;
    return false;
  }
  const int* size = window_->GetSize();
  return write_png_rgb(path, pixels_.data(), size[0], size[1], /*bottom_up=*/true, error);
}

bool RenderSurface::render_to_rgb(std::vector<unsigned char>* rgb, std::string* error) {
  std::string vtk_messages;
  return render_and_read(rgb, &vtk_messages, error);
}

bool RenderSurface::render_and_read(std::vector<unsigned char>* rgb, std::string* vtk_messages, std::string* error) {
  if (!ok_) {
    if (error) *error = error_;
    return false;
  }
  MessageCapture vtk_errors;
  window_->Render();
  const int* size = window_->GetSize();
  const int w = size[0], h = size[1];
  vtkNew<vtkUnsignedCharArray> pixels;
  // the back buffer: where VTK's off-screen framebuffer is read from
  window_->GetPixelData(0, 0, w - 1, h - 1, 0, pixels, 0);
  *vtk_messages = vtk_errors.text();
  if (pixels->GetNumberOfValues() != static_cast<vtkIdType>(3) * w * h) {
    if (error) *error = "could not read the rendered image back" + (vtk_errors.empty() ? "" : ": " + vtk_errors.text());
    return false;
  }
  rgb->assign(pixels->GetPointer(0), pixels->GetPointer(0) + 3 * static_cast<std::size_t>(w) * h);
  return true;
}

}  // namespace ff::render
