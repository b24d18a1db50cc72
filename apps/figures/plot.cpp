// suffuse plot: line charts of CSV columns to PNG, without a display.
//
// The CSV files are read by csv_table.hpp; the chart is drawn with VTK's
// charts into the offscreen render window of offscreen_render_window.hpp
// (an EGL context, as Debian's VTK can open only X windows).
#include "plot.hpp"

#include <vtkAxis.h>
#include <vtkChartLegend.h>
#include <vtkChartXY.h>
#include <vtkContextScene.h>
#include <vtkContextView.h>
#include <vtkDoubleArray.h>
#include <vtkGenericOpenGLRenderWindow.h>
#include <vtkNew.h>
#include <vtkPen.h>
#include <vtkPlot.h>
#include <vtkRenderer.h>
#include <vtkTable.h>
#include <vtkTextProperty.h>
#include <vtkTextRenderer.h>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <limits>
#include <map>
#include <set>
#include <sstream>
#include <suffuse/error.hpp>
#include <utility>

#include "csv_table.hpp"
#include "chart_output.hpp"
#include "format_number.hpp"
#include "offscreen_render_window.hpp"

namespace suffuse::plot {

namespace fs = std::filesystem;
using render::style_axis;
using render::style_text;

namespace {

// ---------------------------------------------------------------- series

// File stems for the legend. With several files, the leading and trailing
// parts that all stems share are dropped, cut at a '.', '-' or ' ' that is not
// a decimal point (so scene.eta_0.element and scene.eta_0.3.element give eta_0
// and eta_0.3), unless a stem would be left empty.
std::vector<std::string> legend_names(const std::vector<fs::path>& files, bool full) {
  std::vector<std::string> stems;
  for (const auto& f : files) stems.push_back(f.stem().string());
  if (std::set<std::string>(stems.begin(), stems.end()).size() != stems.size()) {
    // Same stem in different directories: the paths tell them apart.
    stems.clear();
    for (const auto& f : files) stems.push_back((f.parent_path() / f.stem()).string());
    return stems;
  }
  if (full || stems.size() < 2) return stems;
  auto digit = [](const std::string& s, std::size_t i) {
    return i < s.size() && std::isdigit(static_cast<unsigned char>(s[i]));
  };
  // Whether position I of S separates words.
  auto is_cut = [&](const std::string& s, std::size_t i) {
    const char c = s[i];
    if (c == '-' || c == ' ') return true;
    return c == '.' && !(i > 0 && digit(s, i - 1) && digit(s, i + 1));
  };
  // The longest common prefix that ends with a cut in every stem.
  std::size_t prefix = 0;
  for (std::size_t i = 0;; ++i) {
    bool same = true, cut = true;
    for (const auto& s : stems) {
      same = same && i < s.size() && s[i] == stems[0][i];
      cut = cut && same && is_cut(s, i);
    }
    if (!same) break;
    if (cut) prefix = i + 1;
  }
  // The longest common suffix that starts with a cut in every stem.
  std::size_t suffix = 0;
  for (std::size_t i = 0;; ++i) {
    bool same = true, cut = true;
    for (const auto& s : stems) {
      same = same && i < s.size() && s[s.size() - 1 - i] == stems[0][stems[0].size() - 1 - i];
      cut = cut && same && is_cut(s, s.size() - 1 - i);
    }
    if (!same) break;
    if (cut) suffix = i + 1;
  }
  auto strip = [&](std::size_t p, std::size_t q) {
    std::vector<std::string> out;
    for (const auto& s : stems) {
      if (p + q >= s.size()) return std::vector<std::string>();
      out.push_back(s.substr(p, s.size() - p - q));
    }
    return out;
  };
  for (auto [p, q] : {std::pair{prefix, suffix}, std::pair{prefix, std::size_t{0}}, std::pair{std::size_t{0}, suffix}}) {
    auto out = strip(p, q);
    if (!out.empty()) return out;
  }
  return stems;
}

std::string scaled_label(const std::string& header, double scale) {
  return scale == 1 ? header : header + " (x" + format_number(scale) + ")";
}

// The corner of the plot area crossed by the fewest lines.
LegendCorner choose_corner(const std::vector<Series>& series) {
  double x0 = std::numeric_limits<double>::max(), x1 = -x0, y0 = x0, y1 = -x0;
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i)
      x0 = std::min(x0, s.x[i]), x1 = std::max(x1, s.x[i]), y0 = std::min(y0, s.y[i]), y1 = std::max(y1, s.y[i]);
  const double dx = x1 > x0 ? x1 - x0 : 1, dy = y1 > y0 ? y1 - y0 : 1;
  // The legend box as a fraction of the plot area: a column of entries.
  const double w = 0.4, h = std::min(0.7, 0.07 * static_cast<double>(series.size()) + 0.06);
  std::array<std::size_t, 4> count{};  // top-right, top-left, bottom-right, bottom-left
  auto add = [&](double x, double y) {
    const double u = (x - x0) / dx, v = (y - y0) / dy;
    if (v >= 1 - h && u >= 1 - w) ++count[0];
    if (v >= 1 - h && u <= w) ++count[1];
    if (v <= h && u >= 1 - w) ++count[2];
    if (v <= h && u <= w) ++count[3];
  };
  for (const auto& s : series)
    for (std::size_t i = 0; i < s.x.size(); ++i) {
      add(s.x[i], s.y[i]);
      if (i + 1 < s.x.size())  // points along each segment, so sparse data counts too
        for (int k = 1; k < 8; ++k)
          add(s.x[i] + (s.x[i + 1] - s.x[i]) * k / 8, s.y[i] + (s.y[i + 1] - s.y[i]) * k / 8);
    }
  const std::array<LegendCorner, 4> corners{LegendCorner::top_right, LegendCorner::top_left,
                                            LegendCorner::bottom_right, LegendCorner::bottom_left};
  return corners[std::min_element(count.begin(), count.end()) - count.begin()];
}

// Colours that stay apart on white (Tableau 10); after ten lines the dash changes.
constexpr std::array<std::array<unsigned char, 3>, 10> palette{{{31, 119, 180},
                                                                 {255, 127, 14},
                                                                 {44, 160, 44},
                                                                 {214, 39, 40},
                                                                 {148, 103, 189},
                                                                 {140, 86, 75},
                                                                 {227, 119, 194},
                                                                 {127, 127, 127},
                                                                 {188, 189, 34},
                                                                 {23, 190, 207}}};
constexpr std::array<int, 4> dashes{vtkPen::SOLID_LINE, vtkPen::DASH_LINE, vtkPen::DOT_LINE, vtkPen::DASH_DOT_LINE};

// Shrinks the font of T until TEXT is at most LENGTH pixels long (down to 10
// points); whether it changed.
bool fit_text(vtkTextProperty* t, const std::string& text, double length, int dpi) {
  vtkTextRenderer* renderer = vtkTextRenderer::GetInstance();
  if (!renderer || text.empty()) return false;
  vtkNew<vtkTextProperty> flat;
  flat->ShallowCopy(t);
  flat->SetOrientation(0);
  const int size = t->GetFontSize();
  int fit = size;
  for (; fit > 10; --fit) {
    flat->SetFontSize(fit);
    int box[4];
    if (!renderer->GetBoundingBox(flat, text, box, dpi)) return false;
    if (box[1] - box[0] <= length) break;
  }
  t->SetFontSize(fit);
  return fit != size;
}

// Draws the series and writes the PNG to FILE.
void render(const std::vector<Series>& series, const PlotOptions& o, const std::string& xlabel,
            const std::string& ylabel, const fs::path& file) {
  render::VtkMessages messages;
  render::OffscreenRenderWindow offscreen(o.width, o.height);
  vtkGenericOpenGLRenderWindow* window = offscreen.window();
  messages.check("cannot initialise OpenGL");

  {
    vtkNew<vtkContextView> view;
    render::draw_charts_into(view, window);
    const vtkRectf plot_area(10, 10, static_cast<float>(o.width - 35), static_cast<float>(o.height - 25));
    vtkChartXY* chart = render::add_chart(view, plot_area);
    if (!o.title.empty()) {
      chart->SetTitle(o.title);
      style_text(chart->GetTitleProperties(), 20, true);
    }
    const std::pair<int, const std::string*> axes[] = {{vtkAxis::BOTTOM, &xlabel}, {vtkAxis::LEFT, &ylabel}};
    for (const auto& [which, label] : axes) style_axis(chart->GetAxis(which), *label, 18, 15);
    // Axis ranges a little wider than the data, so that lines along an end of
    // the range stay whole; a flat line gets +-10 % of its value.
    for (const int which : {vtkAxis::BOTTOM, vtkAxis::LEFT}) {
      double lo = std::numeric_limits<double>::max(), hi = -lo;
      for (const auto& s : series)
        for (double v : which == vtkAxis::BOTTOM ? s.x : s.y) lo = std::min(lo, v), hi = std::max(hi, v);
      const double span = hi - lo;
      const double pad = span > 1e-12 * std::max(std::abs(lo), std::abs(hi)) ? 0.02 * span
                         : lo == 0                                            ? 1
                                                                              : 0.1 * std::abs(lo);
      chart->GetAxis(which)->SetBehavior(vtkAxis::FIXED);
      chart->GetAxis(which)->SetRange(lo - pad, hi + pad);
    }

    for (std::size_t i = 0; i < series.size(); ++i) {
      const Series& s = series[i];
      vtkNew<vtkDoubleArray> x, y;
      x->SetName(xlabel.c_str());
      y->SetName(s.label.c_str());
      x->SetNumberOfValues(static_cast<vtkIdType>(s.x.size()));
      y->SetNumberOfValues(static_cast<vtkIdType>(s.y.size()));
      for (std::size_t k = 0; k < s.x.size(); ++k) {
        x->SetValue(static_cast<vtkIdType>(k), s.x[k]);
        y->SetValue(static_cast<vtkIdType>(k), s.y[k]);
      }
      vtkNew<vtkTable> table;  // the plot keeps a reference
      table->AddColumn(x);
      table->AddColumn(y);
      vtkPlot* line = chart->AddPlot(vtkChart::LINE);
      line->SetInputData(table, 0, 1);
      line->SetLabel(s.label);
      const auto& c = palette[i % palette.size()];
      line->SetColor(c[0], c[1], c[2], 255);
      line->SetWidth(2.5);
      line->GetPen()->SetLineType(dashes[(i / palette.size()) % dashes.size()]);
    }

    chart->SetShowLegend(true);
    vtkChartLegend* legend = chart->GetLegend();
    style_text(legend->GetLabelProperties(), 15, false);
    legend->SetSymbolWidth(30);
    const LegendCorner corner = o.legend == LegendCorner::automatic ? choose_corner(series) : o.legend;
    const bool left = corner == LegendCorner::top_left || corner == LegendCorner::bottom_left;
    const bool bottom = corner == LegendCorner::bottom_left || corner == LegendCorner::bottom_right;
    legend->SetHorizontalAlignment(left ? vtkChartLegend::LEFT : vtkChartLegend::RIGHT);
    legend->SetVerticalAlignment(bottom ? vtkChartLegend::BOTTOM : vtkChartLegend::TOP);

    window->Render();
    messages.check("cannot draw the chart");
    // Titles longer than the plot area get a smaller font (the layout follows).
    const int* p1 = chart->GetPoint1();
    const int* p2 = chart->GetPoint2();
    const int dpi = window->GetDPI();
    bool refit = fit_text(chart->GetAxis(vtkAxis::BOTTOM)->GetTitleProperties(), xlabel, p2[0] - p1[0], dpi);
    refit = fit_text(chart->GetAxis(vtkAxis::LEFT)->GetTitleProperties(), ylabel, p2[1] - p1[1] + 20, dpi) || refit;
    refit = fit_text(chart->GetTitleProperties(), o.title, o.width - 20, dpi) || refit;
    if (refit) {
      window->Render();
      messages.check("cannot draw the chart");
    }
    // VTK puts the legend right into the corner, on the axis lines: move it
    // inwards a little and draw again.
    const float inset = 8;
    vtkVector2f at = legend->GetPointVector();
    at.SetX(at.GetX() + (left ? inset : -inset));
    at.SetY(at.GetY() + (bottom ? inset : -inset));
    legend->SetHorizontalAlignment(vtkChartLegend::CUSTOM);
    legend->SetVerticalAlignment(vtkChartLegend::CUSTOM);
    legend->SetPoint(at);
    window->Render();
    messages.check("cannot draw the chart");

    render::write_png(window, o.width, o.height, file, messages);
  }
  messages.report_warnings();
}

}  // namespace

LegendCorner parse_legend_corner(const std::string& name) {
  static const std::map<std::string, LegendCorner> corners{{"auto", LegendCorner::automatic},
                                                           {"top-left", LegendCorner::top_left},
                                                           {"top-right", LegendCorner::top_right},
                                                           {"bottom-left", LegendCorner::bottom_left},
                                                           {"bottom-right", LegendCorner::bottom_right}};
  const auto it = corners.find(name);
  if (it == corners.end())
    throw Error("--legend " + name + ": expected auto, top-left, top-right, bottom-left or bottom-right");
  return it->second;
}

void write_plot(const PlotOptions& o) {
  if (o.png.empty()) throw Error("suffuse plot needs --png OUT.png");
  if (o.x.empty()) throw Error("suffuse plot needs --x COLUMN");
  if (o.y.empty()) throw Error("suffuse plot needs at least one --y COLUMN");
  if (o.files.empty()) throw Error("suffuse plot needs at least one CSV file");
  render::check_image_size(o.width, o.height);
  if (!std::isfinite(o.scale_x) || !std::isfinite(o.scale_y) || o.scale_x == 0 || o.scale_y == 0)
    throw Error("--scale-x and --scale-y must be finite and not zero");
  render::check_writable(o.png);

  // Read and check everything before drawing anything.
  const std::vector<std::string> names = legend_names(o.files, o.full_names);
  std::vector<Series> series;
  std::string x_header;
  std::vector<std::string> y_headers;
  for (std::size_t f = 0; f < o.files.size(); ++f) {
    const CsvFile csv = read_csv(o.files[f]);
    const std::size_t xc = find_column(csv, o.x);
    if (f == 0) x_header = csv.header[xc];
    for (std::size_t j = 0; j < o.y.size(); ++j) {
      const std::size_t yc = find_column(csv, o.y[j]);
      if (f == 0) y_headers.push_back(csv.header[yc]);
      Series s;
      s.label = o.files.size() == 1 ? o.y[j] : o.y.size() == 1 ? names[f] : names[f] + ": " + o.y[j];
      for (std::size_t r = 0; r < csv.rows.size(); ++r) {
        const double x = parse_cell(csv, r, xc) * o.scale_x, y = parse_cell(csv, r, yc) * o.scale_y;
        if (std::isfinite(x) && std::isfinite(y)) s.x.push_back(x), s.y.push_back(y);  // nan, inf: skipped
      }
      if (s.x.empty())
        throw Error(csv.path.string() + ": no row has finite values of both '" + csv.header[xc] + "' and '" +
                    csv.header[yc] + "'");
      series.push_back(std::move(s));
    }
  }
  const std::string xlabel = o.xlabel.empty() ? scaled_label(x_header, o.scale_x) : o.xlabel;
  std::string ylabel = o.ylabel;
  if (ylabel.empty()) {
    for (const auto& h : y_headers) ylabel += (ylabel.empty() ? "" : ", ") + h;
    ylabel = scaled_label(ylabel, o.scale_y);
  }

  write_line_chart(series, o, xlabel, ylabel);
}

void write_line_chart(const std::vector<Series>& series, const PlotOptions& o, const std::string& xlabel,
                      const std::string& ylabel) {
  render::check_image_size(o.width, o.height);
  render::check_writable(o.png);
  render::write_atomically(o.png, [&](const fs::path& part) { render(series, o, xlabel, ylabel, part); });
}

}  // namespace suffuse::plot
