// PSD files: a CSV table with its units in the header, or a JSON object with
// a size unit and the points. Every problem names the file and the line (CSV)
// or JSON pointer, what was expected and what was found.
#include <cctype>
#include <fstream>
#include <sstream>

#include "suffuse/diagnostics.hpp"
#include "suffuse/gradation.hpp"
#include "common/unit_table.hpp"
#include "scene/validation.hpp"

namespace suffuse {

namespace fs = std::filesystem;

using detail::parse_number;
using detail::split_cells;
using detail::trim;
using detail::unit_of;

namespace {

constexpr std::uintmax_t max_psd_bytes = 1u << 20;  // a sieve analysis has tens of rows, not megabytes

[[noreturn]] void fail(const std::string& where, const std::string& problem, const std::string& expected,
                       const std::string& found) {
  throw Error(where + ": " + problem + ": expected " + expected + ", found " + found);
}

std::string read_text(const fs::path& file) {
  std::error_code ec;
  const auto size = fs::file_size(file, ec);
  if (ec) throw Error("cannot read PSD file " + file.string() + ": " + ec.message());
  if (size > max_psd_bytes)
    fail(file.string(), "file too large", "at most " + std::to_string(max_psd_bytes >> 10) + " KiB",
         std::to_string(size) + " bytes");
  std::ifstream in(file, std::ios::binary);
  if (!in) throw Error("cannot read PSD file " + file.string());
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::string quote(const std::string& s) { return std::string(1, '"').append(s).append(1, '"'); }

std::string lower(std::string s) {
  for (char& c : s) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return s;
}

// Millimetres per unit of size, or 0 for a unit that is not one.
double millimetres_per(const std::string& unit) {
  if (unit == "mm") return 1;
  if (unit == "um" || unit == "\xC2\xB5m" || unit == "\xCE\xBCm") return 1e-3;  // um, µm (micro sign, mu)
  if (unit == "m") return 1e3;
  return 0;
}

constexpr const char* size_units = "mm, um or m";

Gradation read_csv(const fs::path& file) {
  const std::string name = file.string();
  std::istringstream in(read_text(file));
  std::string line;
  std::size_t number = 0;
  std::vector<std::array<double, 2>> rows;
  std::vector<std::size_t> lines;  // of each row
  double scale = 0;                // mm per size unit, 0 until the header is read
  while (std::getline(in, line)) {
    ++number;
    if (!line.empty() && line.back() == '\r') line.pop_back();
    const std::string t = trim(line);
    if (t.empty() || t.front() == '#') continue;  // blank lines and comments
    const std::string where = name + ":" + std::to_string(number);
    const std::vector<std::string> cells = split_cells(t);
    if (scale == 0) {
      const std::string expected = "a header \"size [mm], passing [%]\" (size in " + std::string(size_units) +
                                   ", percent passing in %)";
      if (cells.size() != 2) fail(where, "header without two columns", expected, quote(t));
      scale = millimetres_per(unit_of(cells[0]));
      if (scale == 0) fail(where, "size unit missing or unknown", expected, quote(cells[0]));
      if (unit_of(cells[1]) != "%" && lower(cells[1]).find("percent") == std::string::npos)
        fail(where, "percent-passing unit missing", expected, quote(cells[1]));
      continue;
    }
    if (cells.size() != 2)
      fail(where, "wrong number of columns", "2 (size, percent passing)", std::to_string(cells.size()));
    std::array<double, 2> row{};
    for (int c = 0; c < 2; ++c)
      if (!parse_number(cells[c], row[c]))
        fail(where, "not a number", c == 0 ? "a particle size" : "a percent passing", quote(cells[c]));
    rows.push_back({row[0] * scale, row[1]});
    lines.push_back(number);
  }
  if (scale == 0) fail(name, "empty PSD file", "a header \"size [mm], passing [%]\" and at least 3 rows", "nothing");
  if (auto p = check_gradation(rows)) {
    const std::string where = p->row < lines.size() ? name + ":" + std::to_string(lines[p->row]) : name;
    fail(where, p->problem, p->expected, p->found);
  }
  return Gradation(rows, name);
}

Gradation read_json(const fs::path& file) {
  const std::string name = file.string();
  detail::Json root;
  try {
    root = detail::parse_scene_text(read_text(file), name);
  } catch (const SceneError& e) {  // the parser's words, said of a PSD file rather than a scene
    const Diagnostic& d = e.diagnostics().front();
    fail(name, d.problem, d.expected, d.found);
  }
  const std::string expected = "{\"size_unit\": \"mm\", \"points\": [[size, percent passing], ...]}";
  if (!root.is_object()) fail(name + ": /", "units missing", expected, detail::show(root));
  if (!root.contains("size_unit")) fail(name + ": /size_unit", "size unit missing", size_units, "nothing");
  const detail::Json& unit = root["size_unit"];
  const double scale = unit.is_string() ? millimetres_per(unit.get<std::string>()) : 0;
  if (scale == 0) fail(name + ": /size_unit", "unknown size unit", size_units, detail::show(unit));
  for (const auto& [key, value] : root.items())
    if (key != "size_unit" && key != "points")
      fail(name + ": /" + key, "unknown key", "one of {size_unit, points}", quote(key));
  if (!root.contains("points") || !root["points"].is_array())
    fail(name + ": /points", "points missing", "an array of [size, percent passing] pairs",
         root.contains("points") ? detail::show(root["points"]) : "nothing");
  const detail::Json& points = root["points"];
  std::vector<std::array<double, 2>> rows;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const std::string ptr = "/points/" + std::to_string(i);
    const detail::Json& pair = points[i];
    if (!pair.is_array() || pair.size() != 2 || !pair[0].is_number() || !pair[1].is_number())
      fail(name + ": " + ptr, "not a pair of numbers", "[size, percent passing]", detail::show(pair));
    rows.push_back({pair[0].get<double>() * scale, pair[1].get<double>()});
  }
  if (auto p = check_gradation(rows)) {
    const std::string ptr = p->column < 0 ? "/points" : "/points/" + std::to_string(p->row) + "/" +
                                                            std::to_string(p->column);
    fail(name + ": " + ptr, p->problem, p->expected, p->found);
  }
  return Gradation(rows, name);
}

}  // namespace

Gradation read_gradation_file(const fs::path& file) {
  const std::string extension = lower(file.extension().string());
  if (extension == ".csv") return read_csv(file);
  if (extension == ".json") return read_json(file);
  fail(file.string(), "unknown PSD file type", "a .csv or .json file", quote(file.extension().string()));
}

}  // namespace suffuse
