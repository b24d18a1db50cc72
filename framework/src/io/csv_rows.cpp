// keep_csv_rows_until: how a CSV time series resumes after a restart.
#include <cmath>
#include <fstream>
#include <string>

#include "suffuse/error.hpp"
#include "suffuse/writer.hpp"

namespace suffuse {

namespace {

// The first cell of a row as a number, if it is one.
bool first_cell_number(const std::string& line, double& value) {
  const std::size_t end = line.find(',');
  const std::string cell = line.substr(0, end);
  if (cell.empty()) return false;
  char* stop = nullptr;
  value = std::strtod(cell.c_str(), &stop);
  return stop != cell.c_str() && *stop == '\0';
}

}  // namespace

bool keep_csv_rows_until(const std::filesystem::path& file, double time) {
  if (!std::filesystem::exists(file)) return false;
  std::ifstream in(file);
  if (!in) throw Error("cannot restart: cannot read " + file.string());
  const double tolerance = 1e-9 * std::max(1.0, std::abs(time));
  std::string kept, line;
  bool rows = false;
  while (std::getline(in, line)) {
    double t = 0;
    const bool row = first_cell_number(line, t);
    rows = rows || row;
    if (row ? t <= time + tolerance : !rows) kept += line + "\n";
  }
  in.close();
  const std::filesystem::path tmp = file.string() + ".part";
  {
    std::ofstream out(tmp);
    out << kept;
    if (!out) throw Error("cannot write " + file.string());
  }
  std::filesystem::rename(tmp, file);
  return true;
}

}  // namespace suffuse
