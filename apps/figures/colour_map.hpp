// Colour maps of a field over a 2D body, or a slice of a 3D one: each
// material point a filled box of its size, coloured by the field with a
// perceptual scale (viridis), a colour bar titled with the field and its
// unit, and the time over each panel.
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

// The plane a colour map shows: a 2D run's own plane, or a slice of a 3D run
// across an axis; the map's horizontal and vertical axes are the other two,
// in order (a slice across y shows x and z).
struct MapPlane {
  bool slice = false;   // a slice of a 3D run
  int axis = 2;         // across which: 0, 1, 2 for x, y, z
  double position = 0;  // of the slice [m]
  // The axes drawn: horizontal, vertical.
  std::array<int, 2> drawn() const;
  // Whether the box of SIZE at X is drawn: always in 2D; in a slice, when the
  // box, a tenth larger, crosses it.
  bool holds(const double* x, const std::array<double, 3>& size) const;
  // "z = 0.05 m" for a slice, "" in 2D.
  std::string label() const;
};

// The plane of POINTS' map: SLICE is empty for a 2D run, and "x=X", "y=Y" or
// "z=Z" [m] for a 3D one. Throws suffuse::Error when a 3D run has no slice,
// a 2D run has one, or SLICE is not of that form.
MapPlane map_plane(vtkPolyData* points, const std::string& slice);

// Where panels go in a colour-map image: one panel per time, in a row for a
// body taller than wide, else in a column, and the colour bar on the right.
struct MapLayout {
  int width = 0, height = 0;     // of the image [px]
  int panels = 1;
  bool in_row = true;
  std::array<double, 4> body{};  // horizontal min, max, vertical min, max [m]: what each panel shows
  MapPlane plane;                // of the body
  // The pixel (from the bottom-left corner of the image) where the point
  // (X, Y) of the body is drawn in panel PANEL (from 0).
  std::array<double, 2> pixel(int panel, double x, double y) const;
  // The panel's part of the image: x0, y0, x1, y1 as fractions.
  std::array<double, 4> viewport(int panel) const;
  // Metres per pixel.
  double scale() const;
};

// The layout of PANELS panels of BODY (horizontal min, max, vertical min,
// max) in PLANE in an image of WIDTH x HEIGHT pixels; 0 for either: sized
// from the body's shape. Throws suffuse::Error when the body has no extent.
MapLayout map_layout(const std::array<double, 4>& body, int panels, int width, int height, const MapPlane& plane = {});

// The extent of the boxes of POINTS in PLANE (horizontal min, max, vertical
// min, max). Throws suffuse::Error when no box is in the plane.
std::array<double, 4> body_bounds(vtkPolyData* points, const MapPlane& plane = {});

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

  // Draws PANELS in the layout's plane, the colour scale spanning RANGE
  // (values outside take its end colours), and returns the image. Throws
  // suffuse::Error when the drawing fails.
  vtkSmartPointer<vtkImageData> draw(const std::vector<MapPanel>& panels, const std::array<double, 2>& range);

 private:
  MapLayout layout_;
  std::unique_ptr<render::VtkMessages> messages_;        // first: sees the window's errors too
  std::unique_ptr<render::OffscreenRenderWindow> window_;
};

}  // namespace suffuse::plot
