#pragma once
// A body's shape (a box, or a polygon, extruded in 3D) as the points and the
// initial stress need it: whether a position lies inside, and where a
// vertical line through it is inside (docs/geometry.md).
#include <array>
#include <vector>

#include "suffuse/scene.hpp"

namespace suffuse::detail {

// Whether position x (dim components) lies in the body's shape: a box from
// min (included) to max (excluded) on every axis; a polygon by
// polygon_contains in its plane, and so along the extrusion; never for a
// body of points from a file, which has no shape.
bool shape_contains(const BodySpec& body, const double* x, int dim);

// Whether a position may lie in the shape: within the box that holds it,
// widened by round-off (a polygon's inside test may put a point one ulp
// past its tip inside); a cheap test before shape_contains.
bool near_bounds(const BodySpec& body, const double* x, int dim);

// The same test as shape_contains for many positions of one row of the
// grid's lattice: the polygon's crossings of the row's line are kept between
// calls while the row's in-plane coordinate does not change.
class ShapeTest {
 public:
  explicit ShapeTest(const BodySpec& body, int dim);
  bool contains(const double* x);

 private:
  const BodySpec& body_;
  int dim_, u_ = 0, v_ = 1;
  double row_ = 0;
  bool cached_ = false;
  std::vector<double> crossings_;  // sorted
};

// Where the vertical line (the last axis) at x's horizontal position lies
// inside the shape: intervals [lo, hi) of elevation, lowest first, appended
// to `out`.
void vertical_intervals(const BodySpec& body, const double* x, int dim, std::vector<std::array<double, 2>>& out);

}  // namespace suffuse::detail
