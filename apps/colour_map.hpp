// Colour maps of a field over a 2D body: each material point a filled box of
// its size, coloured by the field with a perceptual scale (viridis), a colour
// bar titled with the field and its unit, and the time over each panel.
#pragma once

#include <vtkImageData.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <array>
#include <memory>
#include <string>
#include <vector>

#include "offscreen_render_window.hpp"
#include "point_field.hpp"

namespace suffuse::plot {

// The colour of the fraction F (0 to 1, clamped) of viridis, the perceptual
// colour map of matplotlib (its nine-step version, interpolated in RGB),
// as red, green, blue from 0 to 1.
std::array<double, 3> viridis(double f);

// Where panels go in a colour-map image: one panel per time, in a row for a
// body taller than wide, else in a column, and the colour bar on the right.
struct MapLayout {
  int width = 0, height = 0;     // of the image [px]
  int panels = 1;
  bool in_row = true;
  std::array<double, 4> body{};  // x min, x max, y min, y max [m]: what each panel shows
  // The pixel (from the bottom-left corner of the image) where the point
  // (X, Y) of the body is drawn in panel PANEL (from 0).
  std::array<double, 2> pixel(int panel, double x, double y) const;
  // The panel's part of the image: x0, y0, x1, y1 as fractions.
  std::array<double, 4> viewport(int panel) const;
  // Metres per pixel.
  double scale() const;
};

// The layout of PANELS panels of BODY (x min, x max, y min, y max) in an
// image of WIDTH x HEIGHT pixels; 0 for either: sized from the body's shape.
// Throws suffuse::Error when the body has no extent.
MapLayout map_layout(const std::array<double, 4>& body, int panels, int width, int height);

// The extent of the boxes of POINTS (x min, x max, y min, y max).
std::array<double, 4> body_bounds(vtkPolyData* points);

struct MapPanel {
  vtkPolyData* points = nullptr;
  PointField field;  // one value per point
  double time = 0;
};

// An offscreen window of a layout's size that draws colour maps, one after
// another (an animation's frames share its OpenGL context and shaders).
class ColourMapCanvas {
 public:
  explicit ColourMapCanvas(const MapLayout& layout);  // throws suffuse::Error without OpenGL
  ~ColourMapCanvas();
  ColourMapCanvas(const ColourMapCanvas&) = delete;
  ColourMapCanvas& operator=(const ColourMapCanvas&) = delete;

  // Draws PANELS, the colour scale spanning RANGE (values outside take its
  // end colours), and returns the image. Throws suffuse::Error when the run
  // is not 2D or the drawing fails.
  vtkSmartPointer<vtkImageData> draw(const std::vector<MapPanel>& panels, const std::array<double, 2>& range);

 private:
  MapLayout layout_;
  std::unique_ptr<render::VtkMessages> messages_;        // first: sees the window's errors too
  std::unique_ptr<render::OffscreenRenderWindow> window_;
};

}  // namespace suffuse::plot
