// Loads the figures module on the first call (figures_module.hpp).
#include "figures_module.hpp"

#include <string>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>

#include "figures_entry_points.hpp"

namespace suffuse::figures {

namespace {

struct Entries {
  PlotCommand* plot;
  WriteGradationPng* gradation_png;
};

// Loaded by the first command that draws (PluginLoader::load_module).
const Entries& module() {
  static const Entries entries = [] {
    try {
      const auto at = PluginLoader::load_module("libsuffuse_figures.so", "figures module",
                                                "suffuse_figures_module_version",
                                                {"suffuse_figures_plot", "suffuse_figures_gradation_png"});
      return Entries{reinterpret_cast<PlotCommand*>(at[0]), reinterpret_cast<WriteGradationPng*>(at[1])};
    } catch (const Error& e) {
      throw Error(std::string(e.what()) + "; reinstall suffuse");
    }
  }();
  return entries;
}

}  // namespace

int plot_command(int argc, char** argv) { return module().plot(argc, argv); }

void write_gradation_png(const Gradation& g, const InternalStability& s, const std::filesystem::path& file) {
  module().gradation_png(g, s, file);
}

}  // namespace suffuse::figures
