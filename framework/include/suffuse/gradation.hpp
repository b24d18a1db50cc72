#pragma once
// A particle-size distribution (PSD, gradation curve): percent passing by
// mass against particle size, as a sieve analysis gives it.
//
// Between the measured points the curve is interpolated linearly in log D:
// F(D) = F_i + (F_{i+1} - F_i) log(D / D_i) / log(D_{i+1} / D_i). This is how
// gradations are drawn and read (semi-log chart) and how the USACE RMC
// Internal Instability Toolbox (2023, "Burenkova Method" worksheet)
// interpolates D90, D60 and D15, so values match the toolbox's. It is
// monotone by construction and cannot overshoot the data; a smoother monotone
// cubic would invent curvature the sieve data do not have, and gap-graded
// soils (a flat stretch of the curve) are represented exactly.
//
// Sizes are in millimetres throughout; passing is a fraction in [0, 1].
#include <array>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

namespace suffuse {

// One problem with a table of (size [mm], percent passing [%]) rows: which
// row (0-based) and column (0 size, 1 percent passing, -1 the whole table).
struct GradationProblem {
  std::size_t row = 0;
  int column = -1;
  std::string problem, expected, found;
};

// The order a table lists its sieves in: laboratory sheets list them from
// the largest down, plots and most codes from the smallest up. Both are
// read; the first and last sizes tell which.
enum class SieveOrder { smallest_first, largest_first };
SieveOrder sieve_order(const std::vector<std::array<double, 2>>& rows_mm_percent);
const char* describe(SieveOrder order);  // "smallest sieve first", "largest sieve first"

// The first problem with the rows, in the table's own order, if any: at
// least three rows, sizes positive and strictly monotone, percent passing in
// [0, 100] and cumulative (never decreasing towards the larger sizes), and
// 100 at the largest size.
std::optional<GradationProblem> check_gradation(const std::vector<std::array<double, 2>>& rows_mm_percent);

class Gradation {
 public:
  // Rows of (size [mm], percent passing [%]), in either order; throws Error
  // naming `source` when check_gradation finds a problem (readers check
  // first, to name the file line or JSON pointer).
  Gradation(const std::vector<std::array<double, 2>>& rows_mm_percent, std::string source = "gradation");

  // F(D): fraction passing size D [mm]; below the smallest size, the fraction
  // passing it (nothing is known further down); 1 above the largest.
  double passing(double size_mm) const;
  // Which size has fraction `p` passing, for p in [smallest_passing(), 1]:
  // on a flat stretch (a gap), `lower` gives its start, `upper` its end.
  enum class Side { lower, upper };
  double size_at(double p, Side side = Side::lower) const;
  // D_p for p in percent (D60 = d(60)); NaN where the curve does not reach p.
  double d(double percent) const;

  double smallest_passing() const { return passing_.front(); }
  const std::vector<double>& sizes_mm() const { return sizes_; }
  const std::vector<double>& passing_points() const { return passing_; }
  const std::string& source() const { return source_; }
  // The order the rows were given in (sizes_mm() is always smallest first).
  SieveOrder order() const { return order_; }

 private:
  std::vector<double> sizes_, passing_;
  std::string source_;
  SieveOrder order_ = SieveOrder::smallest_first;
};

// Reads a PSD file: CSV (.csv) with a header naming both units, e.g.
// "size [mm], passing [%]" (size unit mm, um or m), or JSON (.json)
// {"size_unit": "mm", "points": [[size, percent passing], ...]}. Throws
// Error naming the file and line (CSV) or JSON pointer, what was expected
// and what was found.
Gradation read_gradation_file(const std::filesystem::path& file);

}  // namespace suffuse
