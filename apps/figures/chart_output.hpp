// What every figure suffuse draws shares: its fonts, and the PNG read back
// from the offscreen window (offscreen_render_window.hpp).
#pragma once

#include <vtkImageData.h>
#include <vtkSmartPointer.h>

#include <filesystem>
#include <functional>
#include <string>

#include "offscreen_render_window.hpp"

class vtkAxis;
class vtkChartXY;
class vtkContextView;
class vtkRectf;
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
// VIEW drawing into WINDOW on a white background, and a chart added to it
// whose plot fills RECT (pixels from the bottom left; a margin around it
// for tick labels at the ends of the axes): every chart figure's set-up.
// The view's scene keeps the chart.
void draw_charts_into(vtkContextView* view, vtkGenericOpenGLRenderWindow* window);
vtkChartXY* add_chart(vtkContextView* view, const vtkRectf& rect);

// An axis as every figure draws it: TITLE in bold at TITLE_SIZE points, tick
// labels at LABEL_SIZE, a black axis line and a light grey grid.
void style_axis(vtkAxis* axis, const std::string& title, int title_size, int label_size);

// Throws suffuse::Error unless WIDTH x HEIGHT is a sane image size (100 to
// 10000 pixels each way: --width and --height).
void check_image_size(int width, int height);

// Throws suffuse::Error unless FILE can be written: its directory exists and
// FILE is not a directory.
void check_writable(const std::filesystem::path& file);

// DRAW writes the image to the path it is given, FILE.part, which is then
// renamed FILE: a reader never sees half a file, and on an error nothing is
// left. Throws suffuse::Error.
void write_atomically(const std::filesystem::path& file, const std::function<void(const std::filesystem::path&)>& draw);

}  // namespace suffuse::render
