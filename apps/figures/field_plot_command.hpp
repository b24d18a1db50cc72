// The command line of suffuse plot profile, map and animate.
#pragma once

#include <string>

namespace suffuse::plot {

// Whether NAME is one of the modes below (profile, map, animate).
bool is_field_plot_mode(const std::string& name);

// Runs suffuse plot MODE with ARGV[1..ARGC) (ARGV[0] is the mode): parses the
// options, draws, and returns the exit status. Throws suffuse::Error (and
// boost's option errors) on wrong input.
int field_plot_command(int argc, char** argv);

}  // namespace suffuse::plot
