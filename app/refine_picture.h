#pragma once
/// \file refine_picture.h
/// plots/error_indicator.png: the run's last state coloured by the recovered-stress error
/// indicator (core/shell/error_indicator.md (Z9)), the picture of where a finer mesh pays.

#include <string>

#include "core/frame/frame.h"
#include "core/scene/output_settings.h"
#include "render/graphics_context.h"

namespace ff::app {

/// Draws `frame` (whose fields hold the indicator at `info`'s error_indicator index) to png_path in
/// the scene's size and view, coloured from 0 to the largest value. False with *error on failure.
bool draw_refine_picture(render::GraphicsContext& gc, const RunInfo& info, const scene::OutputSettings& out,
                         const std::string& scene_name, const Frame& frame, const std::string& png_path,
                         std::string* error);

}  // namespace ff::app
