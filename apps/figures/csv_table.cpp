// CSV tables for suffuse plot (see csv_table.hpp).
#include "csv_table.hpp"

#include <cstdlib>
#include <fstream>
#include <suffuse/error.hpp>
#include <system_error>

namespace suffuse::plot {

namespace fs = std::filesystem;

namespace {

std::string trim(const std::string& s) {
  const auto first = s.find_first_not_of(" \t\r");
  if (first == std::string::npos) return "";
  return s.substr(first, s.find_last_not_of(" \t\r") - first + 1);
}

// One line of comma-separated cells; a cell may be quoted ("a, b", "say ""x""").
std::vector<std::string> split_csv_line(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (std::size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c == '"' && i + 1 < line.size() && line[i + 1] == '"') cells.back() += '"', ++i;
      else if (c == '"') quoted = false;
      else cells.back() += c;
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      cells.emplace_back();
    } else {
      cells.back() += c;
    }
  }
  for (auto& cell : cells) cell = trim(cell);
  return cells;
}

std::string list_columns(const std::vector<std::string>& header) {
  std::string s;
  for (const auto& h : header) s += (s.empty() ? "" : ", ") + ("'" + h + "'");
  return s;
}

}  // namespace

CsvFile read_csv(const fs::path& path) {
  std::error_code ec;
  if (!fs::exists(path, ec)) throw Error("cannot read " + path.string() + ": no such file");
  if (fs::is_directory(path, ec)) throw Error("cannot read " + path.string() + ": it is a directory");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot read " + path.string());
  CsvFile csv{path, {}, {}, {}};
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (trim(line).empty()) continue;
    if (csv.header.empty()) {
      if (number == 1 && line.rfind("\xEF\xBB\xBF", 0) == 0) line.erase(0, 3);  // a UTF-8 byte order mark
      csv.header = split_csv_line(line);
      continue;
    }
    csv.rows.push_back(split_csv_line(line));
    csv.line_numbers.push_back(number);
  }
  if (in.bad()) throw Error("cannot read " + path.string());
  if (csv.header.empty()) throw Error(path.string() + " is empty (a header row and data rows were expected)");
  if (csv.rows.empty()) throw Error(path.string() + " has a header but no data rows");
  return csv;
}

std::size_t find_column(const CsvFile& csv, const std::string& name) {
  for (std::size_t c = 0; c < csv.header.size(); ++c)
    if (csv.header[c] == name) return c;
  std::vector<std::size_t> found;
  for (std::size_t c = 0; c < csv.header.size(); ++c) {
    const auto bracket = csv.header[c].find(" [");
    if (bracket != std::string::npos && trim(csv.header[c].substr(0, bracket)) == name) found.push_back(c);
  }
  if (found.size() == 1) return found[0];
  if (found.empty())
    throw Error(csv.path.string() + " has no column '" + name + "'; its columns are: " + list_columns(csv.header));
  std::vector<std::string> names;
  for (auto c : found) names.push_back(csv.header[c]);
  throw Error("column '" + name + "' is ambiguous in " + csv.path.string() + ": " + list_columns(names) +
              "; give the whole header");
}

double parse_cell(const CsvFile& csv, std::size_t row, std::size_t column) {
  const auto& cells = csv.rows[row];
  const std::string where = csv.path.string() + ", line " + std::to_string(csv.line_numbers[row]);
  if (column >= cells.size())
    throw Error(where + " has " + std::to_string(cells.size()) + " cell(s) but the header has " +
                std::to_string(csv.header.size()) + "; column '" + csv.header[column] + "' is missing");
  const std::string& text = cells[column];
  const char* begin = text.c_str();
  char* end = nullptr;
  const double v = std::strtod(begin, &end);
  if (text.empty() || end != begin + text.size())
    throw Error(where + ", column '" + csv.header[column] + "': '" + text + "' is not a number");
  return v;
}

}  // namespace suffuse::plot
