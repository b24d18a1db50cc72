// The writers' side of vtk_files.hpp: the frame files, and the VTK module
// loaded when a writer opens its series.
#include <iomanip>
#include <sstream>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>

#include "vtk_files.hpp"

namespace suffuse::vtk {

namespace fs = std::filesystem;

namespace {

struct Entries {
  WritePoints* points;
  WriteImage* image;
};

// Loaded when a VTK writer opens its series (PluginLoader::load_module).
const Entries& module(const std::string& plugin) {
  static const Entries entries = [&plugin] {
    try {
      const auto at = PluginLoader::load_module("libsuffuse_vtk_files.so", "VTK module", "suffuse_vtk_module_version",
                                                {"suffuse_vtk_write_points", "suffuse_vtk_write_image"});
      return Entries{reinterpret_cast<WritePoints*>(at[0]), reinterpret_cast<WriteImage*>(at[1])};
    } catch (const Error& e) {
      throw Error(plugin + ": " + e.what() + "; reinstall suffuse");
    }
  }();
  return entries;
}

}  // namespace

void load_module(const std::string& plugin) { module(plugin); }

void write_points(const PointsFrame& frame, const fs::path& file, bool compress, const std::string& plugin) {
  module(plugin).points(frame, file, compress, plugin);
}

void write_image(const ImageFrame& frame, const fs::path& file, bool compress, const std::string& plugin) {
  module(plugin).image(frame, file, compress, plugin);
}

void FrameFiles::open(const fs::path& directory, const std::string& basename) {
  directory_ = directory;
  basename_ = basename;
  frames_ = 0;
}

void FrameFiles::resume(const fs::path& directory, const std::string& basename, const ResumePoint& at) {
  open(directory, basename);
  frames_ = at.frames;
  for (std::size_t k = frames_; fs::exists(directory_ / name(k)); ++k) fs::remove(directory_ / name(k));
}

std::string FrameFiles::name(std::size_t frame) const {
  std::ostringstream out;
  out << basename_ << "_" << std::setw(6) << std::setfill('0') << frame << "." << extension_;
  return out.str();
}

std::string FrameFiles::next_name() const { return name(frames_); }

void FrameFiles::written(OutputSeries& series, double time) {
  series.add(name(frames_), time);
  ++frames_;
}

}  // namespace suffuse::vtk
