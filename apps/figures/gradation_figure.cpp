// Two charts side by side in one offscreen view, drawn as suffuse plot draws
// its charts (chart_output.hpp, offscreen_render_window.hpp).
#include "gradation_figure.hpp"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>

#include <algorithm>
#include <array>
#include <string>
#include <suffuse/error.hpp>
#include <vector>

#include "chart_output.hpp"

namespace suffuse::gradation_figure {

namespace fs = std::filesystem;

namespace {

constexpr int width = 1400, height = 650;

struct Line {
  std::string label;
  std::vector<std::array<double, 2>> points;
  std::array<unsigned char, 3> colour;
  int dash = vtkPen::SOLID_LINE;
};

void set_axis(vtkChartXY* chart, int which, const std::string& title, double lo, double hi, bool log) {
  vtkAxis* axis = chart->GetAxis(which);
  render::style_axis(axis, title, 17, 14);
  axis->SetBehavior(vtkAxis::FIXED);
  axis->SetRange(lo, hi);
  axis->SetLogScale(log);
}

void add_line(vtkChartXY* chart, const Line& l) {
  vtkNew<vtkDoubleArray> x, y;
  x->SetName("x");
  y->SetName(l.label.c_str());
  for (const auto& [px, py] : l.points) x->InsertNextValue(px), y->InsertNextValue(py);
  vtkNew<vtkTable> table;  // the plot keeps a reference
  table->AddColumn(x);
  table->AddColumn(y);
  vtkPlot* plot = chart->AddPlot(vtkChart::LINE);
  plot->SetInputData(table, 0, 1);
  plot->SetLabel(l.label);
  plot->SetColor(l.colour[0], l.colour[1], l.colour[2], 255);
  plot->SetWidth(2.5);
  plot->GetPen()->SetLineType(l.dash);
}

void finish(vtkChartXY* chart, const std::string& title) {
  chart->SetTitle(title);
  render::style_text(chart->GetTitleProperties(), 18, true);
  chart->SetShowLegend(true);
  render::style_text(chart->GetLegend()->GetLabelProperties(), 13, false);
  chart->GetLegend()->SetSymbolWidth(30);
}

void render_to(const Gradation& g, const InternalStability& s, const fs::path& file) {
  render::VtkMessages messages;
  render::OffscreenRenderWindow offscreen(width, height);
  vtkGenericOpenGLRenderWindow* window = offscreen.window();
  messages.check("cannot initialise OpenGL");
  {
    vtkNew<vtkContextView> view;
    render::draw_charts_into(view, window);

    // The gradation curve: straight between the points on the log-size axis,
    // as it is interpolated.
    vtkChartXY* psd = render::add_chart(view, vtkRectf(10, 10, width / 2.0f - 30, height - 25));
    Line curve{"percent passing", {}, {31, 119, 180}};
    for (std::size_t i = 0; i < g.sizes_mm().size(); ++i)
      curve.points.push_back({g.sizes_mm()[i], 100 * g.passing_points()[i]});
    add_line(psd, curve);
    set_axis(psd, vtkAxis::BOTTOM, "particle size [mm]", g.sizes_mm().front() / 1.5, g.sizes_mm().back() * 1.5, true);
    set_axis(psd, vtkAxis::LEFT, "percent passing [%]", 0, 102, false);
    finish(psd, fs::path(g.source()).filename().string());
    psd->GetLegend()->SetHorizontalAlignment(vtkChartLegend::LEFT);
    psd->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);

    // The shape curve with the boundaries of the criteria drawn on it.
    vtkChartXY* shape = render::add_chart(view, vtkRectf(width / 2.0f + 10, 10, width / 2.0f - 35, height - 25));
    const double f_max = 100 * s.shape_curve_limit, f_end = std::max(50.0, f_max + 10);
    Line h{"shape curve H(F)", {}, {31, 119, 180}};
    double h_top = 1.3 * f_max;
    for (const auto& [f, hh] : shape_curve(g))
      if (100 * f <= f_end) h.points.push_back({100 * f, 100 * hh}), h_top = std::max(h_top, 100 * hh);
    add_line(shape, h);
    add_line(shape, {"Kenney-Lau 1986: H = F", {{0, 0}, {f_max, f_max}, {f_max, 0}}, {214, 39, 40}, vtkPen::DASH_LINE});
    add_line(shape, {"Kenney-Lau 1985: H = 1.3 F", {{0, 0}, {f_max, 1.3 * f_max}, {f_max, 0}}, {255, 127, 14},
                     vtkPen::DOT_LINE});
    add_line(shape, {"Li-Fannin: H = min(F, 15)", {{0, 0}, {15, 15}, {f_max, 15}, {f_max, 0}}, {148, 103, 189},
                     vtkPen::DASH_DOT_LINE});
    add_line(shape, {"Kezdi: H = 15", {{0, 15}, {f_end, 15}}, {44, 160, 44}, vtkPen::DASH_LINE});
    set_axis(shape, vtkAxis::BOTTOM, "F: mass finer than D [%]", 0, f_end, false);
    set_axis(shape, vtkAxis::LEFT, "H: mass between D and 4D [%]", 0, std::min(100.0, h_top * 1.1 + 5), false);
    finish(shape, "shape curve, unstable below the boundaries for F <= " + std::to_string(int(f_max)) + " %");
    shape->GetLegend()->SetHorizontalAlignment(vtkChartLegend::RIGHT);
    shape->GetLegend()->SetVerticalAlignment(vtkChartLegend::TOP);

    window->Render();
    messages.check("cannot draw the charts");
    render::write_png(window, width, height, file, messages);
  }
  messages.report_warnings();
}

}  // namespace

void write_png(const Gradation& g, const InternalStability& s, const fs::path& file) {
  render::check_writable(file);
  render::write_atomically(file, [&](const fs::path& part) { render_to(g, s, part); });
}

}  // namespace suffuse::gradation_figure
