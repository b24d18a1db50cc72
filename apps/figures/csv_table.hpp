// CSV tables for suffuse plot: a header row, then rows of comma-separated
// cells (quoted cells allowed), as suffuse and spreadsheets write them. Cells
// stay text until a column is used, so that an error can name its line.
#pragma once

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

namespace suffuse::plot {

struct CsvFile {
  std::filesystem::path path;
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::size_t> line_numbers;  // of each row in the file, from 1 (the header is line 1)
};

// The header and data rows of PATH; blank lines are skipped. Throws
// suffuse::Error when the file is missing, empty or has no data rows.
CsvFile read_csv(const std::filesystem::path& path);

// The column NAME matches exactly, or by the part of the header before " [" (its unit).
// Throws suffuse::Error when no column or several match.
std::size_t find_column(const CsvFile& csv, const std::string& name);

// The number in ROW (an index into csv.rows) and COLUMN. Throws suffuse::Error
// with the file, line and column when the cell is missing or not a number.
double parse_cell(const CsvFile& csv, std::size_t row, std::size_t column);

}  // namespace suffuse::plot
