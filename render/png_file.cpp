#include "render/png_file.h"

#include "core/frame/output_file.h"

#include <png.h>

#include <cerrno>
#include <csetjmp>
#include <cstdio>
#include <cstring>

namespace ff::render {
namespace {

struct PngError {
  char text[256] = {0};
};

// what the failed system call said, in the words a full disk is reported with everywhere
const char* io_reason(int err) { return err == ENOSPC || err == EDQUOT ? "disk full" : "I/O error"; }

void on_png_error(png_structp png, png_const_charp message) {
  auto* e = static_cast<PngError*>(png_get_error_ptr(png));
  const int err = errno;  // set by the failed fwrite behind libpng's "Write Error"
  if (err != 0)
    std::snprintf(e->text, sizeof e->text, "%s: %s (%s)", message, io_reason(err), std::strerror(err));
  else
    std::snprintf(e->text, sizeof e->text, "%s", message);
  std::longjmp(png_jmpbuf(png), 1);
}
void on_png_warning(png_structp, png_const_charp) {}

// Plain C state only between setjmp and longjmp: nothing with a destructor lives in this frame.
bool write(std::FILE* file, const unsigned char* rgb, int width, int height, bool bottom_up, PngError* err) {
  png_structp png = png_create_write_struct(PNG_LIBPNG_VER_STRING, err, on_png_error, on_png_warning);
  if (!png) {
    std::snprintf(err->text, sizeof err->text, "libpng could not start");
    return false;
  }
  png_infop info = png_create_info_struct(png);
  if (!info || setjmp(png_jmpbuf(png))) {
    png_destroy_write_struct(&png, &info);
    if (!err->text[0]) std::snprintf(err->text, sizeof err->text, "libpng could not start");
    return false;
  }
  png_init_io(png, file);
  png_set_compression_level(png, 1);
  png_set_filter(png, PNG_FILTER_TYPE_BASE, PNG_FILTER_SUB);
  png_set_IHDR(png, info, static_cast<png_uint_32>(width), static_cast<png_uint_32>(height), 8, PNG_COLOR_TYPE_RGB,
               PNG_INTERLACE_NONE, PNG_COMPRESSION_TYPE_BASE, PNG_FILTER_TYPE_BASE);
  png_write_info(png, info);
  const std::size_t stride = 3 * static_cast<std::size_t>(width);
  for (int r = 0; r < height; ++r) {
    const int source = bottom_up ? height - 1 - r : r;
    png_write_row(png, rgb + stride * static_cast<std::size_t>(source));
  }
  png_write_end(png, nullptr);
  png_destroy_write_struct(&png, &info);
  return true;
}

}  // namespace

bool write_png_rgb(const std::string& path, const unsigned char* rgb, int width, int height, bool bottom_up,
                   std::string* error) {
  std::string why;
  std::FILE* file = open_output_stream(path, &why);  // never through a planted link
  if (!file) {
    if (error) *error = "could not write PNG '" + path + "': " + why;
    return false;
  }
  PngError err;
  errno = 0;
  const bool ok = write(file, rgb, width, height, bottom_up, &err);
  const bool closed = std::fclose(file) == 0;  // flushes the last buffer: a full disk shows here
  const int close_errno = errno;
  if (!ok || !closed) {
    const std::string close_reason =
        std::string("closing failed: ") + io_reason(close_errno) + " (" + std::strerror(close_errno) + ")";
    if (error) *error = "could not write PNG '" + path + "': " + (ok ? close_reason : std::string(err.text));
    std::remove(path.c_str());
    return false;
  }
  return true;
}

}  // namespace ff::render
