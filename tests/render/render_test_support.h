#pragma once
// Shared by the render tests: a synthetic hub-beam run (what the first users draw), PNG
// read-back through VTK, and world-to-pixel mapping for the parallel cameras FrameRenderer uses.

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkUnsignedCharArray.h>
#include <vtkPointData.h>

#include <array>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <numbers>
#include <string>
#include <vector>

#include "core/frame/frame.h"
#include "render/frame_renderer.h"

namespace ff::render::test {

constexpr double kHubRadius = 0.05;  // m
constexpr double kBeamLength = 1.8;  // m
constexpr int kHubRim = 24;          // rim points of the hub disc
constexpr int kBeamPoints = 60;      // points along the beam

inline std::string out_dir() {
  const std::string dir = std::string(FF_BINARY_DIR) + "/test_out/render";
  std::filesystem::create_directories(dir);
  return dir;
}

/// Hub disc (centre + rim, triangle fan, z = 0) and a beam polyline from the hub rim along +x.
/// Fields: "axial_strain" (1e-3 at the root falling linearly to 0 at the tip) and "zero".
inline RunInfo hub_beam_run() {
  RunInfo info;
  info.scene_name = std::string("synthetic_hub_beam");
  info.time_unit = std::string("s");
  auto& p = info.mesh.reference_points;
  p.insert(p.end(), {0, 0, 0});
  for (int k = 0; k < kHubRim; ++k) {
    const double a = 2 * std::numbers::pi * k / kHubRim;
    p.insert(p.end(), {kHubRadius * std::cos(a), kHubRadius * std::sin(a), 0});
  }
  for (int k = 0; k < kHubRim; ++k)
    info.mesh.triangles.insert(info.mesh.triangles.end(), {0, 1 + k, 1 + (k + 1) % kHubRim});
  const int first = 1 + kHubRim;
  for (int i = 0; i < kBeamPoints; ++i)
    p.insert(p.end(), {kHubRadius + kBeamLength * i / (kBeamPoints - 1), 0, 0});
  for (int i = 0; i + 1 < kBeamPoints; ++i)
    info.mesh.lines.insert(info.mesh.lines.end(), {first + i, first + i + 1});
  info.fields = {{"axial_strain", "-", "axial strain"}, {"zero", "", "zero"}};
  return info;
}

/// The hub-beam rotated by angle_rad about +z, the beam bent by tip_deflection (m, in the
/// rotating frame, quadratic along the beam). base_points = the rigidly rotated reference.
inline Frame hub_beam_frame(const RunInfo& info, double angle_rad, double tip_deflection,
                            double time, double load_factor = 0.0) {
  Frame f;
  f.time = time;
  f.load_factor = load_factor;
  const auto& ref = info.mesh.reference_points;
  const std::size_t n = info.mesh.point_count();
  const double c = std::cos(angle_rad), s = std::sin(angle_rad);
  f.points.resize(3 * n);
  f.base_points.resize(3 * n);
  std::vector<double> strain(n, 0.0), zero(n, 0.0);
  for (std::size_t i = 0; i < n; ++i) {
    const double x = ref[3 * i], y = ref[3 * i + 1], z = ref[3 * i + 2];
    double v = 0;
    if (i >= static_cast<std::size_t>(1 + kHubRim)) {
      const double xi = (x - kHubRadius) / kBeamLength;
      v = tip_deflection * xi * xi;
      strain[i] = 1e-3 * (1.0 - xi);
    }
    f.base_points[3 * i] = c * x - s * y;
    f.base_points[3 * i + 1] = s * x + c * y;
    f.base_points[3 * i + 2] = z;
    f.points[3 * i] = c * x - s * (y + v);
    f.points[3 * i + 1] = s * x + c * (y + v);
    f.points[3 * i + 2] = z;
  }
  f.fields = {strain, zero};
  return f;
}

struct Image {
  int width = 0, height = 0;
  std::vector<std::array<std::uint8_t, 3>> rgb;  // row 0 = top of the picture
  const std::array<std::uint8_t, 3>& at(int col, int row_from_top) const {
    return rgb[static_cast<std::size_t>(row_from_top) * width + col];
  }
};

inline Image read_png(const std::string& path) {
  Image img;
  vtkNew<vtkPNGReader> reader;
  if (!reader->CanReadFile(path.c_str())) return img;
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3];
  data->GetDimensions(dims);
  auto* scalars = vtkUnsignedCharArray::SafeDownCast(data->GetPointData()->GetScalars());
  if (scalars == nullptr) return img;
  const int comps = scalars->GetNumberOfComponents();
  img.width = dims[0];
  img.height = dims[1];
  img.rgb.resize(static_cast<std::size_t>(dims[0]) * dims[1]);
  // VTK images start at the bottom row
  for (int r = 0; r < dims[1]; ++r)
    for (int c = 0; c < dims[0]; ++c)
      for (int k = 0; k < 3; ++k)
        img.rgb[static_cast<std::size_t>(dims[1] - 1 - r) * dims[0] + c][k] =
            scalars->GetValue((static_cast<vtkIdType>(r) * dims[0] + c) * comps + std::min(k, comps - 1));
  return img;
}

inline std::string file_bytes(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

/// Pixel (column, row from top) of world point (x, y) for a parallel camera looking down -z
/// with +y up, as fitted for planar x-y meshes.
inline std::array<int, 2> to_pixel(const Camera& cam, int width, int height, double x, double y) {
  const double px_per_m = 0.5 * height / cam.parallel_scale;
  const double col = 0.5 * width + (x - cam.focal_point[0]) * px_per_m;
  const double row = 0.5 * height - (y - cam.focal_point[1]) * px_per_m;
  return {static_cast<int>(std::floor(col)), static_cast<int>(std::floor(row))};
}

inline bool is_background(const std::array<std::uint8_t, 3>& p) {
  return p[0] == 255 && p[1] == 255 && p[2] == 255;
}

/// Clearly drawn: some channel well below the white background.
inline bool is_ink(const std::array<std::uint8_t, 3>& p) {
  return p[0] < 215 || p[1] < 215 || p[2] < 215;
}

/// Any pixel of the (2r+1)^2 block around (col, row) satisfies pred.
template <class Pred>
bool any_near(const Image& img, int col, int row, int r, Pred pred) {
  for (int dr = -r; dr <= r; ++dr)
    for (int dc = -r; dc <= r; ++dc) {
      const int c = col + dc, w = row + dr;
      if (c >= 0 && w >= 0 && c < img.width && w < img.height && pred(img.at(c, w))) return true;
    }
  return false;
}

}  // namespace ff::render::test
