// The point series of a finished run (see vtk_series.hpp).
#include "vtk_series.hpp"

#include <vtkNew.h>
#include <vtkXMLDataElement.h>
#include <vtkXMLDataParser.h>
#include <vtkXMLPolyDataReader.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <iomanip>
#include <map>
#include <sstream>
#include <suffuse/error.hpp>
#include <system_error>

#include "format_number.hpp"
#include "offscreen_render_window.hpp"

namespace suffuse::plot {

namespace fs = std::filesystem;

namespace {

// The .pvd that PATH names, or that the directory PATH holds.
fs::path find_pvd(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error(path.string() + " does not exist (expected a .pvd file or a run's output directory)");
  if (!fs::is_directory(path, ec)) return path;
  std::vector<fs::path> found;
  for (const auto& entry : fs::directory_iterator(path, ec))
    if (entry.path().extension() == ".pvd") found.push_back(entry.path());
  std::sort(found.begin(), found.end());
  if (found.size() == 1) return found[0];
  // Several: the one named after the directory (output/<scene>/<scene>.pvd).
  fs::path name = fs::absolute(path).lexically_normal();
  if (name.filename().empty()) name = name.parent_path();
  for (const auto& f : found)
    if (f.stem() == name.filename()) return f;
  if (found.empty()) throw Error(path.string() + " holds no .pvd file (a run writes <scene>.pvd with writer/vtk_particles)");
  std::string names;
  for (const auto& f : found) names += (names.empty() ? "" : ", ") + f.filename().string();
  throw Error(path.string() + " holds several .pvd files (" + names + "): name one");
}

double parse_time(const std::string& text, const fs::path& pvd) {
  char* end = nullptr;
  const double t = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(t))
    throw Error(pvd.string() + ": timestep '" + text + "' is not a number");
  return t;
}

}  // namespace

PointSeries read_point_series(const fs::path& path) {
  PointSeries series;
  series.pvd = find_pvd(path);
  render::VtkMessages messages;
  vtkNew<vtkXMLDataParser> parser;
  parser->SetFileName(series.pvd.c_str());
  if (!parser->Parse() || !parser->GetRootElement())
    throw Error(series.pvd.string() + " is not a VTK collection (.pvd): it cannot be parsed as XML");
  vtkXMLDataElement* root = parser->GetRootElement();
  const char* type = root->GetAttribute("type");
  vtkXMLDataElement* collection = root->FindNestedElementWithName("Collection");
  if (std::string(root->GetName()) != "VTKFile" || !type || std::string(type) != "Collection" || !collection)
    throw Error(series.pvd.string() + " is not a VTK collection (.pvd): expected <VTKFile type=\"Collection\">");

  // Point frames by part number, then by time.
  std::map<int, std::vector<SeriesFrame>> parts;
  const fs::path dir = series.pvd.parent_path();
  for (int i = 0; i < collection->GetNumberOfNestedElements(); ++i) {
    vtkXMLDataElement* e = collection->GetNestedElement(i);
    const char* file = e->GetAttribute("file");
    if (std::string(e->GetName()) != "DataSet" || !file || fs::path(file).extension() != ".vtp") continue;
    const char* timestep = e->GetAttribute("timestep");
    const char* part = e->GetAttribute("part");
    SeriesFrame frame{parse_time(timestep ? timestep : "0", series.pvd), fs::path(file).is_absolute() ? fs::path(file) : dir / file};
    parts[part ? std::atoi(part) : 0].push_back(frame);
  }
  if (parts.empty()) throw Error(series.pvd.string() + " lists no point data (.vtp files)");
  series.frames = parts.begin()->second;
  std::stable_sort(series.frames.begin(), series.frames.end(),
                   [](const SeriesFrame& a, const SeriesFrame& b) { return a.time < b.time; });
  return series;
}

std::size_t nearest_frame(const PointSeries& series, double time) {
  const double first = series.frames.front().time, last = series.frames.back().time;
  const double tolerance = 1e-9 * std::max({last - first, std::abs(first), std::abs(last)}) + 1e-12;
  if (!std::isfinite(time) || time < first - tolerance || time > last + tolerance)
    throw Error("t = " + format_number(time) + " s is outside the series " + series.pvd.string() + ", which runs from " +
                format_number(first) + " s to " + format_number(last) + " s");
  std::size_t best = 0;
  for (std::size_t k = 1; k < series.frames.size(); ++k)
    if (std::abs(series.frames[k].time - time) < std::abs(series.frames[best].time - time)) best = k;
  return best;
}

vtkSmartPointer<vtkPolyData> read_frame(const SeriesFrame& frame) {
  std::error_code ec;
  if (!fs::is_regular_file(frame.file, ec))
    throw Error("the frame at t = " + format_number(frame.time) + " s, " + frame.file.string() + ", does not exist");
  render::VtkMessages messages;
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName(frame.file.c_str());
  reader->Update();
  messages.check("cannot read " + frame.file.string());
  vtkSmartPointer<vtkPolyData> points = reader->GetOutput();
  if (!points || points->GetNumberOfPoints() == 0)
    throw Error(frame.file.string() + " holds no material points");
  return points;
}

std::string time_label(double time) {
  // Frames are written at the first step past each interval (10.0001 s for
  // 10 s): four significant digits, and whole seconds from 1000 s on.
  const double magnitude = std::abs(time) >= 1000 ? 1 : std::pow(10.0, std::floor(std::log10(std::abs(time))) - 3);
  const double rounded = time == 0 ? 0 : std::round(time / magnitude) * magnitude;
  std::ostringstream out;
  out << std::setprecision(12) << rounded;
  return "t = " + out.str() + " s";
}

}  // namespace suffuse::plot
