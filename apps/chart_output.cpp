#include "chart_output.hpp"

#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkTextProperty.h>
#include <vtkWindowToImageFilter.h>

#include <suffuse/error.hpp>
#include <system_error>

namespace suffuse::render {

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

void write_png(vtkGenericOpenGLRenderWindow* window, int width, int height, const fs::path& file,
               const VtkMessages& messages) {
  write_png(read_image(window, width, height, messages), file, messages);
}

vtkSmartPointer<vtkImageData> read_image(vtkGenericOpenGLRenderWindow* window, int width, int height,
                                         const VtkMessages& messages) {
  vtkNew<vtkWindowToImageFilter> grab;
  grab->SetInput(window);
  grab->SetInputBufferTypeToRGB();
  grab->ReadFrontBufferOff();
  grab->ShouldRerenderOff();
  grab->Update();
  messages.check("cannot read the image back");
  vtkSmartPointer<vtkImageData> image = grab->GetOutput();
  int dims[3];
  image->GetDimensions(dims);
  if (dims[0] != width || dims[1] != height)
    throw Error("the image read back is " + std::to_string(dims[0]) + " x " + std::to_string(dims[1]) +
                " pixels, not " + std::to_string(width) + " x " + std::to_string(height));
  return image;
}

void write_png(vtkImageData* image, const fs::path& file, const VtkMessages& messages) {
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputData(image);
  writer->Write();
  messages.check("cannot write " + file.string());
  if (writer->GetErrorCode() != 0) throw Error("cannot write " + file.string());
}

}  // namespace suffuse::render
