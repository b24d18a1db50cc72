#pragma once
// A value that varies in time (a hydrograph's level, a head, a flux, a
// load): linear between (time, value) points, held before the first and
// after the last. A scene gives it as a number (constant), a table
// [[time, value], ...] (seconds) or a CSV file with units ("time [h], head
// [m]"; docs/boundaries.md); plugins declare it with
// ParameterSchema::time_series and read it with Parameters::time_series.
#include <span>
#include <vector>

namespace suffuse {

class TimeFunction {
 public:
  TimeFunction() = default;
  explicit TimeFunction(double constant) : times_{0.0}, values_{constant} {}
  // Points row after row: time, value, time, value, ... (times increasing).
  explicit TimeFunction(std::span<const double> rows);

  double operator()(double time) const;
  bool constant() const { return times_.size() <= 1; }
  // The value before any time: the first row's.
  double initial() const { return values_.empty() ? 0.0 : values_.front(); }

 private:
  std::vector<double> times_, values_;
};

}  // namespace suffuse
