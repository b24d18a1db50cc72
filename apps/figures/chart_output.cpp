#include "chart_output.hpp"

#include <vtkAxis.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkRenderer.h>
#include <vtkVector.h>
#include <vtkImageData.h>
#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkPen.h>
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

void style_axis(vtkAxis* axis, const std::string& title, int title_size, int label_size) {
  axis->SetTitle(title);
  style_text(axis->GetTitleProperties(), title_size, true);
  style_text(axis->GetLabelProperties(), label_size, false);
  axis->GetPen()->SetColor(0, 0, 0);
  axis->GetGridPen()->SetColor(225, 225, 225);
}

void check_image_size(int width, int height) {
  constexpr int max_pixels = 10000;
  if (width < 100 || width > max_pixels || height < 100 || height > max_pixels)
    throw Error("--width and --height must be between 100 and " + std::to_string(max_pixels) + " pixels");
}

void check_writable(const fs::path& file) {
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("cannot write " + file.string() + ": no directory " + dir.string());
  if (fs::is_directory(file, ec)) throw Error("cannot write " + file.string() + ": it is a directory");
}

void write_atomically(const fs::path& file, const std::function<void(const fs::path&)>& draw) {
  const fs::path part = file.string() + ".part";
  try {
    draw(part);
    fs::rename(part, file);
  } catch (const std::exception& e) {
    std::error_code ec;
    fs::remove(part, ec);
    if (dynamic_cast<const Error*>(&e)) throw;
    throw Error("cannot write " + file.string() + ": " + e.what());
  }
}

void draw_charts_into(vtkContextView* view, vtkGenericOpenGLRenderWindow* window) {
  view->SetRenderWindow(window);
  view->GetRenderer()->SetBackground(1, 1, 1);
}

vtkChartXY* add_chart(vtkContextView* view, const vtkRectf& rect) {
  vtkNew<vtkChartXY> chart;
  view->GetScene()->AddItem(chart);
  chart->SetLayoutStrategy(vtkChart::FILL_RECT);
  chart->SetSize(rect);
  return chart;
}

}  // namespace suffuse::render
