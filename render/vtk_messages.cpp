#include "render/vtk_messages.h"

#include <vtkLogger.h>
#include <vtkObjectFactory.h>
#include <vtkOutputWindow.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <mutex>

namespace ff::render {
namespace {

constexpr const char* kGlewMessage = "GLEW could not be initialized";

std::atomic<std::size_t> g_suppressed{0};
thread_local std::string* t_capture = nullptr;

// first meaningful line of a VTK message: drop the "ERROR: In <file>, line <n>" header
std::string message_body(const char* text) {
  std::string s(text ? text : "");
  if (s.rfind("ERROR: In ", 0) == 0 || s.rfind("Warning: In ", 0) == 0 ||
      s.rfind("Generic Warning: In ", 0) == 0) {
    const auto nl = s.find('\n');
    if (nl != std::string::npos) s.erase(0, nl + 1);
  }
  while (!s.empty() && (s.back() == '\n' || s.back() == ' ')) s.pop_back();
  return s;
}

class FilteredOutputWindow : public vtkOutputWindow {
 public:
  static FilteredOutputWindow* New();
  vtkTypeMacro(FilteredOutputWindow, vtkOutputWindow);

  void DisplayText(const char* text) override {
    if (text == nullptr) return;
    if (std::strstr(text, kGlewMessage) != nullptr) {
      ++g_suppressed;
      return;
    }
    const MessageTypes type = this->GetCurrentMessageType();
    if (type == MESSAGE_TYPE_DEBUG) return;
    if (type != MESSAGE_TYPE_TEXT && t_capture != nullptr) {
      if (!t_capture->empty()) t_capture->append("; ");
      t_capture->append(message_body(text));
    }
    // one fprintf per message keeps lines from different threads whole
    std::fprintf(type == MESSAGE_TYPE_TEXT ? stdout : stderr, "[vtk] %s%s", text,
                 text[0] != '\0' && text[std::strlen(text) - 1] == '\n' ? "" : "\n");
  }

 protected:
  FilteredOutputWindow() = default;
  ~FilteredOutputWindow() override = default;
};

vtkStandardNewMacro(FilteredOutputWindow);

}  // namespace

void install_vtk_message_filter() {
  static std::once_flag once;
  std::call_once(once, [] {
    auto* window = FilteredOutputWindow::New();
    vtkOutputWindow::SetInstance(window);
    window->Delete();  // SetInstance holds the reference
    // vtkLogger would print a second, unfiltered copy of every error to stderr
    vtkLogger::SetStderrVerbosity(vtkLogger::VERBOSITY_OFF);
  });
}

std::size_t suppressed_glew_messages() { return g_suppressed.load(); }

MessageCapture::MessageCapture() : previous_(t_capture) { t_capture = &text_; }

MessageCapture::~MessageCapture() { t_capture = previous_; }

}  // namespace ff::render
