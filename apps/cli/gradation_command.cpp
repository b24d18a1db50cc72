// suffuse gradation: reads a PSD file, evaluates the internal-stability
// criteria and prints them as a table (or JSON for scripts); --png draws the
// curve and the Kenney-Lau shape curve with each criterion's boundary.
#include "gradation_command.hpp"

#include <boost/program_options.hpp>
#include <cmath>
#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <suffuse/error.hpp>
#include <suffuse/gradation.hpp>

#include "figures_module.hpp"
#include "subcommand_options.hpp"

namespace suffuse::gradation_command {

namespace po = boost::program_options;

namespace {

const char* usage =
    "Usage: suffuse gradation PSD.csv [--json] [--png FILE.png]\n"
    "Evaluates the internal-stability criteria of a particle-size distribution (Kezdi 1979, Kenney and\n"
    "Lau 1985 and 1986, Li and Fannin 2008, Burenkova 1993, modified Burenkova of Wan and Fell 2004, the\n"
    "alternative method of Wan and Fell 2008, Chang and Zhang 2013) and prints a table: criterion, value,\n"
    "verdict, applicability, and under each what the value is, where on the curve and the boundary.\n"
    "PSD.csv has a header naming the units, \"size [mm], passing [%]\" (size in mm, um or m), then one row\n"
    "per sieve, smallest size first, 100 % passing at the largest; PSD.json is\n"
    "{\"size_unit\": \"mm\", \"points\": [[size, percent passing], ...]}. docs/gradation.md explains each\n"
    "criterion and how scenes use a gradation.\n";

std::string number(double v) {
  if (std::isnan(v)) return "-";
  std::ostringstream s;
  s << std::setprecision(4) << v;
  return s.str();
}

std::string where(const CriterionResult& c) {
  if (std::isnan(c.at_passing)) return "";
  return ", at F = " + number(100 * c.at_passing) + " %, D = " + number(c.at_size_mm) + " mm";
}

nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

nlohmann::json to_json(const Gradation& g, const InternalStability& s) {
  nlohmann::json out;
  out["file"] = g.source();
  out["read_order"] = describe(g.order());
  nlohmann::json points = nlohmann::json::array();
  for (std::size_t i = 0; i < g.sizes_mm().size(); ++i)
    points.push_back({g.sizes_mm()[i], 100 * g.passing_points()[i]});
  out["points_mm_percent"] = points;
  out["cu"] = number_or_null(s.cu);
  out["shape_curve_limit"] = s.shape_curve_limit;
  out["gap"] = s.gap ? nlohmann::json{{"from_mm", s.gap->from_mm}, {"to_mm", s.gap->to_mm},
                                      {"passing", s.gap->passing}, {"ratio", s.gap->ratio()}}
                     : nlohmann::json();
  for (const CriterionResult& c : s.criteria) {
    nlohmann::json also = nlohmann::json::object();
    for (const auto& [name, value] : c.also) also[name] = number_or_null(value);
    out["criteria"].push_back({{"id", c.id},
                               {"name", c.name},
                               {"quantity", c.quantity},
                               {"value", number_or_null(c.value)},
                               {"boundary", c.boundary},
                               {"verdict", to_string(c.verdict)},
                               {"applicability", c.applicability},
                               {"at_size_mm", number_or_null(c.at_size_mm)},
                               {"at_passing", number_or_null(c.at_passing)},
                               {"also", also}});
  }
  out["unstable"] = s.unstable();
  out["stable"] = s.stable();
  out["erodible_fines"] = s.erodible_fines;
  out["erodible_fines_rule"] = s.erodible_fines_rule;
  return out;
}

}  // namespace

void print_table(std::ostream& out, const InternalStability& s, const std::string& indent) {
  std::size_t width = std::string("criterion").size();
  for (const CriterionResult& c : s.criteria) width = std::max(width, c.name.size());
  out << indent << std::left << std::setw(static_cast<int>(width) + 2) << "criterion" << std::setw(10) << "value"
      << std::setw(16) << "verdict"
      << "applicability\n";
  for (const CriterionResult& c : s.criteria) {
    out << indent << std::left << std::setw(static_cast<int>(width) + 2) << c.name << std::setw(10) << number(c.value)
        << std::setw(16) << to_string(c.verdict) << c.applicability << "\n"
        << indent << "    " << c.quantity << where(c) << "; " << c.boundary;
    for (const auto& [name, value] : c.also) out << "; " << name << " = " << number(value);
    out << "\n";
  }
  out << indent << "erodible fines content: " << number(100 * s.erodible_fines) << " % (" << s.erodible_fines_rule
      << ")\n";
}

int run(int argc, char** argv) {
  po::options_description opts("Options of suffuse gradation");
  opts.add_options()("help,h", "show this help")("json", "print JSON instead of the table")(
      "png", po::value<std::string>(), "also draw the PSD and its shape curve with the criteria's boundaries");
  const auto parsed = subcommand::parse(argc, argv, opts, usage);
  if (!parsed) return 0;
  const po::variables_map& vm = parsed->options;
  const std::vector<std::string>& files = parsed->files;
  if (files.size() != 1) throw Error("suffuse gradation needs one PSD file (.csv or .json), found " +
                                     std::to_string(files.size()));
  const Gradation g = read_gradation_file(files[0]);
  const InternalStability s = assess_internal_stability(g);
  if (vm.count("png")) figures::write_gradation_png(g, s, vm["png"].as<std::string>());
  if (vm.count("json")) {
    std::cout << to_json(g, s).dump(2) << "\n";
    return 0;
  }
  std::cout << g.source() << ": " << g.sizes_mm().size() << " points (read " << describe(g.order()) << "), " << number(g.sizes_mm().front()) << "-"
            << number(g.sizes_mm().back()) << " mm; Cu = " << number(s.cu) << "; shape curve examined for F <= "
            << number(s.shape_curve_limit);
  if (s.gap)
    std::cout << "; gap " << number(s.gap->from_mm) << "-" << number(s.gap->to_mm) << " mm at "
              << number(100 * s.gap->passing) << " % passing";
  std::cout << "\n\n";
  print_table(std::cout, s);
  return 0;
}

}  // namespace suffuse::gradation_command
