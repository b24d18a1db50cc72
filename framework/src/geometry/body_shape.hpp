#pragma once
// A body's shape (a box, or a polygon, extruded in 3D) as the points and the
// initial stress need it: whether a position lies inside, and where a
// vertical line through it enters and leaves (docs/geometry.md).
#include "suffuse/scene.hpp"

namespace suffuse::detail {

// Whether position x (dim components) lies in the body's shape: a box from
// min (included) to max (excluded) on every axis; a polygon by
// polygon_contains in its plane, and so along the extrusion.
bool shape_contains(const BodySpec& body, const double* x, int dim);

// Going up the vertical (the last axis) at x's horizontal position from
// elevation y inside the shape: where the line leaves it, the first boundary
// above y + tolerance.
double exit_above(const BodySpec& body, const double* x, int dim, double y, double tolerance);

// Whether the vertical line at x's horizontal position enters the shape at
// elevation y (within tolerance), going up.
bool enters_at(const BodySpec& body, const double* x, int dim, double y, double tolerance);

}  // namespace suffuse::detail
