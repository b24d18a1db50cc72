#pragma once
// Tables from CSV files that name each column's unit in their header
// ("x [m], y [m]", "time [h], level [m]"): read into SI units, each row's
// line kept for messages. Blank lines and lines that start with # are
// skipped. Problems throw suffuse::Error naming the file and the line.
#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace suffuse::detail {

enum class Quantity {
  length,  // m, cm, mm
  time,    // s, min, h, d (a day of 86,400 s)
  count,   // no unit: whole numbers (a ring's number)
  named,   // exactly the column's own unit (UnitColumn::unit: Pa, m/s, ...)
};

// SI units per `unit` of `quantity` (0.01 for cm, 3600 for h), 0 if `unit`
// is not one of its units.
double si_per(const std::string& unit, Quantity quantity);
// The units of a quantity, for messages: "m, cm or mm".
std::string units_of(Quantity quantity);

struct UnitColumn {
  std::string name;  // as a header should name it, e.g. "x"
  Quantity quantity;
  bool optional = false;  // the last columns may be left out of the header
  std::string unit;       // Quantity::named: the one unit accepted
};

struct UnitTable {
  std::vector<std::vector<double>> rows;  // SI; as many values as the header's columns
  std::vector<std::size_t> lines;         // each row's line in the file
  std::size_t columns = 0;                // in the header
};

// At most max_bytes; the header's columns are `columns` in order (their
// names not checked, their units are).
UnitTable read_unit_table(const std::filesystem::path& file, const std::vector<UnitColumn>& columns,
                          std::size_t max_bytes = std::size_t{16} << 20);

// CSV cells, shared with the PSD files' reader.
std::string trim(const std::string& s);
std::vector<std::string> split_cells(const std::string& line);
// The unit of a header cell: "size [mm]", "size (mm)" or "size_mm"; "" if none.
std::string unit_of(const std::string& cell);
bool parse_number(const std::string& cell, double& value);

}  // namespace suffuse::detail
