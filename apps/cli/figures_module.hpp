#pragma once
// The figures module, libsuffuse_figures.so next to the bundled plugins'
// directory: suffuse plot and the PNG of suffuse gradation, which draw with
// VTK's charts and renderer. VTK's rendering and OpenGL libraries would cost
// every suffuse command about 25 MB and a tenth of a second at start-up;
// the module is loaded only by the commands that draw.
#include <filesystem>
#include <suffuse/gradation.hpp>
#include <suffuse/internal_stability.hpp>

namespace suffuse::figures {

// suffuse plot (ARGV[0] is "plot"): plot_command.hpp.
int plot_command(int argc, char** argv);

// The PNG of suffuse gradation --png: gradation_figure.hpp.
void write_gradation_png(const Gradation& g, const InternalStability& s, const std::filesystem::path& file);

}  // namespace suffuse::figures
