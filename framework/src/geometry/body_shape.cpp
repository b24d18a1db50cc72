#include "geometry/body_shape.hpp"

#include <cmath>
#include <vector>

#include "geometry/polygon.hpp"

namespace suffuse::detail {

namespace {

// The polygon's plane: its two axes (u, v) in increasing order, the others
// than the extrusion's in 3D.
struct Plane {
  int u = 0, v = 1;
};

Plane plane_of(const BodySpec& body, int dim) {
  if (dim == 2) return {};
  Plane p;
  int k = 0;
  for (int a = 0; a < 3; ++a)
    if (a != body.extrusion_axis) (k++ == 0 ? p.u : p.v) = a;
  return p;
}

// Whether the horizontal position lies within [min, max) of the axes the
// box (or the extrusion) spans across the vertical.
bool within_box_across(const BodySpec& body, const double* x, int dim, bool extrusion_only) {
  for (int a = 0; a + 1 < dim; ++a) {
    if (extrusion_only && a != body.extrusion_axis) continue;
    if (x[a] < body.min[a] || x[a] >= body.max[a]) return false;
  }
  return true;
}

// The vertical line is along the extrusion: the polygon across it.
bool vertical_extrusion(const BodySpec& body, int dim) { return dim == 3 && body.extrusion_axis == dim - 1; }

}  // namespace

bool shape_contains(const BodySpec& body, const double* x, int dim) {
  if (!body.polygon) {
    for (int a = 0; a < dim; ++a)
      if (x[a] < body.min[a] || x[a] >= body.max[a]) return false;
    return true;
  }
  if (dim == 3 && (x[body.extrusion_axis] < body.min[body.extrusion_axis] ||
                   x[body.extrusion_axis] >= body.max[body.extrusion_axis]))
    return false;
  const Plane p = plane_of(body, dim);
  return polygon_contains(*body.polygon, x[p.u], x[p.v]);
}

double exit_above(const BodySpec& body, const double* x, int dim, double y, double tolerance) {
  const int v = dim - 1;
  if (!body.polygon || vertical_extrusion(body, dim)) return body.max[v];
  const Plane p = plane_of(body, dim);
  std::vector<double> crossings;
  crossings_at(*body.polygon, x[p.u], crossings);
  for (double c : crossings)
    if (c > y + tolerance) return c;
  return y;  // not inside: nothing above
}

bool enters_at(const BodySpec& body, const double* x, int dim, double y, double tolerance) {
  const int v = dim - 1;
  if (!body.polygon) return std::abs(body.min[v] - y) <= tolerance && within_box_across(body, x, dim, false);
  if (vertical_extrusion(body, dim)) {
    const Plane p = plane_of(body, dim);
    return std::abs(body.min[v] - y) <= tolerance && polygon_contains(*body.polygon, x[p.u], x[p.v]);
  }
  if (dim == 3 && !within_box_across(body, x, dim, true)) return false;
  const Plane p = plane_of(body, dim);
  std::vector<double> crossings;
  crossings_at(*body.polygon, x[p.u], crossings);
  for (std::size_t k = 0; k < crossings.size(); k += 2)  // entries going up: the even crossings
    if (std::abs(crossings[k] - y) <= tolerance) return true;
  return false;
}

}  // namespace suffuse::detail
