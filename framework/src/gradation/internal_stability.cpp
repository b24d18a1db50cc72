// The geometric internal-stability criteria, each with its published form,
// boundary and limits. "RMC manual" is the technical manual of the USACE Risk
// Management Center's Internal Instability Toolbox (RMC Internal Erosion
// Suite, 2023, v1.0), whose worksheets implement Burenkova, Wan and Fell and
// Li and Fannin; every number below is quoted from it or from the paper named.
//
// All extrema are exact for the log-linear curve: between the breakpoints
// examined, the quantities are linear (or ratios of linear functions) in
// log D or in F, so they are monotone and their extremes lie at breakpoints.
#include "suffuse/internal_stability.hpp"

#include <algorithm>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <sstream>

namespace suffuse {

namespace {

using Side = Gradation::Side;

std::string text(double v, int digits = 3) {
  std::ostringstream s;
  s.precision(digits);
  s << v;
  return s.str();
}

std::string percent(double fraction) { return text(100 * fraction) + " %"; }

// Strictly beyond a boundary, not by round-off: a curve drawn through a
// boundary (H = 15 % where F = 20 %, say) lies on it.
constexpr double round_off = 1e-9;
bool below(double value, double boundary) { return value < boundary * (1 - round_off); }
bool above(double value, double boundary) { return value > boundary * (1 + round_off); }

// What every criterion needs to know of the curve.
struct Curve {
  const Gradation& g;
  double cu = NAN;        // D60 / D10
  double f_max = 0.3;     // the shape curve is examined for F <= f_max
  std::string f_max_why;  // how f_max was chosen
  std::optional<Gap> gap;
};

// ---------------------------------------------------------------------------
// Shape curve: F = F(D), H = F(4D) - F(D) (Kenney and Lau 1985). F(D) has
// breakpoints at the measured sizes D_i, F(4D) at D_i / 4; extra fractions
// (0.15, f_max) are added where a boundary changes form.

struct ShapePoint {
  double size, f, h;
};

ShapePoint shape_point(const Gradation& g, double size) {
  const double f = g.passing(size);
  return {size, f, g.passing(4 * size) - f};
}

std::vector<ShapePoint> shape_points(const Gradation& g, std::initializer_list<double> extra_fractions = {}) {
  const std::vector<double>& d = g.sizes_mm();
  std::vector<double> sizes;
  for (double s : d) {
    sizes.push_back(s);
    if (s / 4 > d.front()) sizes.push_back(s / 4);
  }
  for (double p : extra_fractions) {
    if (p < g.smallest_passing() || p > 1) continue;
    sizes.push_back(g.size_at(p, Side::lower));
    sizes.push_back(g.size_at(p, Side::upper));
  }
  std::sort(sizes.begin(), sizes.end());
  sizes.erase(std::unique(sizes.begin(), sizes.end()), sizes.end());
  std::vector<ShapePoint> points;
  for (double s : sizes) points.push_back(shape_point(g, s));
  return points;
}

// The point of the shape curve with 0 < F <= f_max where `index` is least.
template <class Index>
std::optional<std::pair<double, ShapePoint>> least_on_shape(const Curve& c, Index index) {
  std::optional<std::pair<double, ShapePoint>> least;
  for (const ShapePoint& p : shape_points(c.g, {0.15, c.f_max})) {
    if (p.f <= 0 || p.f > c.f_max * (1 + 1e-12)) continue;
    const double v = index(p);
    if (!least || v < least->first) least = std::make_pair(v, p);
  }
  return least;
}

// Li and Fannin's (2008) boundary H = F below F = 15 %, H = 15 % above.
double li_fannin_boundary(double f) { return std::min(f, 0.15); }

// The largest F <= f_max at which the shape curve is inside Li and Fannin's
// unstable zone H < min(F, 15 %): "that fraction of the soil gradation is
// considered internally unstable" (RMC manual, Modified Kenney and Lau Method).
std::optional<double> largest_unstable_fraction(const Curve& c) {
  std::vector<ShapePoint> points;
  for (const ShapePoint& p : shape_points(c.g, {0.15, c.f_max}))
    if (p.f > 0 && p.f <= c.f_max * (1 + 1e-12)) points.push_back(p);
  std::optional<double> largest;
  auto keep = [&](double f) { largest = std::max(largest.value_or(f), f); };
  for (std::size_t k = 0; k < points.size(); ++k) {
    const double gap_k = points[k].h - li_fannin_boundary(points[k].f);
    if (gap_k < -round_off) keep(points[k].f);
    if (k + 1 == points.size()) break;
    const double gap_next = points[k + 1].h - li_fannin_boundary(points[k + 1].f);
    if (gap_k < -round_off && gap_next >= 0)  // leaves the zone in between: both are linear in log D there
      keep(points[k].f + (points[k + 1].f - points[k].f) * gap_k / (gap_k - gap_next));
  }
  return largest;
}

// ---------------------------------------------------------------------------

CriterionResult criterion(std::string id, std::string name, std::string quantity) {
  CriterionResult r;
  r.id = std::move(id);
  r.name = std::move(name);
  r.quantity = std::move(quantity);
  return r;
}

CriterionResult not_applicable(CriterionResult r, std::string why) {
  r.verdict = Verdict::not_applicable;
  r.applicability = std::move(why);
  return r;
}

std::string curve_stops_above(const Gradation& g, double percent_needed) {
  return "the curve stops at " + text(g.sizes_mm().front()) + " mm with " + percent(g.smallest_passing()) +
         " passing: D" + text(percent_needed) + " is not known";
}

// Kezdi (1979): split the curve at any size into a coarse and a fine part;
// the coarse part retains the fine one if D'15 / d'85 <= 4 (Terzaghi's filter
// rule), where D'15 is the 15 % size of the coarse part and d'85 the 85 %
// size of the fine part. For a split at F_s: D'15 = D(F_s + 0.15 (1 - F_s)),
// d'85 = D(0.85 F_s). The supremum over F_s is taken at the breakpoints of
// both arguments, from each side (a gap makes D(F) jump).
CriterionResult kezdi(const Curve& c) {
  CriterionResult r = criterion("kezdi", "Kezdi (1979)", "max D'15/d'85 over all splits");
  r.boundary = "unstable if > 4";
  const Gradation& g = c.g;
  const double lowest = g.smallest_passing() / 0.85;  // below it d'85 is not known
  if (lowest >= 1) return not_applicable(r, curve_stops_above(g, 85));
  std::vector<double> splits = {lowest, 1};
  for (double f : g.passing_points()) splits.insert(splits.end(), {(f - 0.15) / 0.85, f / 0.85});
  double best = -1, best_split = NAN, best_coarse = NAN, best_fine = NAN;
  for (double s : splits) {
    if (s < lowest || s > 1) continue;
    for (Side side : {Side::lower, Side::upper}) {
      // lower: the limit from smaller splits, upper: from larger ones.
      if ((side == Side::lower && s == lowest) || (side == Side::upper && s == 1)) continue;
      const double coarse = g.size_at(0.15 + 0.85 * s, side);
      const double fine = g.size_at(std::max(0.85 * s, g.smallest_passing()), side);
      if (coarse / fine > best) best = coarse / fine, best_split = s, best_coarse = coarse, best_fine = fine;
    }
  }
  r.value = best;
  r.at_passing = best_split;
  r.at_size_mm = g.size_at(best_split, Side::lower);
  r.also = {{"D'15 [mm]", best_coarse}, {"d'85 [mm]", best_fine}};
  r.verdict = above(best, 4) ? Verdict::unstable : Verdict::stable;
  r.applicability = "cohesionless soils; every split with F from " + percent(std::max(lowest, 0.0)) + " to 100 %";
  return r;
}

// Kenney and Lau: unstable if the shape curve has H/F below the boundary for
// F <= 0.2 (widely graded, Cu > 3) or F <= 0.3 (narrowly graded, Cu <= 3).
// Boundary 1.3 (Kenney and Lau 1985), revised to 1.0 (Kenney and Lau 1986);
// both as quoted in the RMC manual, Modified Kenney and Lau Method.
CriterionResult kenney_lau(const Curve& c, int year) {
  const double boundary = year == 1985 ? 1.3 : 1.0;
  CriterionResult r = criterion("kenney_lau_" + std::to_string(year), "Kenney and Lau (" + std::to_string(year) + ")",
                    "min H/F for F <= " + text(c.f_max));
  r.boundary = "unstable if < " + text(boundary);
  const auto least = least_on_shape(c, [](const ShapePoint& p) { return p.h / p.f; });
  if (!least) return not_applicable(r, "the curve starts above F = " + percent(c.f_max) + ": no shape curve to examine");
  r.value = least->first;
  r.at_size_mm = least->second.size;
  r.at_passing = least->second.f;
  r.also = {{"H", least->second.h}};
  r.verdict = below(r.value, boundary) ? Verdict::unstable : Verdict::stable;
  r.applicability = "granular soils; " + c.f_max_why;
  return r;
}

// Li and Fannin (2008): Kenney and Lau's H < F governs for F < 15 %, Kezdi's
// H < 15 % above, up to F = 0.2 or 0.3 as Kenney and Lau (RMC manual,
// Modified Kenney and Lau Method). The value is the least H / min(F, 15 %):
// below 1 the shape curve enters the unstable zone.
CriterionResult li_fannin(const Curve& c) {
  CriterionResult r = criterion("li_fannin", "Li and Fannin (2008)", "min H/min(F, 0.15) for F <= " + text(c.f_max));
  r.boundary = "unstable if < 1 (H < F for F < 15 %, H < 15 % above)";
  const auto least = least_on_shape(c, [](const ShapePoint& p) { return p.h / li_fannin_boundary(p.f); });
  if (!least) return not_applicable(r, "the curve starts above F = " + percent(c.f_max) + ": no shape curve to examine");
  r.value = least->first;
  r.at_size_mm = least->second.size;
  r.at_passing = least->second.f;
  r.also = {{"H", least->second.h}};
  r.verdict = below(r.value, 1) ? Verdict::unstable : Verdict::stable;
  r.applicability = "broadly graded and gap-graded soils (RMC manual); " + c.f_max_why;
  return r;
}

// h' = D90/D60 and h'' = D90/D15 (Burenkova 1993, as in the RMC manual; its
// equation 4 prints D10, its text and the modified method D15).
struct Burenkova {
  double h1 = NAN, h2 = NAN;  // h', h''
};

std::optional<Burenkova> burenkova_factors(const Gradation& g) {
  if (std::isnan(g.d(15))) return std::nullopt;
  return Burenkova{g.d(90) / g.d(60), g.d(90) / g.d(15)};
}

// Burenkova (1993): non-suffusive (Zone II) if
// 0.76 log(h'') + 1 < h' < 1.86 log(h'') + 1 (RMC manual, equation 5, log
// base 10). Below: Zone I, suffusive. Above: Zone III, suffusive per
// Burenkova; these concave-down curves are rare and Wan and Fell (2004)
// expected them stable (RMC manual, Modified Burenkova Method). Tested on
// sand-gravels up to 100 mm and Cu up to 200.
CriterionResult burenkova(const Curve& c) {
  CriterionResult r = criterion("burenkova", "Burenkova (1993)", "h' = D90/D60");
  const auto f = burenkova_factors(c.g);
  if (!f) return not_applicable(r, curve_stops_above(c.g, 15));
  const double lower = 0.76 * std::log10(f->h2) + 1, upper = 1.86 * std::log10(f->h2) + 1;
  r.boundary = "stable if " + text(lower) + " < h' < " + text(upper) + " (0.76 log h'' + 1 < h' < 1.86 log h'' + 1)";
  r.also = {{"h''", f->h2}};
  const double d_max = c.g.size_at(1, Side::lower);
  if (d_max > 100) return not_applicable(r, "largest size " + text(d_max) + " mm: tested up to 100 mm");
  if (c.cu > 200) return not_applicable(r, "Cu = " + text(c.cu) + ": tested up to 200");
  r.value = f->h1;
  r.verdict = above(f->h1, lower) && below(f->h1, upper) ? Verdict::stable : Verdict::unstable;
  r.applicability = std::string("cohesionless sand-gravels up to 100 mm, Cu up to 200") +
                    (std::isnan(c.cu) ? " (Cu not known)" : "") +
                    (f->h1 >= upper ? "; Zone III: suffusive per Burenkova, expected stable by Wan and Fell (2004)"
                                    : "");
  return r;
}

// Modified Burenkova (Wan and Fell 2004, 2008): probability of internal
// instability P = 1 / (1 + exp(-Z)) by logistic regression (RMC manual,
// equations 6-10):
//   Z = 3.875 log(h'') - 3.591 h' + 2.436 for sand-gravels with at most 10 %
//   non-plastic fines (finer than 0.075 mm);
//   Z = 2.378 log(h'') - 3.648 h' + 3.701 for silt-sand-gravels and
//   clay-silt-sand-gravels with clay (finer than 0.002 mm) at most 10 % and
//   PI at most 12.
// The papers give probabilities, not a verdict: suffuse calls P >= 50 %
// unstable (the more likely class of the regression).
CriterionResult modified_burenkova(const Curve& c) {
  CriterionResult r = criterion("modified_burenkova", "Modified Burenkova, Wan and Fell (2004)", "probability of instability P");
  r.boundary = "P = 1/(1 + exp(-Z)); unstable if P >= 0.5 (suffuse's cut: the papers give P only)";
  const auto f = burenkova_factors(c.g);
  if (!f) return not_applicable(r, curve_stops_above(c.g, 15));
  const double fines = c.g.passing(0.075), clay = c.g.passing(0.002);
  const bool sand_gravel = fines <= 0.10;
  if (!sand_gravel && clay > 0.10)
    return not_applicable(r, "clay fraction (finer than 0.002 mm) " + percent(clay) + " > 10 %");
  const double z = sand_gravel ? 3.875 * std::log10(f->h2) - 3.591 * f->h1 + 2.436
                               : 2.378 * std::log10(f->h2) - 3.648 * f->h1 + 3.701;
  r.value = 1 / (1 + std::exp(-z));
  r.also = {{"h'", f->h1}, {"h''", f->h2}, {"Z", z}, {"fines < 0.075 mm", fines}};
  r.verdict = r.value >= 0.5 ? Verdict::unstable : Verdict::stable;
  r.applicability = sand_gravel ? "sand-gravel with " + percent(fines) + " <= 10 % fines (assumed non-plastic)"
                                : "silt-sand-gravel with " + percent(fines) +
                                      " fines (clay <= 10 % and PI <= 12 assumed; not in a PSD)";
  r.applicability += "; a finer fraction under 15 % may not be assessed adequately (RMC manual)";
  return r;
}

// Wan and Fell (2008), alternative method for broadly graded
// silt-sand-gravels: the point (30 / log(D90/D60), 15 / log(D20/D5)) against
// a stable and an unstable zone (RMC manual, Alternative Method). Not for
// gap-graded soils. The zone boundaries are published only as a figure
// (Wan and Fell 2008; RMC manual Figure 28), whose values could not be read
// here: suffuse reports the point and gives no verdict.
CriterionResult wan_fell_2008(const Curve& c) {
  CriterionResult r = criterion("wan_fell_2008", "Wan and Fell (2008) alternative method", "30/log(D90/D60)");
  r.boundary = "zones published as a figure only (Wan and Fell 2008): no verdict";
  if (c.gap) return not_applicable(r, "gap-graded soil (gap " + text(c.gap->from_mm) + "-" + text(c.gap->to_mm) +
                                          " mm): the method is not for gap-graded soils");
  if (std::isnan(c.g.d(5))) return not_applicable(r, curve_stops_above(c.g, 5));
  r.value = 30 / std::log10(c.g.d(90) / c.g.d(60));
  r.also = {{"15/log(D20/D5)", 15 / std::log10(c.g.d(20) / c.g.d(5))}};
  r.verdict = Verdict::not_evaluated;
  r.applicability = "broadly graded silt-sand-gravels, not gap-graded; a finer fraction under 20 % may not be "
                    "assessed adequately (RMC manual)";
  return r;
}

// Chang and Zhang (2013), Soils and Foundations 53(4): 569-583, composite
// criteria from the abstract: a well-graded soil with fines content P < 5 %
// is stable if (H/F)min > 1.0; a gap-graded soil with P < 10 % is stable if
// its gap ratio Gr < 3.0; a well-graded soil with P > 20 % or a gap-graded one
// with P > 35 % is stable. The boundaries for 5 % <= P <= 20 % (well-graded)
// and 10 % <= P <= 35 % (gap-graded) were not found: no verdict there. Fines:
// finer than 0.063 mm; gap ratio: largest / smallest size of the gap.
CriterionResult chang_zhang(const Curve& c, const CriterionResult& kenney_lau_1986) {
  CriterionResult r = criterion("chang_zhang", "Chang and Zhang (2013)", c.gap ? "gap ratio Gr" : "min H/F");
  const Gradation& g = c.g;
  if (g.sizes_mm().front() > 0.063 && g.smallest_passing() > 0)
    return not_applicable(r, "fines content (finer than 0.063 mm) unknown: " + curve_stops_above(g, 0));
  const double fines = g.passing(0.063);
  r.also = {{"fines < 0.063 mm", fines}};
  r.applicability = std::string(c.gap ? "gap-graded" : "well-graded") + " soil with " + percent(fines) + " fines";
  if (c.gap) {
    r.value = c.gap->ratio();
    r.at_size_mm = c.gap->from_mm;
    r.at_passing = c.gap->passing;
    r.boundary = "P < 10 %: stable if Gr < 3.0; P > 35 %: stable";
    if (fines < 0.10) r.verdict = r.value < 3.0 ? Verdict::stable : Verdict::unstable;
    else if (fines > 0.35) r.verdict = Verdict::stable;
    else r.verdict = Verdict::not_evaluated, r.applicability += " (10-35 %: published boundary not found)";
    return r;
  }
  r.value = kenney_lau_1986.value;
  r.at_size_mm = kenney_lau_1986.at_size_mm;
  r.at_passing = kenney_lau_1986.at_passing;
  r.boundary = "P < 5 %: stable if (H/F)min > 1.0; P > 20 %: stable";
  if (fines < 0.05) {
    if (std::isnan(r.value)) return not_applicable(r, kenney_lau_1986.applicability);
    r.verdict = r.value > 1.0 ? Verdict::stable : Verdict::unstable;
  } else if (fines > 0.20) {
    r.verdict = Verdict::stable;
  } else {
    r.verdict = Verdict::not_evaluated;
    r.applicability += " (5-20 %: published boundary not found)";
  }
  return r;
}

// The widest stretch where nothing more passes, strictly between 0 and 100 %.
std::optional<Gap> widest_gap(const Gradation& g) {
  const auto& d = g.sizes_mm();
  const auto& f = g.passing_points();
  std::optional<Gap> widest;
  for (std::size_t i = 0; i + 1 < d.size(); ++i) {
    if (f[i] <= 0 || f[i] >= 1 || f[i + 1] != f[i]) continue;
    std::size_t j = i + 1;
    while (j + 1 < d.size() && f[j + 1] == f[i]) ++j;
    const Gap gap{d[i], d[j], f[i]};
    if (!widest || gap.ratio() > widest->ratio()) widest = gap;
    i = j - 1;
  }
  return widest;
}

}  // namespace

std::string to_string(Verdict verdict) {
  switch (verdict) {
    case Verdict::stable: return "stable";
    case Verdict::transitional: return "transitional";
    case Verdict::unstable: return "unstable";
    case Verdict::not_applicable: return "not applicable";
    case Verdict::not_evaluated: return "no verdict";
  }
  return "?";
}

bool InternalStability::unstable() const {
  return std::any_of(criteria.begin(), criteria.end(), [](const auto& c) { return c.verdict == Verdict::unstable; });
}

bool InternalStability::stable() const {
  bool any = false;
  for (const CriterionResult& c : criteria) {
    if (c.verdict == Verdict::unstable || c.verdict == Verdict::transitional) return false;
    any = any || c.verdict == Verdict::stable;
  }
  return any;
}

std::vector<std::array<double, 2>> shape_curve(const Gradation& g) {
  std::vector<std::array<double, 2>> curve;
  for (const ShapePoint& p : shape_points(g)) curve.push_back({p.f, p.h});
  return curve;
}

InternalStability assess_internal_stability(const Gradation& g) {
  Curve c{g, NAN, 0.3, "", std::nullopt};
  if (!std::isnan(g.d(10))) c.cu = g.d(60) / g.d(10);
  // Kenney and Lau (1986): loose particles are at most about 20 % of a widely
  // graded soil (Cu > 3), 30 % of a narrowly graded one (RMC manual).
  if (std::isnan(c.cu)) c.f_max = 0.3, c.f_max_why = "Cu not known (curve starts above 10 %): F up to 0.3 examined";
  else if (c.cu > 3) c.f_max = 0.2, c.f_max_why = "widely graded (Cu = " + text(c.cu) + " > 3): F up to 0.2";
  else c.f_max = 0.3, c.f_max_why = "narrowly graded (Cu = " + text(c.cu) + " <= 3): F up to 0.3";
  c.gap = widest_gap(g);

  InternalStability s;
  s.cu = c.cu;
  s.shape_curve_limit = c.f_max;
  s.gap = c.gap;
  const CriterionResult kl1986 = kenney_lau(c, 1986);
  s.criteria = {kezdi(c),          kenney_lau(c, 1985), kl1986,           li_fannin(c),
                burenkova(c),      modified_burenkova(c), wan_fell_2008(c), chang_zhang(c, kl1986)};

  // Erodible fines: what is finer than the split the criteria identify.
  if (!s.unstable()) {
    s.erodible_fines = 0;
    s.erodible_fines_rule = "no criterion finds the soil unstable: no erodible fines";
  } else if (c.gap) {
    s.erodible_fines = c.gap->passing;
    s.erodible_fines_rule = "gap-graded: the fraction finer than the gap (" + text(c.gap->from_mm) + "-" +
                            text(c.gap->to_mm) + " mm), where the finer fraction ends (Fell et al. 2008, RMC manual)";
  } else if (const auto f = largest_unstable_fraction(c)) {
    s.erodible_fines = *f;
    s.erodible_fines_rule = "the largest F of the shape curve inside Li and Fannin's unstable zone";
  } else {
    s.erodible_fines = 0;
    s.erodible_fines_rule = "unstable only by whole-curve indices, which identify no split: no erodible fines";
  }
  return s;
}

}  // namespace suffuse
