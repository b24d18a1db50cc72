#pragma once
// Polygons: whether a point lies inside, where a line across crosses the
// boundary, the area, and the checks a polygon from a scene must pass.
#include <array>
#include <optional>
#include <string>
#include <vector>

#include "suffuse/polygon.hpp"

namespace suffuse::detail {

// What is wrong with a polygon, and where: ring -1 is the outer ring, k >= 0
// hole k; vertex the first vertex of the edge (or the vertex) concerned, -1
// for the ring as a whole.
struct PolygonProblem {
  int ring = -1;
  int vertex = -1;
  std::string problem, expected, found;
};

// At most 10,000 vertices; each ring has three or more, finite, and an area; no two edges
// cross or touch but neighbours at their shared vertex; every hole lies
// inside the outer ring and outside the other holes.
std::optional<PolygonProblem> check_polygon(const Polygon& polygon);

// The area inside the outer ring and outside the holes.
double polygon_area(const Polygon& polygon);

// Whether (u, v) lies inside (even-odd over every ring; a point on an edge is
// inside on one side of it, so that polygons sharing an edge split the plane).
bool polygon_contains(const Polygon& polygon, double u, double v);

// Where the line of constant u crosses the polygon's edges, in increasing v
// (the line is inside between the first and the second, the third and the
// fourth, ...; polygon_contains may differ on the edges themselves).
void crossings_at(const Polygon& polygon, double u, std::vector<double>& v);

// Where the line of constant v crosses the edges, by the formula
// polygon_contains uses: (u, v) is inside exactly when an odd number of them
// lie above u. Sorted.
void row_crossings(const Polygon& polygon, double v, std::vector<double>& u);

// The smallest box that holds the polygon: {u_min, v_min, u_max, v_max}.
std::array<double, 4> polygon_bounds(const Polygon& polygon);

}  // namespace suffuse::detail
