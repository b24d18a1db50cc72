// The gradation curve: checks on its points and interpolation linear in log D
// (why linear in log D: suffuse/gradation.hpp).
#include "suffuse/gradation.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "suffuse/error.hpp"

namespace suffuse {

namespace {

std::string as_text(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

// Point on the segment from (d0, f0) to (d1, f1), linear in log D.
double size_between(double d0, double f0, double d1, double f1, double p) {
  const double t = (p - f0) / (f1 - f0);
  return d0 * std::pow(d1 / d0, t);
}

}  // namespace

SieveOrder sieve_order(const std::vector<std::array<double, 2>>& rows) {
  return rows.size() >= 2 && rows.front()[0] > rows.back()[0] ? SieveOrder::largest_first
                                                              : SieveOrder::smallest_first;
}

const char* describe(SieveOrder order) {
  return order == SieveOrder::largest_first ? "largest sieve first" : "smallest sieve first";
}

std::optional<GradationProblem> check_gradation(const std::vector<std::array<double, 2>>& rows) {
  if (rows.size() < 3)
    return GradationProblem{rows.size(), -1, "too few points", "at least 3 rows of (size, percent passing)",
                            std::to_string(rows.size()) + " row(s)"};
  // Rows in the file's order, either way round (the first and last sizes tell
  // which): each row is compared with the one listed before it.
  const bool down = sieve_order(rows) == SieveOrder::largest_first;
  const std::string order = std::string(" (") + describe(sieve_order(rows)) + ")";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const double size = rows[i][0], percent = rows[i][1];
    if (!std::isfinite(size) || size <= 0)
      return GradationProblem{i, 0, "size not positive", "a particle size > 0", as_text(size)};
    if (!std::isfinite(percent) || percent < 0 || percent > 100)
      return GradationProblem{i, 1, "percent passing outside 0-100", "a percent passing in [0, 100]", as_text(percent)};
    if (i == 0) continue;
    const double size_before = rows[i - 1][0], percent_before = rows[i - 1][1];
    if (down ? size >= size_before : size <= size_before)
      return GradationProblem{i, 0, down ? "sizes not decreasing" : "sizes not increasing",
                              std::string(down ? "a size below" : "a size above") + " the previous row's " +
                                  as_text(size_before) + order,
                              as_text(size)};
    if (down ? percent > percent_before : percent < percent_before)
      return GradationProblem{i, 1, down ? "percent passing increases" : "percent passing decreases",
                              std::string(down ? "at most" : "at least") + " the previous row's " +
                                  as_text(percent_before) + " (a cumulative curve)",
                              as_text(percent)};
  }
  const std::size_t largest = down ? 0 : rows.size() - 1;
  if (rows[largest][1] != 100)
    return GradationProblem{largest, 1, "the curve does not reach 100 percent passing",
                            "100 at the largest size (the whole sample passes it)", as_text(rows[largest][1])};
  return std::nullopt;
}

Gradation::Gradation(const std::vector<std::array<double, 2>>& rows, std::string source)
    : source_(std::move(source)), order_(sieve_order(rows)) {
  if (auto problem = check_gradation(rows))
    throw Error(source_ + ", point " + std::to_string(problem->row + 1) + ": " + problem->problem + ": expected " +
                problem->expected + ", found " + problem->found);
  for (const auto& [size, percent] : rows) {
    sizes_.push_back(size);
    passing_.push_back(percent / 100);
  }
  if (order_ == SieveOrder::largest_first) {
    std::reverse(sizes_.begin(), sizes_.end());
    std::reverse(passing_.begin(), passing_.end());
  }
}

double Gradation::passing(double size) const {
  if (size <= sizes_.front()) return passing_.front();
  if (size >= sizes_.back()) return 1;
  const std::size_t i = std::upper_bound(sizes_.begin(), sizes_.end(), size) - sizes_.begin();  // sizes_[i] > size
  const double t = std::log(size / sizes_[i - 1]) / std::log(sizes_[i] / sizes_[i - 1]);
  return passing_[i - 1] + t * (passing_[i] - passing_[i - 1]);
}

double Gradation::size_at(double p, Side side) const {
  const std::size_t n = sizes_.size();
  if (!(p >= passing_.front())) return NAN;  // nothing is known below the smallest size
  if (side == Side::lower) {
    // The first size with at least p passing.
    const std::size_t i = std::lower_bound(passing_.begin(), passing_.end(), p) - passing_.begin();
    if (i == 0) return sizes_.front();
    if (i == n) return sizes_.back();
    return size_between(sizes_[i - 1], passing_[i - 1], sizes_[i], passing_[i], p);
  }
  // The last size with at most p passing.
  const std::size_t j = std::upper_bound(passing_.begin(), passing_.end(), p) - passing_.begin();  // passing_[j] > p
  if (j == n) return sizes_.back();
  return size_between(sizes_[j - 1], passing_[j - 1], sizes_[j], passing_[j], p);
}

double Gradation::d(double percent) const { return size_at(percent / 100, Side::lower); }

}  // namespace suffuse
