// Images of suffuse plot written as PNG (see png_file.hpp).
#include "png_file.hpp"

#include <vtkNew.h>
#include <vtkPNGWriter.h>
#include <vtkRenderWindow.h>
#include <vtkWindowToImageFilter.h>

#include <string>
#include <suffuse/error.hpp>
#include <system_error>

#include "offscreen_render_window.hpp"

namespace suffuse::plot {

namespace fs = std::filesystem;

void check_output_path(const fs::path& file) {
  const fs::path dir = file.has_parent_path() ? file.parent_path() : fs::path(".");
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) throw Error("cannot write " + file.string() + ": no directory " + dir.string());
  if (fs::is_directory(file, ec)) throw Error("cannot write " + file.string() + ": it is a directory");
}

void check_image_size(int width, int height) {
  constexpr int max_pixels = 10000;
  if (width < 100 || width > max_pixels || height < 100 || height > max_pixels)
    throw Error("--width and --height must be between 100 and " + std::to_string(max_pixels) + " pixels");
}

void write_atomically(const fs::path& file, const std::function<void(const fs::path&)>& write) {
  const fs::path part = file.string() + ".part";
  std::error_code ec;
  try {
    write(part);
    fs::rename(part, file);
  } catch (const std::exception& e) {
    fs::remove(part, ec);
    if (dynamic_cast<const Error*>(&e)) throw;
    throw Error("cannot write " + file.string() + ": " + e.what());
  }
}

vtkSmartPointer<vtkImageData> grab_image(vtkRenderWindow* window, const render::VtkMessages& messages, int width,
                                         int height) {
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

void write_png(vtkImageData* image, const render::VtkMessages& messages, const fs::path& file) {
  vtkNew<vtkPNGWriter> writer;
  writer->SetFileName(file.c_str());
  writer->SetInputData(image);
  writer->Write();
  messages.check("cannot write " + file.string());
  if (writer->GetErrorCode() != 0) throw Error("cannot write " + file.string());
}

}  // namespace suffuse::plot
