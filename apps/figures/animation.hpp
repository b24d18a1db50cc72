// suffuse plot animate: the colour map of a field at every frame of a run, as
// numbered PNG files and as a looping animated GIF.
#pragma once

#include <array>
#include <filesystem>
#include <iosfwd>
#include <optional>
#include <string>

namespace suffuse::plot {

struct AnimationOptions {
  std::filesystem::path series;  // a .pvd or a run's output directory
  std::string field;
  std::filesystem::path frames;  // a directory for <field>_000000.png, ... (created); empty: none
  std::filesystem::path gif;     // an animated GIF; empty: none
  std::optional<std::array<double, 2>> range;  // empty: the field's range over the whole series
  int width = 0, height = 0;                   // 0: from the body's shape
  std::string slice;                           // of a 3D run: "x=X", "y=Y" or "z=Z" (colour_map.hpp)
  double seconds_per_frame = 0.1;              // of the GIF
  int every = 1;                               // draw every N-th frame of the series
};

// The numbered PNG of frame INDEX of FIELD in DIRECTORY.
std::filesystem::path frame_png(const std::filesystem::path& directory, const std::string& field, std::size_t index);

// Checks the options and every frame first (nothing is written on an error),
// then draws every N-th frame (and the last) with the same view and colour
// scale. Names what it wrote in LOG. Throws suffuse::Error.
void write_animation(const AnimationOptions& options, std::ostream& log);

}  // namespace suffuse::plot
