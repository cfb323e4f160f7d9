#pragma once
/// \file png_file.h
/// Writes an RGB image as PNG with libpng, choosing what costs time: zlib level 1 and one fixed
/// row filter (Sub) instead of libpng's per-row trial of all five filters. On rendered frames
/// (flat backgrounds, smooth shading) that trial was a quarter of a frame's time and bought
/// little size (docs/performance.md, "headless frames").

#include <string>

namespace ff::render {

/// rgb: 3 bytes per pixel, `width` × `height`; rows from the bottom up when `bottom_up` (OpenGL
/// read-back order), otherwise from the top. False, with the reason in *error, when the file
/// cannot be written.
bool write_png_rgb(const std::string& path, const unsigned char* rgb, int width, int height, bool bottom_up,
                   std::string* error);

}  // namespace ff::render
