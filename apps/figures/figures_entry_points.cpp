// The figures module's entry points (figures_module.hpp).
#include "figures_entry_points.hpp"

#include <suffuse/version.hpp>
#include <type_traits>

#include "gradation_figure.hpp"
#include "plot_command.hpp"

extern "C" int suffuse_figures_plot(int argc, char** argv) { return suffuse::plot::plot_command(argc, argv); }

extern "C" void suffuse_figures_gradation_png(const suffuse::Gradation& g, const suffuse::InternalStability& s,
                                              const std::filesystem::path& file) {
  suffuse::gradation_figure::write_png(g, s, file);
}

extern "C" const char* suffuse_figures_module_version() { return suffuse::framework_version; }

static_assert(std::is_same_v<decltype(suffuse_figures_plot), suffuse::figures::PlotCommand>);
static_assert(std::is_same_v<decltype(suffuse_figures_gradation_png), suffuse::figures::WriteGradationPng>);
static_assert(std::is_same_v<decltype(suffuse_figures_module_version), suffuse::figures::ModuleVersion>);
