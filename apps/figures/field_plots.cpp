// suffuse plot profile and suffuse plot map (see field_plots.hpp).
#include "field_plots.hpp"

#include <algorithm>
#include <cmath>
#include <ostream>
#include <set>
#include <sstream>
#include <suffuse/error.hpp>

#include "chart_output.hpp"
#include "colour_map.hpp"
#include "format_number.hpp"
#include "offscreen_render_window.hpp"
#include "point_field.hpp"

namespace suffuse::plot {

namespace fs = std::filesystem;

namespace {

std::string format_point(const std::array<double, 3>& p) {
  std::ostringstream out;
  out << "(" << p[0] << ", " << p[1];
  if (p[2] != 0) out << ", " << p[2];
  out << ")";
  return out.str();
}

}  // namespace

fs::path png_of_field(const fs::path& png, const std::string& field, const std::vector<std::string>& fields) {
  if (fields.size() < 2) return png;
  std::string name = field;
  std::replace(name.begin(), name.end(), ':', '_');
  fs::path out = png;
  out.replace_extension();
  return out.string() + "." + name + png.extension().string();
}

std::vector<std::size_t> frames_at(const PointSeries& series, const std::vector<double>& times, std::ostream& log) {
  std::vector<double> wanted = times;
  if (wanted.empty()) {
    const double first = series.frames.front().time, last = series.frames.back().time;
    for (int k = 0; k < 4; ++k) wanted.push_back(first + (last - first) * k / 3);
  }
  std::set<std::size_t> frames;
  for (double t : wanted) {
    const std::size_t f = nearest_frame(series, t);
    const double used = series.frames[f].time;
    // Said when the frame is off by more than a hundredth of the mean interval between frames.
    const double interval = series.frames.size() > 1 ? (series.frames.back().time - series.frames.front().time) /
                                                           static_cast<double>(series.frames.size() - 1)
                                                     : 0;
    if (!times.empty() && std::abs(used - t) > 0.01 * interval + 1e-12 * std::abs(t))
      log << "t = " << format_number(t) << " s: the nearest frame is at t = " << format_number(used) << " s ("
          << series.frames[f].file.filename().string() << ")\n";
    if (!frames.insert(f).second && !times.empty())
      log << "t = " << format_number(t) << " s: that frame is drawn once\n";
  }
  return {frames.begin(), frames.end()};
}

void write_profiles(const ProfileOptions& o, std::ostream& log) {
  if (o.png.empty()) throw Error("suffuse plot profile needs --png OUT.png");
  if (o.fields.empty()) throw Error("suffuse plot profile needs at least one --field NAME");
  render::check_image_size(o.width, o.height);
  if (!(o.line.band >= 0) || !std::isfinite(o.line.band)) throw Error("--band must be a width in metres, at least 0");
  render::check_writable(o.png);
  const PointSeries series = read_point_series(o.series);
  const std::vector<std::size_t> frames = frames_at(series, o.times, log);

  // Read every frame and field before drawing: nothing is written on an error.
  std::vector<std::vector<Series>> lines(o.fields.size());
  std::vector<std::string> labels(o.fields.size());
  for (std::size_t f : frames) {
    const auto points = read_frame(series.frames[f]);
    const auto sizes = o.line.band > 0 ? std::vector<std::array<double, 3>>() : point_sizes(points);
    for (std::size_t k = 0; k < o.fields.size(); ++k) {
      const PointField field = point_field(points, o.fields[k]);
      labels[k] = field.label;
      const auto samples = extract_profile(points, field.values, sizes, o.line);
      if (samples.empty())
        throw Error("no material point lies near the line from " + format_point(o.line.from) + " to " +
                    format_point(o.line.to) + " at " + time_label(series.frames[f].time) +
                    (o.line.band > 0 ? " within --band " + format_number(o.line.band) + " m"
                                     : " (no point's box touches it)") +
                    ": check the ends, or widen the band with --band WIDTH [m]");
      Series line;
      line.label = time_label(series.frames[f].time);
      for (const auto& s : samples) line.x.push_back(s.s), line.y.push_back(s.value);
      lines[k].push_back(std::move(line));
    }
  }
  const std::string xlabel = "distance from " + format_point(o.line.from) + " towards " + format_point(o.line.to) + " [m]";
  for (std::size_t k = 0; k < o.fields.size(); ++k) {
    PlotOptions chart;
    chart.png = png_of_field(o.png, o.fields[k], o.fields);
    chart.width = o.width, chart.height = o.height;
    chart.title = o.title;
    chart.legend = o.legend;
    write_line_chart(lines[k], chart, xlabel, labels[k]);
    log << "wrote " << chart.png.string() << "\n";
  }
}

std::array<double, 2> series_range(const PointSeries& series, const std::string& field) {
  double lo = INFINITY, hi = -INFINITY;
  for (const auto& frame : series.frames)
    for (double v : point_field(read_frame(frame), field).values)
      if (std::isfinite(v)) lo = std::min(lo, v), hi = std::max(hi, v);
  if (!std::isfinite(lo)) throw Error("field '" + field + "' has no finite value in " + series.pvd.string());
  if (hi - lo <= 1e-12 * std::max(std::abs(lo), std::abs(hi))) {
    // A uniform field: a scale around its value, so that it takes the middle colour.
    const double pad = lo == 0 ? 1 : 0.1 * std::abs(lo);
    lo -= pad, hi += pad;
  }
  return {lo, hi};
}

void check_range(const std::array<double, 2>& range) {
  if (!std::isfinite(range[0]) || !std::isfinite(range[1]) || !(range[0] < range[1]))
    throw Error("--range MIN MAX: expected finite numbers with MIN < MAX, got " + format_number(range[0]) + " " +
                format_number(range[1]));
}

void write_map(const MapOptions& o, std::ostream& log) {
  if (o.png.empty()) throw Error("suffuse plot map needs --png OUT.png");
  if (o.field.empty()) throw Error("suffuse plot map needs --field NAME");
  if (o.range) check_range(*o.range);
  render::check_writable(o.png);
  const PointSeries series = read_point_series(o.series);
  const std::vector<std::size_t> frames =
      o.times.empty() ? std::vector<std::size_t>{series.frames.size() - 1} : frames_at(series, o.times, log);

  // The initial frame fixes the view, so that maps of different times line up.
  const auto initial = read_frame(series.frames.front());
  const MapPlane plane = map_plane(initial, o.slice);
  const MapLayout layout =
      map_layout(body_bounds(initial, plane), static_cast<int>(frames.size()), o.width, o.height, plane);
  const std::array<double, 2> range = o.range ? *o.range : series_range(series, o.field);
  std::vector<vtkSmartPointer<vtkPolyData>> points;
  std::vector<MapPanel> panels;
  for (std::size_t f : frames) {
    points.push_back(read_frame(series.frames[f]));
    panels.push_back({points.back(), point_field(points.back(), o.field), series.frames[f].time});
  }
  ColourMapCanvas canvas(layout);
  const auto image = canvas.draw(panels, range);
  render::write_atomically(o.png, [&](const fs::path& part) {
    render::VtkMessages messages;
    render::write_png(image, part, messages);
  });
  log << "wrote " << o.png.string() << " (" << panels.front().field.label << " from " << format_number(range[0])
      << " to " << format_number(range[1]) << ")\n";
}

}  // namespace suffuse::plot
