#include "suffuse/parameters.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "suffuse/error.hpp"

namespace suffuse {

namespace {
std::string number_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}
}  // namespace

std::string to_string(ParamType type) {
  switch (type) {
    case ParamType::Number: return "number";
    case ParamType::Integer: return "integer";
    case ParamType::Boolean: return "boolean";
    case ParamType::String: return "string";
    case ParamType::Choice: return "string";
    case ParamType::Vector: return "array of numbers";
    case ParamType::StringList: return "array of strings";
    case ParamType::Table: return "array of rows of numbers";
    case ParamType::Tables: return "array of arrays of rows of numbers";
    case ParamType::TimeSeries: return "number, [[time, value], ...] or CSV file";
  }
  return "?";
}

std::string to_string(const ParamValue& value) {
  struct Visitor {
    std::string operator()(double v) const { return number_text(v); }
    std::string operator()(long long v) const { return std::to_string(v); }
    std::string operator()(bool v) const { return v ? "true" : "false"; }
    std::string operator()(const std::string& v) const { return "\"" + v + "\""; }
    std::string operator()(const std::vector<double>& v) const {
      std::string s = "[";
      for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + number_text(v[i]);
      return s + "]";
    }
    std::string operator()(const std::vector<std::vector<double>>& v) const {
      std::string s = "[";
      for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", " : "") + (*this)(v[i]);
      return s + "]";
    }
    std::string operator()(const std::vector<std::string>& v) const {
      std::string s = "[";
      for (std::size_t i = 0; i < v.size(); ++i) s += (i ? ", \"" : "\"") + v[i] + "\"";
      return s + "]";
    }
  };
  return std::visit(Visitor{}, value);
}

std::string Param::expectation(int dimension) const {
  std::string text;
  if (type == ParamType::Choice) {
    text = "one of {";
    for (std::size_t i = 0; i < choices.size(); ++i) text += (i ? ", " : "") + choices[i];
    text += "}";
    return text;
  }
  if (type == ParamType::TimeSeries) {
    text = "a number, a table [[time [s], value], ...] (times increasing) or a CSV file with units";
  } else if (type == ParamType::Table || type == ParamType::Tables) {
    text = "array of [" + std::string(length == 2 ? "number, number" : std::to_string(length) + " numbers") + "] rows";
    if (type == ParamType::Tables) text = "array of arrays of [" + text.substr(10);
  } else if (type == ParamType::Vector) {
    int n = length > 0 ? length : dimension;
    text = n > 0 ? "array of " + std::to_string(n) + " numbers" : "array of numbers (one per dimension)";
  } else {
    text = to_string(type);
  }
  const bool has_min = std::isfinite(min), has_max = std::isfinite(max);
  if (has_min && has_max) {
    text += " in " + std::string(min_exclusive ? "(" : "[") + number_text(min) + ", " +
            number_text(max) + (max_exclusive ? ")" : "]");
  } else if (has_min) {
    text += std::string(min_exclusive ? " > " : " >= ") + number_text(min);
  } else if (has_max) {
    text += std::string(max_exclusive ? " < " : " <= ") + number_text(max);
  }
  if (!unit.empty()) text += " [" + unit + "]";
  return text;
}

Param& ParameterSchema::add(std::string name, ParamType type) {
  for (const Param& p : params_)
    if (p.name == name) throw Error("parameter '" + name + "' declared twice in one schema");
  Param p;
  p.name = std::move(name);
  p.type = type;
  params_.push_back(std::move(p));
  return params_.back();
}

const Param* ParameterSchema::find(const std::string& name) const {
  for (const Param& p : params_)
    if (p.name == name) return &p;
  return nullptr;
}

const ParamValue& Parameters::get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end())
    throw Error("parameter '" + name + "' was not declared in the schema or has no value");
  return it->second;
}

double Parameters::number(const std::string& name) const {
  const ParamValue& v = get(name);
  if (const auto* i = std::get_if<long long>(&v)) return static_cast<double>(*i);
  return std::get<double>(v);
}
long long Parameters::integer(const std::string& name) const { return std::get<long long>(get(name)); }
bool Parameters::boolean(const std::string& name) const { return std::get<bool>(get(name)); }
const std::string& Parameters::string(const std::string& name) const {
  return std::get<std::string>(get(name));
}
const std::vector<double>& Parameters::vector(const std::string& name) const {
  return std::get<std::vector<double>>(get(name));
}
const std::vector<std::string>& Parameters::string_list(const std::string& name) const {
  return std::get<std::vector<std::string>>(get(name));
}
const std::vector<std::vector<double>>& Parameters::tables(const std::string& name) const {
  return std::get<std::vector<std::vector<double>>>(get(name));
}
TimeFunction Parameters::time_series(const std::string& name) const {
  const ParamValue& v = get(name);
  if (const double* constant = std::get_if<double>(&v)) return TimeFunction(*constant);
  return TimeFunction(std::get<std::vector<double>>(v));
}

TimeFunction::TimeFunction(std::span<const double> rows) {
  for (std::size_t k = 0; k + 1 < rows.size(); k += 2) {
    if (!times_.empty() && !(rows[k] > times_.back()))
      throw Error("a time function's times must increase: " + number_text(rows[k]) + " s after " +
                  number_text(times_.back()) + " s");
    times_.push_back(rows[k]);
    values_.push_back(rows[k + 1]);
  }
}

double TimeFunction::operator()(double time) const {
  if (times_.empty()) return 0.0;
  if (!(time > times_.front())) return values_.front();
  if (time >= times_.back()) return values_.back();
  const std::size_t k = static_cast<std::size_t>(std::upper_bound(times_.begin(), times_.end(), time) - times_.begin());
  const double t0 = times_[k - 1], t1 = times_[k];
  return values_[k - 1] + (time - t0) / (t1 - t0) * (values_[k] - values_[k - 1]);
}
std::optional<double> Parameters::maybe_number(const std::string& name) const {
  if (!has(name)) return std::nullopt;
  return number(name);
}

Parameters ParameterSchema::complete(std::map<std::string, ParamValue> values) const {
  for (const auto& [name, value] : values) {
    const Param* p = find(name);
    if (!p) throw Error("parameter '" + name + "' is not declared by the schema");
    // value passed on: clang before 16 cannot capture a structured binding.
    const bool type_ok = [p](const ParamValue& value) {
      switch (p->type) {
        case ParamType::Number: return std::holds_alternative<double>(value);
        case ParamType::Integer: return std::holds_alternative<long long>(value);
        case ParamType::Boolean: return std::holds_alternative<bool>(value);
        case ParamType::String:
        case ParamType::Choice: return std::holds_alternative<std::string>(value);
        case ParamType::Vector: return std::holds_alternative<std::vector<double>>(value);
        case ParamType::StringList: return std::holds_alternative<std::vector<std::string>>(value);
        case ParamType::Table: return std::holds_alternative<std::vector<double>>(value);
        case ParamType::Tables: return std::holds_alternative<std::vector<std::vector<double>>>(value);
        case ParamType::TimeSeries:
          return std::holds_alternative<double>(value) || std::holds_alternative<std::vector<double>>(value);
      }
      return false;
    }(value);
    if (!type_ok) throw Error("parameter '" + name + "': expected " + p->expectation(3));
    if (p->type == ParamType::Number || p->type == ParamType::Integer) {
      const double v = p->type == ParamType::Number ? std::get<double>(value)
                                                    : static_cast<double>(std::get<long long>(value));
      const bool low = p->min_exclusive ? !(v > p->min) : !(v >= p->min);
      const bool high = p->max_exclusive ? !(v < p->max) : !(v <= p->max);
      if (low || high) throw Error("parameter '" + name + "' = " + to_string(value) + ": expected " + p->expectation(3));
    }
    if (p->type == ParamType::Choice &&
        std::find(p->choices.begin(), p->choices.end(), std::get<std::string>(value)) == p->choices.end())
      throw Error("parameter '" + name + "' = " + to_string(value) + ": expected " + p->expectation(3));
  }
  for (const Param& p : params_) {
    if (values.count(p.name)) continue;
    if (p.default_value) {
      values.emplace(p.name, *p.default_value);
    } else if (p.required()) {
      throw Error("missing required parameter '" + p.name + "': " + p.expectation(3));
    }
  }
  return Parameters(std::move(values));
}

}  // namespace suffuse
