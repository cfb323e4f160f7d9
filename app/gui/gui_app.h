#pragma once
/// \file gui_app.h
/// `flexframe gui [SCENE]`: a GLFW window with Dear ImGui panels around a VTK viewport. The
/// solver runs on a SimWorker thread; the window only sends commands and shows copies.

#include <atomic>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "core/model/simulation.h"

namespace ff::app::gui {

struct GuiOptions {
  std::string scene_path;               ///< resolved scene file
  std::string new_problem;              ///< --new static|dynamic: start from a new problem instead
  std::vector<std::string> overrides;   ///< --set key=value
  std::string actions_file;             ///< --actions FILE ("" = none)
  std::string screenshot;               ///< --screenshot FILE: the window, written just before quitting
  double quit_after = 0.0;              ///< --quit-after SECONDS (0 = stay open)
  bool run = false;                     ///< --run: start the solver at once
  int width = 1360, height = 860;       ///< window size
};

/// Exit code of `flexframe gui` when no display can be opened.
constexpr int kNoDisplayExitCode = 2;

/// Runs the GUI until the window closes, `quit`, --quit-after or `stop` (Ctrl-C). Returns the exit
/// code: 0, or 2 for bad input (scene, --set, actions file; a refused action) and for no display.
int run_gui(const GuiOptions& options, const std::atomic<bool>& stop);

}  // namespace ff::app::gui
