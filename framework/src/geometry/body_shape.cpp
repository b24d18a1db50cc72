#include "geometry/body_shape.hpp"

#include <algorithm>
#include <cmath>

#include "geometry/polygon.hpp"

namespace suffuse::detail {

namespace {

// The polygon's plane: its two axes (u, v) in increasing order, the others
// than the extrusion's in 3D.
std::array<int, 2> plane_of(const BodySpec& body, int dim) {
  if (dim == 2) return {0, 1};
  std::array<int, 2> p{};
  int k = 0;
  for (int a = 0; a < 3; ++a)
    if (a != body.extrusion_axis) p[k++] = a;
  return p;
}

bool within_extrusion(const BodySpec& body, const double* x, int dim) {
  const int e = body.extrusion_axis;
  return dim == 2 || (x[e] >= body.min[e] && x[e] < body.max[e]);
}

// Whether a position lies inside the box from min (included) to max
// (excluded): a box body's shape.
bool within_bounds(const BodySpec& body, const double* x, int dim) {
  for (int a = 0; a < dim; ++a)
    if (x[a] < body.min[a] || x[a] >= body.max[a]) return false;
  return true;
}

}  // namespace

bool shape_contains(const BodySpec& body, const double* x, int dim) {
  if (!body.points.empty()) return false;  // points from a file have no shape
  if (!body.polygon) return within_bounds(body, x, dim);
  if (!within_extrusion(body, x, dim)) return false;
  const std::array<int, 2> p = plane_of(body, dim);
  return polygon_contains(*body.polygon, x[p[0]], x[p[1]]);
}


bool near_bounds(const BodySpec& body, const double* x, int dim) {
  for (int a = 0; a < dim; ++a) {
    const double margin = 1e-9 * (std::abs(body.min[a]) + std::abs(body.max[a]) + (body.max[a] - body.min[a]));
    if (x[a] < body.min[a] - margin || x[a] > body.max[a] + margin) return false;
  }
  return true;
}

ShapeTest::ShapeTest(const BodySpec& body, int dim) : body_(body), dim_(dim) {
  if (body.polygon) {
    const std::array<int, 2> p = plane_of(body, dim);
    u_ = p[0];
    v_ = p[1];
  }
}

bool ShapeTest::contains(const double* x) {
  if (!body_.points.empty()) return false;  // as shape_contains
  if (!body_.polygon) return within_bounds(body_, x, dim_);
  if (!within_extrusion(body_, x, dim_)) return false;
  if (!cached_ || x[v_] != row_) {
    row_crossings(*body_.polygon, x[v_], crossings_);
    row_ = x[v_];
    cached_ = true;
  }
  // Inside when an odd number of crossings lie above u (polygon_contains's rule).
  const auto above = crossings_.end() - std::upper_bound(crossings_.begin(), crossings_.end(), x[u_]);
  return above % 2 == 1;
}

void vertical_intervals(const BodySpec& body, const double* x, int dim, std::vector<std::array<double, 2>>& out) {
  if (!body.points.empty()) return;  // points from a file have no shape
  const int v = dim - 1;
  if (!body.polygon) {
    for (int a = 0; a < v; ++a)
      if (x[a] < body.min[a] || x[a] >= body.max[a]) return;
    out.push_back({body.min[v], body.max[v]});
    return;
  }
  const std::array<int, 2> p = plane_of(body, dim);
  if (dim == 3 && body.extrusion_axis == v) {  // the line runs along the extrusion
    if (polygon_contains(*body.polygon, x[p[0]], x[p[1]])) out.push_back({body.min[v], body.max[v]});
    return;
  }
  if (!within_extrusion(body, x, dim)) return;
  std::vector<double> crossings;
  crossings_at(*body.polygon, x[p[0]], crossings);  // the plane's v is the vertical
  for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) out.push_back({crossings[k], crossings[k + 1]});
}

}  // namespace suffuse::detail
