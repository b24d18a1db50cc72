// Colour maps of a field over a 2D body (see colour_map.hpp).
#include "colour_map.hpp"

#include <vtkCamera.h>
#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkCoordinate.h>
#include <vtkDoubleArray.h>
#include <vtkLookupTable.h>
#include <vtkNew.h>
#include <vtkPoints.h>
#include <vtkPolyDataMapper.h>
#include <vtkProperty.h>
#include <vtkRenderer.h>
#include <vtkScalarBarActor.h>
#include <vtkTextActor.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <string>
#include <suffuse/error.hpp>

#include "chart_output.hpp"
#include "format_number.hpp"
#include "offscreen_render_window.hpp"
#include "vtk_series.hpp"

namespace suffuse::plot {

namespace {

// Pixels: the strip of the colour bar, the band for the time over each panel,
// the margin around the body.
constexpr int bar_strip = 190, time_band = 44, margin = 12;

// The boxes of the points in PLANE as quads in its coordinates (at z = 0),
// with the field as cell data, each PAD wider on every side (so that no seam
// shows between boxes that a deformation has moved a little apart).
vtkSmartPointer<vtkPolyData> boxes(vtkPolyData* points, const std::vector<double>& values, double pad,
                                   const MapPlane& plane) {
  const auto sizes = point_sizes(points);
  const auto [u, v] = plane.drawn();
  vtkNew<vtkPoints> corners;
  corners->SetDataTypeToDouble();
  vtkNew<vtkCellArray> quads;
  vtkNew<vtkDoubleArray> scalars;
  for (vtkIdType p = 0; p < points->GetNumberOfPoints(); ++p) {
    double x[3];
    points->GetPoint(p, x);
    const auto& s = sizes[static_cast<std::size_t>(p)];
    if (!plane.holds(x, s)) continue;
    const double hu = 0.5 * s[u] + pad, hv = 0.5 * s[v] + pad;
    const vtkIdType first = corners->InsertNextPoint(x[u] - hu, x[v] - hv, 0);
    corners->InsertNextPoint(x[u] + hu, x[v] - hv, 0);
    corners->InsertNextPoint(x[u] + hu, x[v] + hv, 0);
    corners->InsertNextPoint(x[u] - hu, x[v] + hv, 0);
    const vtkIdType ids[4] = {first, first + 1, first + 2, first + 3};
    quads->InsertNextCell(4, ids);
    scalars->InsertNextValue(values[static_cast<std::size_t>(p)]);
  }
  auto poly = vtkSmartPointer<vtkPolyData>::New();
  poly->SetPoints(corners);
  poly->SetPolys(quads);
  poly->GetCellData()->SetScalars(scalars);
  return poly;
}

vtkSmartPointer<vtkLookupTable> viridis_table(const std::array<double, 2>& range) {
  auto table = vtkSmartPointer<vtkLookupTable>::New();
  constexpr int entries = 256;
  table->SetNumberOfTableValues(entries);
  for (int i = 0; i < entries; ++i) {
    const auto c = viridis(static_cast<double>(i) / (entries - 1));
    table->SetTableValue(i, c[0], c[1], c[2], 1);
  }
  table->SetTableRange(range[0], range[1]);
  table->SetNanColor(0.6, 0.6, 0.6, 1);
  return table;
}

std::string title_of(const std::vector<MapPanel>& panels) {
  return panels.empty() ? std::string() : panels.front().field.label;
}

}  // namespace

std::array<double, 3> viridis(double f) {
  // matplotlib's viridis (public domain) at 0, 1/8, ..., 1.
  static constexpr std::array<std::array<int, 3>, 9> knots{{{68, 1, 84},
                                                           {71, 44, 122},
                                                           {59, 81, 139},
                                                           {44, 113, 142},
                                                           {33, 144, 141},
                                                           {39, 173, 129},
                                                           {92, 200, 99},
                                                           {170, 220, 50},
                                                           {253, 231, 37}}};
  const double u = std::clamp(std::isfinite(f) ? f : 0.0, 0.0, 1.0) * (knots.size() - 1);
  const std::size_t k = std::min(static_cast<std::size_t>(u), knots.size() - 2);
  const double w = u - static_cast<double>(k);
  std::array<double, 3> c{};
  for (int i = 0; i < 3; ++i) c[i] = ((1 - w) * knots[k][i] + w * knots[k + 1][i]) / 255.0;
  return c;
}

std::array<int, 2> MapPlane::drawn() const {
  if (axis == 0) return {1, 2};
  if (axis == 1) return {0, 2};
  return {0, 1};
}

bool MapPlane::holds(const double* x, const std::array<double, 3>& size) const {
  return !slice || std::abs(x[axis] - position) <= 0.55 * size[axis];
}

std::string MapPlane::label() const {
  if (!slice) return "";
  return std::string(1, static_cast<char>('x' + axis)) + " = " + format_number(position) + " m";
}

MapPlane map_plane(vtkPolyData* points, const std::string& slice) {
  const bool planar = is_planar(points);
  if (planar && !slice.empty())
    throw Error("--slice " + slice + ": this run is 2D (its points lie in the plane z = 0); draw it without --slice");
  if (planar) return {};
  double bounds[6];
  points->GetBounds(bounds);
  const std::string extent = "x from " + format_number(bounds[0]) + " to " + format_number(bounds[1]) + ", y from " +
                             format_number(bounds[2]) + " to " + format_number(bounds[3]) + ", z from " +
                             format_number(bounds[4]) + " to " + format_number(bounds[5]) + " m";
  if (slice.empty())
    throw Error("this run is 3D: a colour map shows a slice of it; name one with --slice x=X, y=Y or z=Z (the points "
                "span " + extent + ")");
  MapPlane plane;
  plane.slice = true;
  char* end = nullptr;
  const char* number = slice.c_str() + std::min<std::size_t>(2, slice.size());
  plane.position = std::strtod(number, &end);
  if (slice.size() < 3 || slice[1] != '=' || (slice[0] != 'x' && slice[0] != 'y' && slice[0] != 'z') || *end != '\0' ||
      !std::isfinite(plane.position))
    throw Error("--slice " + slice + ": expected x=X, y=Y or z=Z, a plane across an axis at a position in metres");
  plane.axis = slice[0] - 'x';
  return plane;
}

double MapLayout::scale() const {
  const double pw = in_row ? static_cast<double>(width - bar_strip) / panels : width - bar_strip;
  const double ph = in_row ? height : static_cast<double>(height) / panels;
  return std::max((body[1] - body[0]) / (pw - 2 * margin), (body[3] - body[2]) / (ph - time_band - margin));
}

std::array<double, 4> MapLayout::viewport(int panel) const {
  const double bar = static_cast<double>(bar_strip) / width;
  if (in_row) {
    const double w = (1 - bar) / panels;
    return {panel * w, 0, (panel + 1) * w, 1};
  }
  const double h = 1.0 / panels;
  return {0, 1 - (panel + 1) * h, 1 - bar, 1 - panel * h};
}

std::array<double, 2> MapLayout::pixel(int panel, double x, double y) const {
  const auto v = viewport(panel);
  const double x0 = v[0] * width, y0 = v[1] * height, pw = (v[2] - v[0]) * width, ph = (v[3] - v[1]) * height;
  const double s = scale();
  return {x0 + pw / 2 + (x - 0.5 * (body[0] + body[1])) / s,
          y0 + margin + (ph - time_band - margin) / 2 + (y - 0.5 * (body[2] + body[3])) / s};
}

MapLayout map_layout(const std::array<double, 4>& body, int panels, int width, int height, const MapPlane& plane) {
  const double bw = body[1] - body[0], bh = body[3] - body[2];
  if (!(bw > 0) || !(bh > 0) || !std::isfinite(bw) || !std::isfinite(bh))
    throw Error("the body has no extent to draw (its boxes span " + std::to_string(bw) + " x " + std::to_string(bh) +
                " m)");
  if (width < 0 || height < 0) throw Error("--width and --height must be positive (or 0: from the body's shape)");
  MapLayout layout;
  layout.body = body;
  layout.plane = plane;
  layout.panels = std::max(1, panels);
  layout.in_row = bw <= bh;
  const double aspect = bw / bh;
  if (layout.in_row) {
    layout.height = height > 0 ? height : 800;
    const double body_height = layout.height - time_band - margin;
    const int panel = std::max(150, static_cast<int>(std::ceil(aspect * body_height)) + 2 * margin);
    layout.width = width > 0 ? width : std::min(10000, layout.panels * panel + bar_strip);
  } else {
    layout.width = width > 0 ? width : 1100;
    const double body_width = layout.width - bar_strip - 2 * margin;
    const int panel = std::max(120, static_cast<int>(std::ceil(body_width / aspect)) + time_band + margin);
    layout.height = height > 0 ? height : std::min(10000, layout.panels * panel);
  }
  render::check_image_size(layout.width, layout.height);
  const double pw = layout.in_row ? static_cast<double>(layout.width - bar_strip) / layout.panels
                                  : layout.width - bar_strip;
  const double ph = layout.in_row ? layout.height : static_cast<double>(layout.height) / layout.panels;
  if (pw < 2 * margin + 10 || ph < time_band + margin + 10)
    throw Error("an image of " + std::to_string(layout.width) + " x " + std::to_string(layout.height) +
                " pixels leaves too little room for " + std::to_string(layout.panels) + " panel(s) and the colour bar");
  return layout;
}

std::array<double, 4> body_bounds(vtkPolyData* points, const MapPlane& plane) {
  const auto sizes = point_sizes(points);
  const auto [u, v] = plane.drawn();
  std::array<double, 4> b{INFINITY, -INFINITY, INFINITY, -INFINITY};
  for (vtkIdType p = 0; p < points->GetNumberOfPoints(); ++p) {
    double x[3];
    points->GetPoint(p, x);
    const auto& s = sizes[static_cast<std::size_t>(p)];
    if (!plane.holds(x, s)) continue;
    b[0] = std::min(b[0], x[u] - 0.5 * s[u]), b[1] = std::max(b[1], x[u] + 0.5 * s[u]);
    b[2] = std::min(b[2], x[v] - 0.5 * s[v]), b[3] = std::max(b[3], x[v] + 0.5 * s[v]);
  }
  if (!(b[0] <= b[1])) {
    double bounds[6];
    points->GetBounds(bounds);
    throw Error("no material point's box crosses the plane " + plane.label() + " (the points span " +
                format_number(bounds[2 * plane.axis]) + " to " + format_number(bounds[2 * plane.axis + 1]) + " m)");
  }
  return b;
}

ColourMapCanvas::ColourMapCanvas(const MapLayout& layout)
    : layout_(layout),
      messages_(std::make_unique<render::VtkMessages>()),
      window_(std::make_unique<render::OffscreenRenderWindow>(layout.width, layout.height)) {
  messages_->check("cannot initialise OpenGL");
}

ColourMapCanvas::~ColourMapCanvas() {
  window_.reset();  // before the messages stop being collected
  messages_->report_warnings();
}

vtkSmartPointer<vtkImageData> ColourMapCanvas::draw(const std::vector<MapPanel>& panels,
                                                    const std::array<double, 2>& range) {
  const auto table = viridis_table(range);
  const MapLayout& layout = layout_;
  const render::VtkMessages& messages = *messages_;
  vtkGenericOpenGLRenderWindow* window = window_->window();
  std::vector<vtkSmartPointer<vtkRenderer>> renderers;
  const double s = layout.scale();
  for (std::size_t k = 0; k < panels.size(); ++k) {
    const auto v = layout.viewport(static_cast<int>(k));
    auto renderer = vtkSmartPointer<vtkRenderer>::New();
    renderer->SetViewport(v.data());
    renderer->SetBackground(1, 1, 1);

    vtkNew<vtkPolyDataMapper> mapper;
    mapper->SetInputData(boxes(panels[k].points, panels[k].field.values, 0.5 * s, layout.plane));  // half a pixel
    mapper->SetScalarModeToUseCellData();
    mapper->SetLookupTable(table);
    mapper->SetScalarRange(range[0], range[1]);
    mapper->UseLookupTableScalarRangeOff();
    vtkNew<vtkActor> actor;
    actor->SetMapper(mapper);
    actor->GetProperty()->LightingOff();  // the colours of the scale, unshaded
    renderer->AddActor(actor);

    vtkNew<vtkTextActor> time;
    const std::string where = layout.plane.label();
    time->SetInput((time_label(panels[k].time) + (where.empty() ? "" : ", " + where)).c_str());
    render::style_text(time->GetTextProperty(), 18, true);
    time->GetTextProperty()->SetJustificationToCentered();
    time->GetTextProperty()->SetVerticalJustificationToCentered();
    const double ph = (v[3] - v[1]) * layout.height;
    time->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
    time->GetPositionCoordinate()->SetValue(0.5, 1 - 0.5 * time_band / ph);
    renderer->AddActor2D(time);

    // The body's centre at the middle of the panel below the time band.
    vtkCamera* camera = renderer->GetActiveCamera();
    camera->ParallelProjectionOn();
    const double cx = 0.5 * (layout.body[0] + layout.body[1]);
    const double cy = 0.5 * (layout.body[2] + layout.body[3]) + s * (time_band - margin) / 2;
    camera->SetFocalPoint(cx, cy, 0);
    camera->SetPosition(cx, cy, 1);
    camera->SetViewUp(0, 1, 0);
    camera->SetParallelScale(s * ph / 2);
    camera->SetClippingRange(0.5, 1.5);
    window->AddRenderer(renderer);
    renderers.push_back(renderer);
  }

  auto bar_renderer = vtkSmartPointer<vtkRenderer>::New();
  const double bar = static_cast<double>(bar_strip) / layout.width;
  bar_renderer->SetViewport(1 - bar, 0, 1, 1);
  bar_renderer->SetBackground(1, 1, 1);
  vtkNew<vtkScalarBarActor> scale_bar;
  scale_bar->SetLookupTable(table);
  scale_bar->SetTitle(title_of(panels).c_str());
  scale_bar->SetNumberOfLabels(6);
  scale_bar->SetLabelFormat("%.3g");
  scale_bar->UnconstrainedFontSizeOn();
  render::style_text(scale_bar->GetTitleTextProperty(), 16, true);
  render::style_text(scale_bar->GetLabelTextProperty(), 15, false);
  scale_bar->GetLabelTextProperty()->ShadowOff();
  scale_bar->GetTitleTextProperty()->ShadowOff();
  scale_bar->SetMaximumWidthInPixels(bar_strip - 20);
  scale_bar->GetPositionCoordinate()->SetCoordinateSystemToNormalizedViewport();
  scale_bar->GetPositionCoordinate()->SetValue(0.08, 0.1);
  scale_bar->SetWidth(0.84);
  scale_bar->SetHeight(std::min(0.8, 600.0 / layout.height));
  scale_bar->SetBarRatio(0.25);
  scale_bar->SetVerticalTitleSeparation(12);  // the top label clear of the title
  bar_renderer->AddActor2D(scale_bar);
  window->AddRenderer(bar_renderer);
  renderers.push_back(bar_renderer);

  window->Render();
  messages.check("cannot draw the colour map");
  auto image = render::read_image(window, layout.width, layout.height, messages);
  for (auto& r : renderers) window->RemoveRenderer(r);  // the next drawing starts afresh
  return image;
}

}  // namespace suffuse::plot
