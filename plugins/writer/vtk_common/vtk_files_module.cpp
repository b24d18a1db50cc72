// The writers' side of vtk_files.hpp: the frame files, and the VTK module
// loaded on the first frame written.
#include <boost/dll/shared_library.hpp>
#include <exception>
#include <iomanip>
#include <memory>
#include <sstream>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/version.hpp>

#include "vtk_files.hpp"

namespace suffuse::vtk {

namespace fs = std::filesystem;

namespace {

// Beside the bundled plugins (<libdir>/suffuse), found from the core's own
// location as they are: the build tree and a moved install both work. Never
// unloaded: VTK's own clean-up at exit must find its code.
const boost::dll::shared_library& module(const std::string& plugin) {
  static const boost::dll::shared_library* library = [&plugin] {
    const auto path = PluginLoader::bundled_plugin_directory().parent_path() / "libsuffuse_vtk_files.so";
    try {
      auto loaded = std::make_unique<boost::dll::shared_library>(path.string(), boost::dll::load_mode::rtld_now);
      const std::string version = loaded->get<ModuleVersion>("suffuse_vtk_module_version")();
      if (version != framework_version)
        throw Error("it is suffuse " + version + "'s, this is suffuse " + framework_version);
      for (const char* entry : {"suffuse_vtk_write_points", "suffuse_vtk_write_image"})
        if (!loaded->has(entry)) throw Error(std::string("it has no ") + entry);
      return loaded.release();
    } catch (const std::exception& e) {
      throw Error(plugin + ": cannot load the VTK module " + path.string() + " (" + e.what() + "); reinstall suffuse");
    }
  }();
  return *library;
}

}  // namespace

void write_points(const PointsFrame& frame, const fs::path& file, bool compress, const std::string& plugin) {
  module(plugin).get<WritePoints>("suffuse_vtk_write_points")(frame, file, compress, plugin);
}

void write_image(const ImageFrame& frame, const fs::path& file, bool compress, const std::string& plugin) {
  module(plugin).get<WriteImage>("suffuse_vtk_write_image")(frame, file, compress, plugin);
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
