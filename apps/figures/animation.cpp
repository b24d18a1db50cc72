// suffuse plot animate (see animation.hpp).
#include "animation.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <ostream>
#include <sstream>
#include <suffuse/error.hpp>
#include <system_error>
#include <vector>

#include "chart_output.hpp"
#include "colour_map.hpp"
#include "field_plots.hpp"
#include "gif_file.hpp"
#include "offscreen_render_window.hpp"
#include "point_field.hpp"
#include "vtk_series.hpp"

namespace suffuse::plot {

namespace fs = std::filesystem;

fs::path frame_png(const fs::path& directory, const std::string& field, std::size_t index) {
  std::string name = field;
  std::replace(name.begin(), name.end(), ':', '_');
  std::ostringstream file;
  file << name << "_" << std::setw(6) << std::setfill('0') << index << ".png";
  return directory / file.str();
}

void write_animation(const AnimationOptions& o, std::ostream& log) {
  if (o.field.empty()) throw Error("suffuse plot animate needs --field NAME");
  if (o.frames.empty() && o.gif.empty())
    throw Error("suffuse plot animate needs --frames DIR (numbered PNGs), --gif OUT.gif, or both");
  if (o.range) check_range(*o.range);
  if (o.every < 1) throw Error("--every must be at least 1");
  if (!(o.seconds_per_frame >= 0.01 && o.seconds_per_frame <= 600))
    throw Error("--frame-time must be between 0.01 and 600 s");
  std::error_code ec;
  if (!o.frames.empty() && fs::exists(o.frames, ec) && !fs::is_directory(o.frames, ec))
    throw Error("--frames " + o.frames.string() + ": it is a file, not a directory");
  if (!o.gif.empty()) render::check_writable(o.gif);
  const PointSeries series = read_point_series(o.series);

  std::vector<std::size_t> frames;
  for (std::size_t f = 0; f < series.frames.size(); f += static_cast<std::size_t>(o.every)) frames.push_back(f);
  if (frames.back() != series.frames.size() - 1) frames.push_back(series.frames.size() - 1);

  // The initial frame fixes the view; the scale is read from every frame,
  // which also checks that each has the field before anything is drawn.
  const auto initial = read_frame(series.frames.front());
  const MapPlane plane = map_plane(initial, o.slice);
  const MapLayout layout = map_layout(body_bounds(initial, plane), 1, o.width, o.height, plane);
  std::array<double, 2> range = series_range(series, o.field);
  if (o.range) range = *o.range;

  if (!o.frames.empty()) fs::create_directories(o.frames);
  std::vector<vtkSmartPointer<vtkImageData>> images;
  ColourMapCanvas canvas(layout);
  for (std::size_t k = 0; k < frames.size(); ++k) {
    const auto points = read_frame(series.frames[frames[k]]);
    const MapPanel panel{points, point_field(points, o.field), series.frames[frames[k]].time};
    auto image = canvas.draw({panel}, range);
    if (!o.frames.empty())
      render::write_atomically(frame_png(o.frames, o.field, k), [&](const fs::path& part) {
        render::VtkMessages messages;
        render::write_png(image, part, messages);
      });
    if (!o.gif.empty()) images.push_back(image);
  }
  if (!o.frames.empty())
    log << "wrote " << frames.size() << " frames to " << frame_png(o.frames, o.field, 0).string() << " ...\n";
  if (!o.gif.empty()) {
    const int delay = static_cast<int>(std::lround(100 * o.seconds_per_frame));
    render::write_atomically(o.gif, [&](const fs::path& part) { write_gif(part, images, delay); });
    log << "wrote " << o.gif.string() << " (" << images.size() << " frames)\n";
  }
}

}  // namespace suffuse::plot
