#include "render/text_style.h"

#include <vtkTextProperty.h>

#include <cmath>
#include <filesystem>
#include <string>

namespace ff::render {
namespace {

// font files looked for, regular then bold; Debian's fonts-dejavu-core puts them here
const std::string& font_file(bool bold) {
  static const std::string regular = [] {
    const char* path = "/usr/share/fonts/truetype/dejavu/DejaVuSans.ttf";
    return std::filesystem::exists(path) ? std::string(path) : std::string();
  }();
  static const std::string heavy = [] {
    const char* path = "/usr/share/fonts/truetype/dejavu/DejaVuSans-Bold.ttf";
    return std::filesystem::exists(path) ? std::string(path) : std::string();
  }();
  return bold && !heavy.empty() ? heavy : regular;
}

}  // namespace

void set_text_style(vtkTextProperty* p, double size_px, const double rgb[3], bool bold) {
  const std::string& file = font_file(bold);
  if (!file.empty()) {
    p->SetFontFamily(VTK_FONT_FILE);
    p->SetFontFile(file.c_str());
    p->SetBold(false);  // the file already is the bold face
  } else {
    p->SetFontFamilyToArial();
    p->SetBold(bold);
  }
  p->SetFontSize(static_cast<int>(std::lround(size_px)));
  p->SetColor(rgb[0], rgb[1], rgb[2]);
  p->SetOpacity(1.0);
  p->SetShadow(false);
  p->SetItalic(false);
}

}  // namespace ff::render
