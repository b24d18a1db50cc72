#include "mpm/geostatic_stress.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "geometry/body_shape.hpp"

namespace suffuse::detail {

namespace {

// A stretch of the vertical inside one body.
struct Stretch {
  std::size_t body;
  double lo, hi;
};

}  // namespace

void add_geostatic_stress(const Scene& scene, const WeightBetween& weight, std::size_t body, double liquid_density,
                          double g, PointSet& points, PointRange range) {
  const BodySpec& own = scene.bodies[body];
  if (!own.k0) return;
  const int dim = scene.dim, v = dim - 1;
  const double* x = points.data(points.core().position);
  double* s = points.data(points.core().stress);
  std::vector<std::array<double, 2>> intervals;
  std::vector<Stretch> stretches;
  for (std::size_t p = range.begin; p < range.end; ++p) {
    const double* xp = x + p * dim;
    const double y = xp[v];
    // The vertical through the point: where each body is on it.
    stretches.clear();
    for (std::size_t b = 0; b < scene.bodies.size(); ++b) {
      intervals.clear();
      vertical_intervals(scene.bodies[b], xp, dim, intervals);
      for (const auto& i : intervals) stretches.push_back({b, i[0], i[1]});
    }
    // Where a body holds a height: the first body of the scene whose stretch
    // does (a later body fills only what earlier ones left). The end of its
    // hold from `from` up: its stretch's end, or where an earlier body starts.
    auto held_until = [&](const Stretch& st, double from, double tolerance) {
      double end = st.hi;
      for (const Stretch& e : stretches)
        if (e.body < st.body && e.lo > from + tolerance && e.lo < end) end = e.lo;
      return end;
    };
    // Its own body's surface above it (a point on its surface has none above).
    const double own_tolerance = 1e-9 * (1 + std::abs(y));
    double own_top = y;
    for (const Stretch& st : stretches)
      if (st.body == body && st.lo <= y + own_tolerance && st.hi >= y - own_tolerance) {
        own_top = std::max(y, held_until(st, y, own_tolerance));
        break;
      }
    // Then up the vertical, body after body, to the first gap (a tolerance of
    // round-off in the coordinates where bodies meet). Each pass ends at an
    // end or a start of a stretch above the last (a stretch cut by an
    // earlier body is walked in parts), so at most one pass per end and start.
    double top = own_top, load = 0;
    for (std::size_t pass = 0; pass < 2 * stretches.size(); ++pass) {
      const double tolerance = 1e-9 * (1 + std::abs(top));
      const Stretch* holder = nullptr;
      for (const Stretch& st : stretches)
        if (st.lo <= top + tolerance && st.hi > top + tolerance && (!holder || st.body < holder->body)) holder = &st;
      if (!holder) break;
      const double end = held_until(*holder, top, tolerance);
      load += weight(holder->body, top, end);
      top = end;
    }
    double total = load + weight(body, y, own_top);
    if (own.water_table) {
      const double rho_g = liquid_density * g;
      total += rho_g * std::max(0.0, *own.water_table - top);  // water ponded on the stack
      total -= rho_g * std::max(0.0, *own.water_table - y);    // the hydrostatic pore pressure
    }
    for (int a = 0; a < 3; ++a) s[p * 6 + a] -= (a == v ? 1.0 : *own.k0) * total;
  }
}

}  // namespace suffuse::detail
