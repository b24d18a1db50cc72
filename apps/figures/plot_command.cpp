// suffuse plot, all its forms: line charts of CSV columns (here) and the
// figures of a run's points (field_plot_command.cpp). Built into the figures
// module (figures_module.hpp), which only suffuse plot and suffuse gradation
// --png load.
#include "plot_command.hpp"

#include <boost/program_options.hpp>
#include <string>
#include <vector>

#include "field_plot_command.hpp"
#include "plot.hpp"
#include "subcommand_options.hpp"

namespace suffuse::plot {

namespace po = boost::program_options;

namespace {

const char* plot_usage =
    "Usage: suffuse plot --png OUT.png --x COLUMN --y COLUMN [--y COLUMN ...] [options] FILE.csv [FILE.csv ...]\n"
    "Draws one line per FILE and --y COLUMN against --x COLUMN into a PNG, without a display (VTK\n"
    "charts in an offscreen EGL context). Each FILE has a header row; a COLUMN is a header cell, or\n"
    "the part of it before \" [\" (eroded_fraction matches 'eroded_fraction [-]'). Rows where x or y\n"
    "is nan or inf are skipped; any other cell of those columns that is not a number is an error.\n"
    "Legend: '<file>: <column>', or just <file> with one --y, or just <column> with one FILE. <file>\n"
    "is the file name without .csv; with several files, the part at the start and at the end that\n"
    "all of them share, cut at a '-', ' ' or '.' (not a decimal point), is left out (a.eta_0.element.csv\n"
    "and a.eta_0.55.element.csv give eta_0 and eta_0.55); --full-names keeps it.\n"
    "The PNG is written as OUT.png.part, then renamed; nothing is written on an error.\n"
    "Example: suffuse plot --png strain.png --x eroded_fraction --y erosion_volumetric_strain\n"
    "           --scale-x 100 --scale-y 100 output/suffosion_element/*.element.csv\n"
    "Figures of a run's material points: suffuse plot profile, map and animate (each with --help).\n";

int line_chart_command(int argc, char** argv) {
  po::options_description opts("Options of suffuse plot");
  opts.add_options()("help,h", "show this help")(
      "png", po::value<std::string>(), "the PNG file to write (required)")(
      "x", po::value<std::string>(), "the column of the horizontal axis (required)")(
      "y", po::value<std::vector<std::string>>(), "a column of the vertical axis; repeat for more (at least one)")(
      "title", po::value<std::string>()->default_value(""), "the chart title (default: none)")(
      "xlabel", po::value<std::string>()->default_value(""),
      "the horizontal axis title (default: the --x header, with its unit)")(
      "ylabel", po::value<std::string>()->default_value(""),
      "the vertical axis title (default: the --y headers, with their units)")(
      "width", po::value<int>()->default_value(900), "image width [px]")(
      "height", po::value<int>()->default_value(600), "image height [px]")(
      "scale-x", po::value<double>()->default_value(1), "multiply the x values by F (100: fractions in percent)")(
      "scale-y", po::value<double>()->default_value(1), "multiply the y values by F")(
      "legend", po::value<std::string>()->default_value("auto"),
      "legend corner: top-left, top-right, bottom-left, bottom-right, or auto (the corner the lines cross least)")(
      "full-names", "legend with the whole file names (without .csv)");
  const auto parsed = subcommand::parse(argc, argv, opts, plot_usage);
  if (!parsed) return 0;
  const po::variables_map& vm = parsed->options;
  PlotOptions o;
  if (vm.count("png")) o.png = vm["png"].as<std::string>();
  if (vm.count("x")) o.x = vm["x"].as<std::string>();
  if (vm.count("y")) o.y = vm["y"].as<std::vector<std::string>>();
  for (const auto& f : parsed->files) o.files.emplace_back(f);
  o.title = vm["title"].as<std::string>();
  o.xlabel = vm["xlabel"].as<std::string>();
  o.ylabel = vm["ylabel"].as<std::string>();
  o.width = vm["width"].as<int>();
  o.height = vm["height"].as<int>();
  o.scale_x = vm["scale-x"].as<double>();
  o.scale_y = vm["scale-y"].as<double>();
  o.legend = parse_legend_corner(vm["legend"].as<std::string>());
  o.full_names = vm.count("full-names") != 0;
  write_plot(o);
  return 0;
}

}  // namespace

int plot_command(int argc, char** argv) {
  if (argc >= 2 && is_field_plot_mode(argv[1])) return field_plot_command(argc - 1, argv + 1);
  return line_chart_command(argc, argv);
}

}  // namespace suffuse::plot
