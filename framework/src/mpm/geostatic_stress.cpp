#include "mpm/geostatic_stress.hpp"

#include <algorithm>
#include <cmath>

namespace suffuse::detail {

namespace {

// Whether horizontal position x (all axes but the vertical) lies in body b's extent.
bool above(const BodySpec& b, const double* x, int dim) {
  for (int a = 0; a + 1 < dim; ++a)
    if (x[a] < b.min[a] || x[a] >= b.max[a]) return false;
  return true;
}

}  // namespace

void add_geostatic_stress(const Scene& scene, std::span<const double> unit_weights, std::size_t body,
                          double liquid_density, double g, PointSet& points, PointRange range) {
  const BodySpec& own = scene.bodies[body];
  if (!own.k0) return;
  const int dim = scene.dim, v = dim - 1;
  const double* x = points.data(points.core().position);
  double* s = points.data(points.core().stress);
  for (std::size_t p = range.begin; p < range.end; ++p) {
    const double* xp = x + p * dim;
    // The bodies stacked above: each resting on the top reached so far (a
    // tolerance of round-off in the coordinates); at most one pass per body.
    double top = own.max[v], load = 0;
    for (std::size_t pass = 0; pass < scene.bodies.size(); ++pass) {
      const double tolerance = 1e-9 * (1 + std::abs(top));
      std::size_t next = scene.bodies.size();
      for (std::size_t b = 0; b < scene.bodies.size() && next == scene.bodies.size(); ++b)
        if (b != body && std::abs(scene.bodies[b].min[v] - top) <= tolerance && above(scene.bodies[b], xp, dim))
          next = b;
      if (next == scene.bodies.size()) break;
      load += unit_weights[next] * (scene.bodies[next].max[v] - top);
      top = scene.bodies[next].max[v];
    }
    const double y = xp[v];
    double total = load + unit_weights[body] * (own.max[v] - y);
    if (own.water_table) {
      const double rho_g = liquid_density * g;
      total += rho_g * std::max(0.0, *own.water_table - top);           // water ponded on the stack
      total -= rho_g * std::max(0.0, *own.water_table - y);             // the hydrostatic pore pressure
    }
    for (int a = 0; a < 3; ++a) s[p * 6 + a] -= (a == v ? 1.0 : *own.k0) * total;
  }
}

}  // namespace suffuse::detail
