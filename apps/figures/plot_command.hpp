#pragma once

namespace suffuse::plot {

// suffuse plot: ARGV[0] is "plot"; a line chart of CSV columns, or, with
// ARGV[1] profile, map or animate, a figure of a run's points.
int plot_command(int argc, char** argv);

}  // namespace suffuse::plot
