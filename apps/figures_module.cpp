// Loads the figures module on the first call (figures_module.hpp).
#include "figures_module.hpp"

#include <boost/dll/shared_library.hpp>
#include <exception>
#include <memory>
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/version.hpp>

#include "figures_entry_points.hpp"

namespace suffuse::figures {

namespace {

// Beside the bundled plugins (<libdir>/suffuse), found from the core's own
// location as they are: the build tree and a moved install both work. Never
// unloaded: VTK's own clean-up at exit must find its code.
const boost::dll::shared_library& module() {
  static const boost::dll::shared_library* library = [] {
    const auto path = PluginLoader::bundled_plugin_directory().parent_path() / "libsuffuse_figures.so";
    try {
      auto loaded = std::make_unique<boost::dll::shared_library>(path.string(), boost::dll::load_mode::rtld_now);
      const std::string version = loaded->get<ModuleVersion>("suffuse_figures_module_version")();
      if (version != framework_version)
        throw Error("it is suffuse " + version + "'s, this is suffuse " + framework_version);
      for (const char* entry : {"suffuse_figures_plot", "suffuse_figures_gradation_png"})
        if (!loaded->has(entry)) throw Error(std::string("it has no ") + entry);
      return loaded.release();
    } catch (const std::exception& e) {
      throw Error("cannot load the figures module " + path.string() + " (" + e.what() + "); reinstall suffuse");
    }
  }();
  return *library;
}

}  // namespace

int plot_command(int argc, char** argv) { return module().get<PlotCommand>("suffuse_figures_plot")(argc, argv); }

void write_gradation_png(const Gradation& g, const InternalStability& s, const std::filesystem::path& file) {
  module().get<WriteGradationPng>("suffuse_figures_gradation_png")(g, s, file);
}

}  // namespace suffuse::figures
