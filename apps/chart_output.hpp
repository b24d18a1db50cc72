// What every figure suffuse draws shares: its fonts, and the PNG read back
// from the offscreen window (offscreen_render_window.hpp).
#pragma once

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <filesystem>

#include "offscreen_render_window.hpp"

class vtkTextProperty;

namespace suffuse::render {

// DejaVu Sans when installed (Debian's fonts-dejavu-core), else VTK's built-in
// sans-serif font (whose Debian build draws '[' and ']' as parentheses).
void style_text(vtkTextProperty* t, int size, bool bold);

// Reads the rendered WIDTH x HEIGHT image back and writes it to FILE as PNG.
// Throws suffuse::Error.
void write_png(vtkGenericOpenGLRenderWindow* window, int width, int height, const std::filesystem::path& file,
               const VtkMessages& messages);

// The rendered WIDTH x HEIGHT image (RGB, bottom row first), read back; for
// images kept or written later (the frames of an animation). Throws suffuse::Error.
vtkSmartPointer<vtkImageData> read_image(vtkGenericOpenGLRenderWindow* window, int width, int height,
                                         const VtkMessages& messages);

// Writes IMAGE to FILE as PNG. Throws suffuse::Error.
void write_png(vtkImageData* image, const std::filesystem::path& file, const VtkMessages& messages);

}  // namespace suffuse::render
