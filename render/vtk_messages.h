#pragma once
/// \file vtk_messages.h
/// Where VTK's messages go. VTK reports errors through a process-wide output window (and,
/// when built with logging, through vtkLogger as well). render/ installs one output window
/// that
///  - drops exactly one harmless message: "GLEW could not be initialized", which VTK prints on
///    the EGL path because GLEW's GLX half finds no X display (the frame renders correctly);
///    glew_shim.cpp normally prevents it at the root, this filter is the second line;
///  - forwards every other error and warning to stderr, prefixed "[vtk] ";
///  - additionally records errors and warnings raised on the current thread while a
///    MessageCapture is alive, so render calls can return them in their *error string.
/// No VTK types here.

#include <cstddef>
#include <string>

namespace ff::render {

/// Installs the filtering output window once per process (idempotent, thread safe). Also
/// silences vtkLogger's own stderr copy so each message is printed once, by the window.
void install_vtk_message_filter();

/// Number of "GLEW could not be initialized" messages dropped so far in this process.
std::size_t suppressed_glew_messages();

/// While alive, VTK errors and warnings raised on this thread are appended to text().
class MessageCapture {
 public:
  MessageCapture();
  ~MessageCapture();
  MessageCapture(const MessageCapture&) = delete;
  MessageCapture& operator=(const MessageCapture&) = delete;
  const std::string& text() const { return text_; }
  bool empty() const { return text_.empty(); }

 private:
  std::string text_;
  std::string* previous_;
};

}  // namespace ff::render
