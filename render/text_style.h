#pragma once
/// \file text_style.h
/// Internal to render/ (exposes VTK): one text look for frames and plots. Uses DejaVu Sans
/// when installed (it has λ, ×, ° and the rest of the symbols engineers write), else VTK's
/// built-in Arial.

class vtkTextProperty;

namespace ff::render {

/// Font size in pixels, RGB colour in [0, 1], bold or regular; no shadow, opaque.
void set_text_style(vtkTextProperty* p, double size_px, const double rgb[3], bool bold);

}  // namespace ff::render
