// Images of suffuse plot: read back from the offscreen window, written as PNG
// under a temporary name and then renamed, so a reader never sees half a file
// and nothing is left behind on an error.
#pragma once

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <filesystem>
#include <functional>

class vtkRenderWindow;

namespace suffuse::render {
class VtkMessages;
}

namespace suffuse::plot {

// Throws suffuse::Error unless FILE can be created: its directory exists and
// FILE is not a directory.
void check_output_path(const std::filesystem::path& file);

// Throws suffuse::Error unless the image size is a sane --width and --height.
void check_image_size(int width, int height);

// Calls WRITE with FILE + ".part", then renames that to FILE. On an error the
// part is removed and the error rethrown (as suffuse::Error).
void write_atomically(const std::filesystem::path& file, const std::function<void(const std::filesystem::path&)>& write);

// The RGB image drawn in WINDOW; throws suffuse::Error when it cannot be read
// back or is not WIDTH x HEIGHT pixels.
vtkSmartPointer<vtkImageData> grab_image(vtkRenderWindow* window, const render::VtkMessages& messages, int width,
                                         int height);

// Writes IMAGE as a PNG to FILE (no rename: see write_atomically).
void write_png(vtkImageData* image, const render::VtkMessages& messages, const std::filesystem::path& file);

}  // namespace suffuse::plot
