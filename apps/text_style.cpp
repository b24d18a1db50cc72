// The text of suffuse plot's figures (see text_style.hpp).
#include "text_style.hpp"

#include <vtkTextProperty.h>

#include <filesystem>
#include <system_error>

namespace suffuse::plot {

namespace fs = std::filesystem;

void style_text(vtkTextProperty* t, int size, bool bold) {
  static const fs::path dejavu = "/usr/share/fonts/truetype/dejavu";
  const fs::path font = dejavu / (bold ? "DejaVuSans-Bold.ttf" : "DejaVuSans.ttf");
  std::error_code ec;
  if (fs::is_regular_file(font, ec)) {
    t->SetFontFamily(VTK_FONT_FILE);
    t->SetFontFile(font.c_str());
  } else {
    t->SetFontFamilyToArial();
    t->SetBold(bold);
  }
  t->SetFontSize(size);
  t->SetColor(0, 0, 0);
}

}  // namespace suffuse::plot
