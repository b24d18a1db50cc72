#include "scene/validation.hpp"

#include <cmath>
#include <cstdio>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <vector>

#include "common/unit_table.hpp"
#include "scene/scene_reader.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

using json = Json;

std::string pointer_append(const std::string& pointer, const std::string& key) {
  std::string escaped;
  for (char c : key) {
    if (c == '~') escaped += "~0";
    else if (c == '/') escaped += "~1";
    else escaped += c;
  }
  return pointer + "/" + escaped;
}

std::string show(const json& value) {
  std::string text = value.dump();
  if (text.size() > 60) text = text.substr(0, 57) + "...";
  const char* kind = value.is_object()    ? "object "
                     : value.is_array()   ? "array "
                     : value.is_string()  ? "string "
                     : value.is_boolean() ? "boolean "
                     : value.is_null()    ? ""
                                          : "";
  return kind + text;
}

namespace {

bool in_range(const Param& p, double v) {
  if (p.min_exclusive ? !(v > p.min) : !(v >= p.min)) return false;
  if (p.max_exclusive ? !(v < p.max) : !(v <= p.max)) return false;
  return true;
}

// A table's rows of `columns` numbers, row after row into xs; the problem if
// a row is not an array of that many numbers, else null.
const char* rows_of(const json& table, int columns, std::vector<double>& xs) {
  for (const auto& row : table) {
    if (!row.is_array() || static_cast<int>(row.size()) != columns) return "wrong shape of a row";
    for (const auto& e : row) {
      if (!e.is_number()) return "wrong type of component";
      xs.push_back(e.get<double>());
    }
  }
  return nullptr;
}

// A value in time: a number, a table of (time, value) rows or a CSV file with
// units (time in s, min, h or d; the value in the parameter's unit, lengths
// also in cm or mm), into rows in seconds; the times increasing, every value
// in range. Returns the value, or nothing after appending a diagnostic.
std::optional<ParamValue> time_series(const json& v, const Param& p, const std::string& ptr, const std::string& by,
                                      std::vector<Diagnostic>& out, const std::filesystem::path& base_dir) {
  auto fail = [&](std::string at, const std::string& problem, const std::string& expected, const std::string& found) {
    out.push_back({std::move(at), problem, expected, found, by});
    return std::nullopt;
  };
  if (v.is_number()) {
    const double x = v.get<double>();
    if (!in_range(p, x)) return fail(ptr, "value out of range", p.expectation(0), show(v));
    return ParamValue{x};
  }
  std::vector<double> rows;
  std::vector<std::size_t> lines;  // a file's row's line, for messages
  std::string file_name;
  if (v.is_array()) {
    if (const char* problem = rows_of(v, 2, rows)) return fail(ptr, problem, p.expectation(0), show(v));
  } else if (v.is_string()) {
    std::filesystem::path file = v.get<std::string>();
    if (file.is_relative()) file = base_dir / file;
    const Quantity quantity = p.unit == "m" ? Quantity::length : Quantity::named;
    try {
      const UnitTable t = read_unit_table(file, {{"time", Quantity::time, false, ""}, {"value", quantity, false, p.unit}},
                                          std::size_t{16} << 20);
      for (const std::vector<double>& row : t.rows) rows.insert(rows.end(), row.begin(), row.end());
      lines = t.lines;
      file_name = file.string();
    } catch (const Error& e) {
      return fail(ptr, "unreadable time series", "a CSV file \"time [h], value [" + p.unit + "]\" (docs/boundaries.md)",
                  e.what());
    }
  } else {
    return fail(ptr, "wrong type", p.expectation(0), show(v));
  }
  if (rows.empty()) return fail(ptr, "empty time series", "at least one row (time, value)", "none");
  // Inline rows are named by their JSON path; a file's by the key that names
  // it, with the file's line.
  const bool from_file = v.is_string();
  auto at = [&](std::size_t k) { return from_file ? ptr : ptr + "/" + std::to_string(k); };
  auto line = [&](std::size_t k) { return from_file ? file_name + ":" + std::to_string(lines[k]) + ": " : std::string(); };
  for (std::size_t k = 0; 2 * k < rows.size(); ++k) {
    const double t = rows[2 * k], x = rows[2 * k + 1];
    if (k > 0 && !(t > rows[2 * k - 2]))
      return fail(at(k), "times not increasing", "a time after the previous row's " + format(rows[2 * k - 2]) + " s",
                  line(k) + format(t) + " s");
    if (!in_range(p, x)) return fail(at(k), "value out of range", p.expectation(0), line(k) + format(x));
  }
  return ParamValue{rows};
}

// Returns the value, or nothing after appending a diagnostic.
std::optional<ParamValue> convert(const json& v, const Param& p, const std::string& ptr, const std::string& by,
                                  int dim, std::vector<Diagnostic>& out, const std::filesystem::path& base_dir) {
  auto fail = [&](const std::string& problem) {
    out.push_back({ptr, problem, p.expectation(dim), show(v), by});
    return std::nullopt;
  };
  switch (p.type) {
    case ParamType::Number: {
      if (!v.is_number()) return fail("wrong type");
      double x = v.get<double>();
      if (!in_range(p, x)) return fail("value out of range");
      return ParamValue{x};
    }
    case ParamType::Integer: {
      if (!v.is_number_integer()) return fail("wrong type");
      long long x = v.get<long long>();
      if (!in_range(p, static_cast<double>(x))) return fail("value out of range");
      return ParamValue{x};
    }
    case ParamType::Boolean:
      if (!v.is_boolean()) return fail("wrong type");
      return ParamValue{v.get<bool>()};
    case ParamType::String:
      if (!v.is_string()) return fail("wrong type");
      return ParamValue{v.get<std::string>()};
    case ParamType::Choice: {
      if (!v.is_string()) return fail("wrong type");
      std::string s = v.get<std::string>();
      for (const auto& c : p.choices)
        if (c == s) return ParamValue{s};
      return fail("unknown choice");
    }
    case ParamType::Vector: {
      if (!v.is_array()) return fail("wrong type");
      const int n = p.length > 0 ? p.length : dim;
      if (n > 0 && static_cast<int>(v.size()) != n) return fail("wrong number of components");
      std::vector<double> xs;
      for (const auto& e : v) {
        if (!e.is_number()) return fail("wrong type of component");
        xs.push_back(e.get<double>());
        if (!in_range(p, xs.back())) return fail("component out of range");
      }
      return ParamValue{xs};
    }
    case ParamType::Table: {
      if (!v.is_array()) return fail("wrong type");
      std::vector<double> xs;
      if (const char* problem = rows_of(v, p.length, xs)) return fail(problem);
      return ParamValue{xs};
    }
    case ParamType::Tables: {
      if (!v.is_array()) return fail("wrong type");
      std::vector<std::vector<double>> tables;
      for (const auto& table : v) {
        if (!table.is_array()) return fail("wrong type of a table");
        if (const char* problem = rows_of(table, p.length, tables.emplace_back())) return fail(problem);
      }
      return ParamValue{tables};
    }
    case ParamType::TimeSeries:
      return time_series(v, p, ptr, by, out, base_dir);
    case ParamType::StringList: {
      if (!v.is_array()) return fail("wrong type");
      std::vector<std::string> xs;
      for (const auto& e : v) {
        if (!e.is_string()) return fail("wrong type of element");
        xs.push_back(e.get<std::string>());
      }
      return ParamValue{xs};
    }
  }
  return std::nullopt;
}

}  // namespace

Parameters validate_object(const json& node, const ParameterSchema& schema, const std::string& pointer,
                           const std::string& declared_by, int dim, std::vector<Diagnostic>& out,
                           const std::set<std::string>& reserved, const std::filesystem::path& base_dir) {
  std::map<std::string, ParamValue> values;
  if (!node.is_object()) {
    out.push_back({pointer, "wrong type", "object", show(node), declared_by});
    return Parameters{};
  }
  for (const auto& [key, value] : node.items()) {
    if (reserved.count(key)) continue;
    const std::string ptr = pointer_append(pointer, key);
    const Param* p = schema.find(key);
    if (!p) {
      std::string keys;
      for (const Param& q : schema.params()) keys += (keys.empty() ? "" : ", ") + q.name;
      for (const std::string& r : reserved) keys += (keys.empty() ? "" : ", ") + r;
      out.push_back({ptr, "unknown key", keys.empty() ? "no parameters" : "one of {" + keys + "}",
                     "\"" + key + "\"", declared_by});
      continue;
    }
    if (auto v = convert(value, *p, ptr, declared_by, dim, out, base_dir)) values[key] = *v;
  }
  for (const Param& p : schema.params()) {
    if (node.contains(p.name)) continue;
    if (p.default_value) {
      values[p.name] = *p.default_value;
    } else if (p.required()) {
      out.push_back({pointer_append(pointer, p.name), "missing required parameter", p.expectation(dim),
                     "nothing", declared_by});
    }
  }
  return Parameters{std::move(values)};
}

Json parse_scene_text(const std::string& text, const std::string& name) {
  auto refuse = [&](const std::string& problem, const std::string& expected, const std::string& found) {
    return SceneError(name, {{"", problem, expected, found, "core"}});
  };
  if (text.size() > max_scene_bytes)
    throw refuse("file too large", "at most " + std::to_string(max_scene_bytes >> 20) + " MiB",
                 std::to_string(text.size()) + " bytes");
  // Nesting depth, outside strings: nlohmann's values nest recursively.
  int depth = 0;
  bool in_string = false, escaped = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    const char c = text[i];
    if (in_string) {
      if (escaped) escaped = false;
      else if (c == '\\') escaped = true;
      else if (c == '"') in_string = false;
    } else if (c == '"') {
      in_string = true;
    } else if (c == '[' || c == '{') {
      if (++depth > max_scene_depth)
        throw refuse("nested too deeply", "at most " + std::to_string(max_scene_depth) + " levels of arrays and objects",
                     "more, at byte " + std::to_string(i));
    } else if (c == ']' || c == '}') {
      --depth;
    }
  }
  if (text.find_first_not_of(" \t\r\n") == std::string::npos)
    throw refuse("not valid JSON", "a JSON object", "an empty file");
  // Keys given twice in one object: nlohmann keeps the last silently, so a
  // second material or liquid of the same name would replace the first.
  struct Container {
    std::string pointer;
    bool object;
    std::set<std::string> keys;
    std::string key;        // objects: the key being read
    std::size_t count = 0;  // arrays: elements read
  };
  std::vector<Container> open;
  std::optional<std::pair<std::string, std::string>> duplicate;  // pointer, key
  auto child_pointer = [&]() {
    if (open.empty()) return std::string();
    const Container& c = open.back();
    return pointer_append(c.pointer, c.object ? c.key : std::to_string(c.count));
  };
  auto element_done = [&]() {
    if (!open.empty() && !open.back().object) ++open.back().count;
  };
  const Json::parser_callback_t track = [&](int, Json::parse_event_t event, Json& parsed) {
    using E = Json::parse_event_t;
    switch (event) {
      case E::object_start:
      case E::array_start:
        open.push_back({child_pointer(), event == E::object_start, {}, {}, 0});
        break;
      case E::key: {
        Container& c = open.back();
        c.key = parsed.get<std::string>();
        if (!c.keys.insert(c.key).second && !duplicate) duplicate = {pointer_append(c.pointer, c.key), c.key};
        break;
      }
      case E::object_end:
      case E::array_end:
        open.pop_back();
        element_done();
        break;
      case E::value:
        element_done();
        break;
    }
    return true;
  };
  Json root;
  try {
    root = Json::parse(text, track);
  } catch (const Json::exception& e) {
    // "[json.exception.parse_error.101] parse error at line 1, ...": the part after the tag.
    std::string what = e.what();
    if (const auto tag = what.find("] "); what.rfind("[json.exception.", 0) == 0 && tag != std::string::npos)
      what = what.substr(tag + 2);
    if (e.id == 406) what += " (a number beyond the range of a double is not finite)";
    // The message quotes the bytes it read: show any that are not printable ASCII as \xNN.
    std::string shown;
    for (unsigned char c : what) {
      if (c >= 0x20 && c < 0x7f) {
        shown += static_cast<char>(c);
      } else {
        char hex[5];
        std::snprintf(hex, sizeof hex, "\\x%02X", c);
        shown += hex;
      }
    }
    throw refuse("not valid JSON", "a JSON object", shown);
  }
  if (duplicate)
    throw SceneError(name, {{duplicate->first, "duplicate key", "each key once in its object",
                             "\"" + duplicate->second + "\" twice", "core"}});
  return root;
}

std::string read_scene_file(const std::filesystem::path& file) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(file, ec);
  if (!ec && size > max_scene_bytes)
    throw SceneError(file.string(), {{"", "file too large", "at most " + std::to_string(max_scene_bytes >> 20) + " MiB",
                                      std::to_string(size) + " bytes", "core"}});
  std::ifstream in(file);
  if (!in) throw Error("cannot read scene file " + file.string());
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

}  // namespace suffuse::detail
