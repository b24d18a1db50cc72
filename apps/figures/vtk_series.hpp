// The point series of a finished run: the .pvd collection the writer
// writer/vtk_particles keeps, with one .vtp of material points per frame.
#pragma once

#include <vtkPolyData.h>
#include <vtkSmartPointer.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace suffuse::plot {

struct SeriesFrame {
  double time = 0;             // simulated time [s]
  std::filesystem::path file;  // the .vtp, absolute or relative to the working directory
};

struct PointSeries {
  std::filesystem::path pvd;
  std::vector<SeriesFrame> frames;  // by increasing time, at least one
};

// The point frames listed in PATH: a .pvd file, or a run's output directory
// holding it (its only .pvd, or <directory name>.pvd). Entries of other files
// in the collection (grid .vti/.vtu parts) are skipped; with several point
// parts, the lowest part number is taken. Throws suffuse::Error when there is
// no .pvd, it cannot be parsed, or it lists no .vtp.
PointSeries read_point_series(const std::filesystem::path& path);

// The index of the frame nearest TIME. Throws suffuse::Error, with the range
// of the series, when TIME lies outside it (beyond a round-off tolerance).
std::size_t nearest_frame(const PointSeries& series, double time);

// The material points of one frame. Throws suffuse::Error when the file is
// missing or VTK cannot read it.
vtkSmartPointer<vtkPolyData> read_frame(const SeriesFrame& frame);

// A time for a legend or a title, in seconds, to four significant digits
// (whole seconds from 1000 s on): "t = 12.5 s", "t = 10 s" for 10.0001 s.
std::string time_label(double time);

}  // namespace suffuse::plot
