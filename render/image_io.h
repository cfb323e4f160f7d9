#pragma once
/// \file image_io.h
/// PNG images as plain RGB bytes (no VTK types), e.g. to assemble rendered frames into a movie.

#include <cstdint>
#include <string>
#include <vector>

namespace ff::render {

/// An 8-bit RGB image, rows from the top, 3 bytes per pixel (width * height * 3 bytes).
struct RgbImage {
  int width = 0, height = 0;
  std::vector<std::uint8_t> rgb;
};

/// Reads a PNG (grey, grey + alpha, RGB or RGBA; alpha is dropped). Returns false and fills
/// *error (if non-null) when the file is missing or not a readable PNG.
bool read_png_rgb(const std::string& path, RgbImage* image, std::string* error);

}  // namespace ff::render
