#include "mpm/geostatic_stress.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/body_shape.hpp"

namespace suffuse::detail {

void add_geostatic_stress(const Scene& scene, std::span<const double> unit_weights, std::size_t body,
                          double liquid_density, double g, PointSet& points, PointRange range) {
  const BodySpec& own = scene.bodies[body];
  if (!own.k0) return;
  const int dim = scene.dim, v = dim - 1;
  const double* x = points.data(points.core().position);
  double* s = points.data(points.core().stress);
  for (std::size_t p = range.begin; p < range.end; ++p) {
    const double* xp = x + p * dim;
    // Up the vertical through the point: its own body's surface above it,
    // then the bodies stacked on it, each entered where the last was left (a
    // tolerance of round-off in the coordinates); at most one pass per body.
    const double own_top = exit_above(own, xp, dim, xp[v], 1e-9 * (1 + std::abs(xp[v])));
    double top = own_top, load = 0;
    for (std::size_t pass = 0; pass < scene.bodies.size(); ++pass) {
      const double tolerance = 1e-9 * (1 + std::abs(top));
      std::size_t next = scene.bodies.size();
      for (std::size_t b = 0; b < scene.bodies.size() && next == scene.bodies.size(); ++b)
        if (b != body && enters_at(scene.bodies[b], xp, dim, top, tolerance)) next = b;
      if (next == scene.bodies.size()) break;
      const double leaves = exit_above(scene.bodies[next], xp, dim, top, tolerance);
      load += unit_weights[next] * (leaves - top);
      top = leaves;
    }
    const double y = xp[v];
    double total = load + unit_weights[body] * (own_top - y);
    if (own.water_table) {
      const double rho_g = liquid_density * g;
      total += rho_g * std::max(0.0, *own.water_table - top);           // water ponded on the stack
      total -= rho_g * std::max(0.0, *own.water_table - y);             // the hydrostatic pore pressure
    }
    for (int a = 0; a < 3; ++a) s[p * 6 + a] -= (a == v ? 1.0 : *own.k0) * total;
  }
}

}  // namespace suffuse::detail
