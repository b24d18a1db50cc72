// The command line of suffuse plot profile, map and animate (see field_plot_command.hpp).
#include "field_plot_command.hpp"

#include <boost/program_options.hpp>
#include <cmath>
#include <cstdlib>
#include <iostream>
#include <sstream>
#include <suffuse/error.hpp>
#include <vector>

#include "animation.hpp"
#include "field_plots.hpp"

namespace suffuse::plot {

namespace po = boost::program_options;

namespace {

const char* profile_usage =
    "Usage: suffuse plot profile --png OUT.png --field NAME [--field NAME ...] --from X,Y[,Z] --to X,Y[,Z]\n"
    "                            [--times T,T,...] [options] RUN\n"
    "Draws a field of the material points along the line from --from to --to, one line per time, into a\n"
    "PNG (with several --field, one PNG each: OUT.<field>.png). RUN is a run's output directory or its\n"
    ".pvd. The points taken are those whose box, a tenth larger, the line passes through (--band W:\n"
    "those at most W m from it), between the two ends, at their distance along the line; a line along\n"
    "the edge between two rows of points takes both. Each time is drawn from the\n"
    "nearest frame (the command says when that is not the time asked for); by default four times\n"
    "spread evenly over the run.\n"
    "A NAME is a field of the points (porosity, fines_content, concentration, ...), or NAME:x, NAME:y,\n"
    "NAME:z, NAME:magnitude for a vector (magnitude by default), NAME:XX ... for stress and strain.\n"
    "Example: suffuse plot profile --png column.png --field porosity --field fines_content\n"
    "           --from 0.02,0 --to 0.02,0.4 --times 0,10,25,50 output/suffusion_column\n";

const char* map_usage =
    "Usage: suffuse plot map --png OUT.png --field NAME [--time T ...] [--range MIN MAX] [options] RUN\n"
    "Draws a 2D run's material points (or, with --slice z=Z, those of a 3D run whose box crosses\n"
    "that plane) as boxes of their size coloured by a field (viridis), one panel\n"
    "per time (default: the last frame), with a colour bar titled with the field and its unit. The view\n"
    "is the body's extent in the first frame; the colour scale is the field's range over the whole run\n"
    "unless --range is given, so that maps of different times compare. RUN is a run's output directory\n"
    "or its .pvd; NAME as in suffuse plot profile. Image size: from the body's shape, or --width, --height.\n"
    "Example: suffuse plot map --png fines.png --field fines_content --times 0,10,25,50 output/suffusion_column\n";

const char* animate_usage =
    "Usage: suffuse plot animate --field NAME [--frames DIR] [--gif OUT.gif] [options] RUN\n"
    "Draws the colour map of suffuse plot map at every frame of the run (every N-th with --every N),\n"
    "with one view and one colour scale throughout: numbered PNGs DIR/<field>_000000.png, ... (DIR is\n"
    "created; files there are overwritten, others are left), and a looping animated GIF.\n"
    "Example: suffuse plot animate --field fines_content --frames frames --gif fines.gif output/suffusion_column\n";

double parse_number(const std::string& text, const std::string& option) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0' || !std::isfinite(v))
    throw Error(option + ": '" + text + "' is not a number");
  return v;
}

// Comma-separated numbers ("0,10,50"), from one or more arguments.
std::vector<double> parse_numbers(const std::vector<std::string>& args, const std::string& option) {
  std::vector<double> out;
  for (const auto& arg : args) {
    std::stringstream in(arg);
    for (std::string cell; std::getline(in, cell, ',');) out.push_back(parse_number(cell, option));
    if (!arg.empty() && arg.back() == ',') throw Error(option + " " + arg + ": a number is missing after the last ','");
  }
  return out;
}

std::array<double, 3> parse_position(const std::string& text, const std::string& option) {
  const auto v = parse_numbers({text}, option);
  if (v.size() != 2 && v.size() != 3)
    throw Error(option + " " + text + ": expected a position X,Y (2D) or X,Y,Z (3D) in metres");
  return {v[0], v[1], v.size() == 3 ? v[2] : 0.0};
}

std::optional<std::array<double, 2>> parse_range(const po::variables_map& vm) {
  if (!vm.count("range")) return std::nullopt;
  const auto v = parse_numbers({vm["range"].as<std::string>()}, "--range");
  if (v.size() != 2) throw Error("--range: expected MIN MAX (or MIN,MAX), got " + std::to_string(v.size()) + " number(s)");
  return std::array<double, 2>{v[0], v[1]};
}

std::vector<double> parse_times(const po::variables_map& vm) {
  std::vector<std::string> args;
  for (const char* key : {"time", "times"})
    if (vm.count(key))
      for (const auto& a : vm[key].as<std::vector<std::string>>()) args.push_back(a);
  return parse_numbers(args, "--times");
}

// ARGV[1..ARGC) with "--range MIN MAX" joined into one argument "--range=MIN,MAX"
// (boost would take the run after them as a third value) and -h as --help.
std::vector<std::string> normalised_arguments(int argc, char** argv) {
  std::vector<std::string> args(argv + 1, argv + argc);
  for (std::size_t i = 0; i < args.size(); ++i) {
    if (args[i] == "-h") args[i] = "--help";
    if (args[i] != "--range" || i + 1 == args.size()) continue;
    const bool two = args[i + 1].find(',') == std::string::npos && i + 2 < args.size();
    args[i] = "--range=" + args[i + 1] + (two ? "," + args[i + 2] : "");
    args.erase(args.begin() + static_cast<std::ptrdiff_t>(i) + 1, args.begin() + static_cast<std::ptrdiff_t>(i) + (two ? 3 : 2));
  }
  return args;
}

}  // namespace

bool is_field_plot_mode(const std::string& name) { return name == "profile" || name == "map" || name == "animate"; }

int field_plot_command(int argc, char** argv) {
  const std::string mode = argv[0];
  po::options_description opts("Options of suffuse plot " + mode);
  opts.add_options()("help,h", "show this help")("field", po::value<std::vector<std::string>>(),
                                                  mode == "profile" ? "a field to draw; repeat for more"
                                                                    : "the field to draw (required)");
  if (mode != "animate")
    opts.add_options()("png", po::value<std::string>(), "the PNG file to write (required)")(
        "time", po::value<std::vector<std::string>>(), "a time to draw [s]; repeat for more")(
        "times", po::value<std::vector<std::string>>(), "times to draw [s], comma-separated: 0,10,50");
  if (mode == "profile")
    opts.add_options()("from", po::value<std::string>(), "the start of the line: X,Y or X,Y,Z [m] (required)")(
        "to", po::value<std::string>(), "the end of the line [m] (required)")(
        "band", po::value<double>()->default_value(0),
        "take the points at most this far from the line [m] (default: those whose box it crosses)")(
        "title", po::value<std::string>()->default_value(""), "the chart title (default: none)")(
        "legend", po::value<std::string>()->default_value("auto"),
        "legend corner: top-left, top-right, bottom-left, bottom-right, or auto")(
        "width", po::value<int>()->default_value(900), "image width [px]")(
        "height", po::value<int>()->default_value(600), "image height [px]");
  else
    opts.add_options()("range", po::value<std::string>(),
                       "the colour scale: MIN MAX (default: the field's range over the run)")(
        "width", po::value<int>()->default_value(0), "image width [px] (default: from the body's shape)")(
        "height", po::value<int>()->default_value(0), "image height [px] (default: from the body's shape)")(
        "slice", po::value<std::string>()->default_value(""),
        "of a 3D run: the plane drawn, x=X, y=Y or z=Z [m] (the points whose box crosses it)");
  if (mode == "animate")
    opts.add_options()("frames", po::value<std::string>(), "a directory for the numbered PNG frames")(
        "gif", po::value<std::string>(), "an animated GIF to write")(
        "every", po::value<int>()->default_value(1), "draw every N-th frame (and the last)")(
        "frame-time", po::value<double>()->default_value(0.1), "seconds per frame of the GIF");
  po::options_description hidden;
  hidden.add_options()("run", po::value<std::vector<std::string>>());
  po::options_description all;
  all.add(opts).add(hidden);
  po::positional_options_description positional;
  positional.add("run", -1);
  po::variables_map vm;
  // No short options, so that a negative number (--from -0.1,0) is a value.
  const auto style = po::command_line_style::unix_style ^ po::command_line_style::allow_short;
  po::store(po::command_line_parser(normalised_arguments(argc, argv)).options(all).positional(positional).style(style).run(),
            vm);
  po::notify(vm);
  const char* usage = mode == "profile" ? profile_usage : mode == "map" ? map_usage : animate_usage;
  if (vm.count("help")) {
    std::cout << usage << "\n" << opts;
    return 0;
  }
  const auto runs = vm.count("run") ? vm["run"].as<std::vector<std::string>>() : std::vector<std::string>();
  if (runs.size() != 1)
    throw Error("suffuse plot " + mode + " needs one run: its output directory or its .pvd (got " +
                std::to_string(runs.size()) + ")");
  const auto fields = vm.count("field") ? vm["field"].as<std::vector<std::string>>() : std::vector<std::string>();
  if (mode != "profile" && fields.size() > 1)
    throw Error("suffuse plot " + mode + " draws one --field (got " + std::to_string(fields.size()) + ")");
  const std::string field = fields.empty() ? "" : fields.front();

  if (mode == "profile") {
    ProfileOptions o;
    o.series = runs.front();
    o.fields = fields;
    if (vm.count("png")) o.png = vm["png"].as<std::string>();
    if (!vm.count("from") || !vm.count("to")) throw Error("suffuse plot profile needs --from X,Y and --to X,Y");
    o.line.from = parse_position(vm["from"].as<std::string>(), "--from");
    o.line.to = parse_position(vm["to"].as<std::string>(), "--to");
    o.line.band = vm["band"].as<double>();
    o.times = parse_times(vm);
    o.title = vm["title"].as<std::string>();
    o.legend = parse_legend_corner(vm["legend"].as<std::string>());
    o.width = vm["width"].as<int>();
    o.height = vm["height"].as<int>();
    write_profiles(o, std::cout);
  } else if (mode == "map") {
    MapOptions o;
    o.series = runs.front();
    o.field = field;
    if (vm.count("png")) o.png = vm["png"].as<std::string>();
    o.times = parse_times(vm);
    o.range = parse_range(vm);
    o.width = vm["width"].as<int>();
    o.height = vm["height"].as<int>();
    o.slice = vm["slice"].as<std::string>();
    write_map(o, std::cout);
  } else {
    AnimationOptions o;
    o.series = runs.front();
    o.field = field;
    if (vm.count("frames")) o.frames = vm["frames"].as<std::string>();
    if (vm.count("gif")) o.gif = vm["gif"].as<std::string>();
    o.range = parse_range(vm);
    o.width = vm["width"].as<int>();
    o.height = vm["height"].as<int>();
    o.every = vm["every"].as<int>();
    o.slice = vm["slice"].as<std::string>();
    o.seconds_per_frame = vm["frame-time"].as<double>();
    write_animation(o, std::cout);
  }
  return 0;
}

}  // namespace suffuse::plot
