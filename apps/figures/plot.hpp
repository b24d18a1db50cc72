// suffuse plot: line charts of CSV columns, drawn with VTK's charts into an
// offscreen OpenGL context and written as PNG; no display needed.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace suffuse::plot {

enum class LegendCorner { automatic, top_left, top_right, bottom_left, bottom_right };

struct PlotOptions {
  std::filesystem::path png;                 // written as png + ".part", then renamed
  std::string x;                             // column of the horizontal axis
  std::vector<std::string> y;                // columns of the vertical axis: one line per file and column
  std::vector<std::filesystem::path> files;  // CSV files, each with a header row
  std::string title;
  std::string xlabel, ylabel;                // empty: the column headers (with their units)
  int width = 900, height = 600;             // image size [px]
  double scale_x = 1, scale_y = 1;           // multiply the values (100: fractions in percent)
  LegendCorner legend = LegendCorner::automatic;
  bool full_names = false;                   // legend with whole file stems, no common part dropped
};

// One line of a chart.
struct Series {
  std::string label;
  std::vector<double> x, y;
};

// The legend corner named NAME (auto, top-left, top-right, bottom-left, bottom-right); throws suffuse::Error.
LegendCorner parse_legend_corner(const std::string& name);

// Reads and checks every file and column first (nothing is written when one is
// wrong), then draws and writes the PNG. Throws suffuse::Error.
void write_plot(const PlotOptions& options);

// Draws SERIES (each with at least one point) as lines into options.png, with
// options' size, title and legend corner (its files and columns are not used).
// Throws suffuse::Error; nothing is left behind on an error.
void write_line_chart(const std::vector<Series>& series, const PlotOptions& options, const std::string& xlabel,
                      const std::string& ylabel);

}  // namespace suffuse::plot
