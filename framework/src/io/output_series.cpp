#include "io/output_series.hpp"

#include <cmath>
#include <fstream>
#include <iomanip>
#include <regex>
#include <sstream>

#include "suffuse/error.hpp"

namespace suffuse::detail {

namespace fs = std::filesystem;

PvdSeries::PvdSeries(fs::path file) : file_(std::move(file)) {}

PvdSeries PvdSeries::resumed(fs::path file, double time) {
  std::ifstream in(file);
  if (!in) throw Error("cannot restart: " + file.string() + " is missing (the run's VTK collection)");
  PvdSeries series(file);
  // Only our own format is read back: one DataSet element per line.
  const std::regex dataset(R"re(<DataSet timestep="([^"]*)" group="[^"]*" part="([0-9]+)" file="([^"]*)"/>)re");
  const double tolerance = 1e-9 * std::max(1.0, std::abs(time));
  std::string line;
  std::smatch m;
  while (std::getline(in, line)) {
    if (!std::regex_search(line, m, dataset)) continue;
    const double t = std::stod(m[1].str());
    if (t <= time + tolerance) series.entries_.push_back({t, std::stoi(m[2].str()), m[3].str()});
  }
  return series;
}

void PvdSeries::add(const std::string& file, double time) {
  entries_.push_back({time, part_, file});
  changed_ = true;
}

void PvdSeries::save() {
  if (!changed_) return;
  const fs::path tmp = file_.string() + ".part";
  {
    std::ofstream out(tmp);
    out << std::setprecision(17);
    out << "<?xml version=\"1.0\"?>\n"
        << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n  <Collection>\n";
    for (const Entry& e : entries_)
      out << "    <DataSet timestep=\"" << e.time << "\" group=\"\" part=\"" << e.part << "\" file=\"" << e.file
          << "\"/>\n";
    out << "  </Collection>\n</VTKFile>\n";
    if (!out) throw Error("cannot write " + file_.string());
  }
  fs::rename(tmp, file_);  // a reader never sees a half-written collection
  changed_ = false;
}

}  // namespace suffuse::detail
