#include "common/unit_table.hpp"

#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "suffuse/error.hpp"

namespace suffuse::detail {

namespace fs = std::filesystem;

namespace {

[[noreturn]] void fail(const std::string& where, const std::string& problem, const std::string& expected,
                       const std::string& found) {
  throw Error(where + ": " + problem + ": expected " + expected + ", found " + found);
}

std::string quote(const std::string& s) { return std::string(1, '"').append(s).append(1, '"'); }

std::string header_of(const std::vector<UnitColumn>& columns) {
  std::string h;
  for (const UnitColumn& c : columns) {
    h += (h.empty() ? "" : ", ") + c.name;
    if (c.quantity == Quantity::length) h += " [m]";
    if (c.quantity == Quantity::time) h += " [s]";
    if (c.quantity == Quantity::named) h += " [" + c.unit + "]";
  }
  return quote(h);
}

}  // namespace

double si_per(const std::string& unit, Quantity quantity) {
  switch (quantity) {
    case Quantity::length:
      return unit == "m" ? 1 : unit == "cm" ? 0.01 : unit == "mm" ? 0.001 : 0;
    case Quantity::time:
      return unit == "s" ? 1 : unit == "min" ? 60 : unit == "h" ? 3600 : unit == "d" ? 86400 : 0;
    case Quantity::count:
      return unit.empty() ? 1 : 0;
    case Quantity::named:
      return 0;  // read_unit_table compares with the column's unit
  }
  return 0;
}

std::string units_of(Quantity quantity) {
  switch (quantity) {
    case Quantity::length: return "m, cm or mm";
    case Quantity::time: return "s, min, h or d";
    case Quantity::count: return "no unit";
    case Quantity::named: return "its unit";
  }
  return "?";
}

std::string trim(const std::string& s) {
  std::size_t a = 0, b = s.size();
  while (a < b && std::isspace(static_cast<unsigned char>(s[a]))) ++a;
  while (b > a && std::isspace(static_cast<unsigned char>(s[b - 1]))) --b;
  return s.substr(a, b - a);
}

std::vector<std::string> split_cells(const std::string& line) {
  std::vector<std::string> cells;
  std::string cell;
  std::istringstream in(line);
  while (std::getline(in, cell, ',')) cells.push_back(trim(cell));
  if (!line.empty() && line.back() == ',') cells.push_back("");
  return cells;
}

std::string unit_of(const std::string& cell) {
  const char close = cell.empty() ? 0 : cell.back();
  if (close == ']' || close == ')') {
    const std::size_t open = cell.rfind(close == ']' ? '[' : '(');
    if (open != std::string::npos) return trim(cell.substr(open + 1, cell.size() - open - 2));
  }
  const std::size_t underscore = cell.rfind('_');
  return underscore == std::string::npos ? "" : cell.substr(underscore + 1);
}

bool parse_number(const std::string& cell, double& value) {
  const std::string t = trim(cell);
  if (t.empty()) return false;
  std::istringstream in(t);
  in >> value;
  return in && in.peek() == std::char_traits<char>::eof();
}

UnitTable read_unit_table(const fs::path& file, const std::vector<UnitColumn>& columns, std::size_t max_bytes) {
  const std::string name = file.string();
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (ec) throw Error("cannot read " + name + ": " + ec.message());
  if (size > max_bytes)
    fail(name, "file too large", "at most " + std::to_string(max_bytes >> 10) + " KiB", std::to_string(size) + " bytes");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error("cannot read " + name);

  UnitTable table;
  std::vector<double> scale;
  std::string line;
  std::size_t number = 0;
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;
    const std::string where = name + ":" + std::to_string(number);
    const std::vector<std::string> cells = split_cells(t);
    if (scale.empty()) {  // the header
      std::size_t required = 0;
      for (const UnitColumn& c : columns) required += !c.optional;
      if (cells.size() < required || cells.size() > columns.size())
        fail(where, "wrong number of columns in the header", "a header " + header_of(columns), quote(t));
      for (std::size_t c = 0; c < cells.size(); ++c) {
        const UnitColumn& column = columns[c];
        const double s = column.quantity == Quantity::named ? (unit_of(cells[c]) == column.unit ? 1.0 : 0.0)
                                                             : si_per(unit_of(cells[c]), column.quantity);
        if (s == 0)
          fail(where, "unit missing or unknown",
               column.name + " in " + (column.quantity == Quantity::named ? column.unit : units_of(column.quantity)) +
                   " (" + header_of(columns) + ")",
               quote(cells[c]));
        scale.push_back(s);
      }
      table.columns = cells.size();
      continue;
    }
    if (cells.size() != table.columns)
      fail(where, "wrong number of columns", std::to_string(table.columns) + ", as in the header",
           std::to_string(cells.size()));
    std::vector<double> row(cells.size());
    for (std::size_t c = 0; c < cells.size(); ++c) {
      if (!parse_number(cells[c], row[c]) || !std::isfinite(row[c]))
        fail(where, "not a number", "a finite " + columns[c].name, quote(cells[c]));
      if (columns[c].quantity == Quantity::count && row[c] != std::floor(row[c]))
        fail(where, "not a whole number", "a whole " + columns[c].name, quote(cells[c]));
      row[c] *= scale[c];
      if (!std::isfinite(row[c]))
        fail(where, "number too large", "a " + columns[c].name + " finite in SI units", quote(cells[c]));
    }
    table.rows.push_back(std::move(row));
    table.lines.push_back(number);
  }
  if (scale.empty()) fail(name, "empty file", "a header " + header_of(columns) + " and rows", "nothing");
  return table;
}

}  // namespace suffuse::detail
