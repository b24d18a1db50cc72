#pragma once
// Internal stability of a gradation: the published geometric criteria that
// say, from the particle-size distribution alone, whether seepage can wash a
// soil's fines out through the voids of its coarse skeleton (suffusion).
// Each criterion gets a gradation and returns its governing value, where on
// the curve it occurs, its verdict, and its applicability limits; one outside
// its limits says why instead of answering. Forms, boundaries and sources:
// docs/gradation.md and the comments of internal_stability.cpp.
#include <array>
#include <cmath>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "suffuse/gradation.hpp"

namespace suffuse {

enum class Verdict { stable, transitional, unstable, not_applicable, not_evaluated };
std::string to_string(Verdict verdict);  // "stable", ..., "not applicable", "no verdict"

struct CriterionResult {
  std::string id;        // for scripts: "kezdi", "kenney_lau_1986", ...
  std::string name;      // "Kezdi (1979)"
  std::string quantity;  // what `value` is, e.g. "max D'15/d'85"
  double value = NAN;    // the governing value (NaN when not applicable)
  std::string boundary;  // the published boundary the value is compared with
  Verdict verdict = Verdict::not_applicable;
  std::string applicability;                         // the limits checked, or why it does not apply
  double at_size_mm = NAN, at_passing = NAN;         // where it occurs: D and F (NaN: a whole-curve index)
  std::vector<std::pair<std::string, double>> also;  // the other numbers it used, e.g. {"h''", 12.8}
};

// A stretch of the curve where nothing more passes (a gap in the sizes),
// between 0 and 100 percent passing.
struct Gap {
  double from_mm = 0, to_mm = 0;  // the sizes missing
  double passing = 0;             // fraction finer than the gap
  double ratio() const { return to_mm / from_mm; }
};

struct InternalStability {
  std::vector<CriterionResult> criteria;
  double cu = NAN;               // D60 / D10 (NaN when the curve does not reach down to 10 %)
  double shape_curve_limit = 0;  // F up to which the shape curve is examined: 0.2 (Cu > 3) or 0.3
  std::optional<Gap> gap;        // the widest gap, if any
  double erodible_fines = 0;     // fraction finer than the split the criteria identify [-]
  std::string erodible_fines_rule;  // which rule gave it

  // Some criterion within its limits finds the soil unstable.
  bool unstable() const;
  // Every criterion within its limits that gives a verdict finds the soil
  // stable, and at least one does.
  bool stable() const;
};

InternalStability assess_internal_stability(const Gradation& gradation);

// The Kenney-Lau shape curve: points (F, H) with F the fraction finer than D
// and H the fraction between D and 4D, at every breakpoint of the curve
// (exact: in between, both are linear in log D). For figures.
std::vector<std::array<double, 2>> shape_curve(const Gradation& gradation);

}  // namespace suffuse
