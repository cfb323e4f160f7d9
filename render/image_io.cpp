#include "render/image_io.h"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGReader.h>
#include <vtkPointData.h>
#include <vtkUnsignedCharArray.h>

#include <algorithm>
#include <mutex>

#include "render/graphics_context.h"

namespace ff::render {

bool read_png_rgb(const std::string& path, RgbImage* image, std::string* error) {
  std::lock_guard<std::recursive_mutex> lock(vtk_mutex());
  auto fail = [&](const std::string& why) {
    if (error) *error = "'" + path + "': " + why;
    return false;
  };
  vtkNew<vtkPNGReader> reader;
  if (!reader->CanReadFile(path.c_str())) return fail("not a readable PNG file");
  reader->SetFileName(path.c_str());
  reader->Update();
  vtkImageData* data = reader->GetOutput();
  int dims[3] = {0, 0, 0};
  data->GetDimensions(dims);
  auto* scalars = vtkUnsignedCharArray::SafeDownCast(data->GetPointData()->GetScalars());
  if (scalars == nullptr || dims[0] <= 0 || dims[1] <= 0) return fail("no 8-bit image data");
  const int comps = scalars->GetNumberOfComponents();
  image->width = dims[0];
  image->height = dims[1];
  image->rgb.assign(static_cast<std::size_t>(dims[0]) * dims[1] * 3, 0);
  // VTK's rows start at the bottom; grey images repeat their one channel
  const int colour_comps = comps >= 3 ? 3 : 1;
  for (int r = 0; r < dims[1]; ++r) {
    const std::uint8_t* src = scalars->GetPointer(static_cast<vtkIdType>(r) * dims[0] * comps);
    std::uint8_t* dst = &image->rgb[static_cast<std::size_t>(dims[1] - 1 - r) * dims[0] * 3];
    for (int c = 0; c < dims[0]; ++c)
      for (int k = 0; k < 3; ++k) dst[3 * c + k] = src[c * comps + std::min(k, colour_comps - 1)];
  }
  return true;
}

}  // namespace ff::render
