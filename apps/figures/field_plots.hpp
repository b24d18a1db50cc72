// suffuse plot profile and suffuse plot map: figures of a run's point series
// (the .pvd of writer/vtk_particles) as PNG, without a display.
#pragma once

#include <array>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>
#include <vector>

#include "field_profile.hpp"
#include "plot.hpp"
#include "vtk_series.hpp"

namespace suffuse::plot {

struct ProfileOptions {
  std::filesystem::path png;     // with several fields: one file each, the field before .png
  std::filesystem::path series;  // a .pvd or a run's output directory
  std::vector<std::string> fields;
  std::vector<double> times;  // empty: four times evenly over the series
  ProfileLine line;
  int width = 900, height = 600;
  std::string title;
  LegendCorner legend = LegendCorner::automatic;
};

// The PNG of FIELD when a call draws FIELDS: PNG itself for one field, else
// PNG with the field before the extension (profile.png -> profile.porosity.png).
std::filesystem::path png_of_field(const std::filesystem::path& png, const std::string& field,
                                   const std::vector<std::string>& fields);

// The frames of SERIES nearest TIMES (empty: four times evenly spread), each
// once, by time; a line in LOG for every time that is not a frame's. Throws
// suffuse::Error for a time outside the series.
std::vector<std::size_t> frames_at(const PointSeries& series, const std::vector<double>& times, std::ostream& log);

// Reads everything first (nothing is written on an error), then writes one
// line chart per field: the field along the line, one line per time. Names
// the files written in LOG. Throws suffuse::Error.
void write_profiles(const ProfileOptions& options, std::ostream& log);

struct MapOptions {
  std::filesystem::path png;
  std::filesystem::path series;
  std::string field;
  std::vector<double> times;  // one panel each; empty: the last frame
  std::optional<std::array<double, 2>> range;  // empty: the field's range over the whole series
  int width = 0, height = 0;                   // 0: from the body's shape
  std::string slice;                           // of a 3D run: "x=X", "y=Y" or "z=Z" (colour_map.hpp)
};

// The field's smallest and largest value over every frame of SERIES, widened
// when they are equal. Throws suffuse::Error when a frame lacks the field.
std::array<double, 2> series_range(const PointSeries& series, const std::string& field);

// Throws suffuse::Error unless RANGE is finite and increasing.
void check_range(const std::array<double, 2>& range);

// A colour map of the field at each time, side by side, with one colour bar.
void write_map(const MapOptions& options, std::ostream& log);

}  // namespace suffuse::plot
