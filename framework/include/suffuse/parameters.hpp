#pragma once
// Parameter schemas: every plugin declares its parameters here, once.
// Validation, defaults, `suffuse describe` and the scene reference come from
// these declarations, never from hand-written checks.
#include <cstddef>
#include <deque>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <variant>
#include <vector>

#include "suffuse/time_function.hpp"

namespace suffuse {

enum class ParamType { Number, Integer, Boolean, String, Choice, Vector, StringList, Table, Tables, TimeSeries };

// A parameter value after validation.
// A Table is rows of numbers, each row `length` long, stored row after row;
// Tables are any number of such tables (the holes of a polygon). A
// TimeSeries is stored as a table of (time [s], value) rows, whatever the
// scene gave (a number, a table or a CSV file).
using ParamValue = std::variant<double, long long, bool, std::string, std::vector<double>, std::vector<std::string>,
                                std::vector<std::vector<double>>>;

// Declaration of one parameter. Built through the fluent setters of ParameterSchema.
struct Param {
  std::string name;
  ParamType type = ParamType::Number;
  std::string unit;  // SI unit, "-" for dimensionless, "" for non-numeric
  std::string description;
  std::optional<ParamValue> default_value;  // no default and not optional: required
  bool optional = false;                    // may be absent without a default
  double min = -std::numeric_limits<double>::infinity();
  double max = std::numeric_limits<double>::infinity();
  bool min_exclusive = false;
  bool max_exclusive = false;
  std::vector<std::string> choices;  // Choice
  int length = 0;                    // Vector: 0 means "one value per spatial dimension"; Table: columns

  // Fluent setters, used as schema.number("E").with_unit("Pa").above(0).doc("...").
  Param& with_unit(std::string u) { unit = std::move(u); return *this; }
  Param& doc(std::string d) { description = std::move(d); return *this; }
  Param& at_least(double v) { min = v; min_exclusive = false; return *this; }
  Param& above(double v) { min = v; min_exclusive = true; return *this; }
  Param& at_most(double v) { max = v; max_exclusive = false; return *this; }
  Param& below(double v) { max = v; max_exclusive = true; return *this; }
  Param& fallback(ParamValue v) { default_value = std::move(v); return *this; }
  Param& may_be_absent() { optional = true; return *this; }
  Param& of_length(int n) { length = n; return *this; }

  bool required() const { return !default_value && !optional; }
  // Human-readable form of the type and range, e.g. "number > 0" or "one of {left, right}".
  std::string expectation(int dimension) const;
};

class ParameterSchema {
 public:
  Param& number(std::string name) { return add(std::move(name), ParamType::Number); }
  Param& integer(std::string name) { return add(std::move(name), ParamType::Integer); }
  Param& boolean(std::string name) { return add(std::move(name), ParamType::Boolean); }
  Param& string(std::string name) { return add(std::move(name), ParamType::String); }
  Param& vector(std::string name) { return add(std::move(name), ParamType::Vector); }
  Param& string_list(std::string name) { return add(std::move(name), ParamType::StringList); }
  // Rows of `columns` numbers, e.g. [[0.1, 0], [0.2, 35]]: read with Parameters::vector, row after row.
  Param& table(std::string name, int columns) {
    Param& p = add(std::move(name), ParamType::Table);
    p.length = columns;
    return p;
  }
  // Any number of tables of `columns` numbers per row: read with Parameters::tables.
  Param& tables(std::string name, int columns) {
    Param& p = add(std::move(name), ParamType::Tables);
    p.length = columns;
    return p;
  }
  // A value in time: a number, a table [[time, value], ...] or a CSV file
  // with units beside the scene (docs/boundaries.md); with_unit gives the
  // value's unit, at_least and the like bound every value. Read with
  // Parameters::time_series.
  Param& time_series(std::string name) { return add(std::move(name), ParamType::TimeSeries); }
  Param& choice(std::string name, std::vector<std::string> choices) {
    Param& p = add(std::move(name), ParamType::Choice);
    p.choices = std::move(choices);
    return p;
  }

  const std::deque<Param>& params() const { return params_; }
  const Param* find(const std::string& name) const;

  // Parameters from values given in code, for a plugin's unit tests: unknown
  // keys, missing required keys, wrong types and numbers out of range throw
  // suffuse::Error; defaults are filled in. Scenes get the full validation.
  class Parameters complete(std::map<std::string, ParamValue> values) const;

 private:
  Param& add(std::string name, ParamType type);
  std::deque<Param> params_;  // deque: references returned by add() stay valid
};

// Validated parameters of one scene node, defaults filled in. Read them once,
// in the plugin's constructor, into a typed struct: never in the time loop.
class Parameters {
 public:
  Parameters() = default;
  explicit Parameters(std::map<std::string, ParamValue> values) : values_(std::move(values)) {}

  bool has(const std::string& name) const { return values_.count(name) != 0; }
  double number(const std::string& name) const;
  long long integer(const std::string& name) const;
  bool boolean(const std::string& name) const;
  const std::string& string(const std::string& name) const;
  const std::vector<double>& vector(const std::string& name) const;
  const std::vector<std::string>& string_list(const std::string& name) const;
  const std::vector<std::vector<double>>& tables(const std::string& name) const;
  TimeFunction time_series(const std::string& name) const;
  // Optional parameters without default.
  std::optional<double> maybe_number(const std::string& name) const;

  const std::map<std::string, ParamValue>& values() const { return values_; }

 private:
  const ParamValue& get(const std::string& name) const;
  std::map<std::string, ParamValue> values_;
};

std::string to_string(ParamType type);
std::string to_string(const ParamValue& value);

}  // namespace suffuse
