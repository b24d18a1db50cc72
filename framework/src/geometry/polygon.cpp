#include "geometry/polygon.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

namespace suffuse::detail {

namespace {

using Point = std::array<double, 2>;

std::string text(const Point& p) {
  std::ostringstream s;
  s.precision(10);
  s << "(" << p[0] << ", " << p[1] << ")";
  return s.str();
}

// Twice the signed area of triangle a b c: > 0 when c lies left of a -> b.
double orientation(const Point& a, const Point& b, const Point& c) {
  return (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]);
}

bool on_segment(const Point& a, const Point& b, const Point& c) {  // c collinear with a b
  return std::min(a[0], b[0]) <= c[0] && c[0] <= std::max(a[0], b[0]) && std::min(a[1], b[1]) <= c[1] &&
         c[1] <= std::max(a[1], b[1]);
}

// Whether segments a b and c d share a point (crossing, touching or overlapping).
bool segments_meet(const Point& a, const Point& b, const Point& c, const Point& d) {
  const double o1 = orientation(a, b, c), o2 = orientation(a, b, d), o3 = orientation(c, d, a),
               o4 = orientation(c, d, b);
  if (((o1 > 0 && o2 < 0) || (o1 < 0 && o2 > 0)) && ((o3 > 0 && o4 < 0) || (o3 < 0 && o4 > 0))) return true;
  return (o1 == 0 && on_segment(a, b, c)) || (o2 == 0 && on_segment(a, b, d)) || (o3 == 0 && on_segment(c, d, a)) ||
         (o4 == 0 && on_segment(c, d, b));
}

double signed_area(const Polygon::Ring& ring) {
  double twice = 0;
  for (std::size_t i = 0; i < ring.size(); ++i) {
    const Point& a = ring[i];
    const Point& b = ring[(i + 1) % ring.size()];
    twice += a[0] * b[1] - b[0] * a[1];
  }
  return 0.5 * twice;
}

bool ring_contains(const Polygon::Ring& ring, double u, double v) {
  bool inside = false;
  for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
    const Point& a = ring[i];
    const Point& b = ring[j];
    if ((a[1] > v) != (b[1] > v) && u < a[0] + (v - a[1]) * (b[0] - a[0]) / (b[1] - a[1])) inside = !inside;
  }
  return inside;
}

// Every ring of the polygon, the outer one first (index -1).
template <class F>
void for_each_ring(const Polygon& polygon, F&& f) {
  f(-1, polygon.outer);
  for (std::size_t k = 0; k < polygon.holes.size(); ++k) f(static_cast<int>(k), polygon.holes[k]);
}

}  // namespace

std::optional<PolygonProblem> check_polygon(const Polygon& polygon) {
  // The edges are checked pairwise: a cross-section has tens or hundreds of
  // vertices, and 10,000 are checked in about a second.
  constexpr std::size_t max_vertices = 10000;
  std::size_t vertices = polygon.outer.size();
  for (const Polygon::Ring& hole : polygon.holes) vertices += hole.size();
  if (vertices > max_vertices)
    return PolygonProblem{-1, -1, "too many vertices", "at most " + std::to_string(max_vertices) + " in all rings",
                          std::to_string(vertices)};
  std::optional<PolygonProblem> found;
  for_each_ring(polygon, [&](int r, const Polygon::Ring& ring) {
    if (found) return;
    if (ring.size() < 3) {
      found = PolygonProblem{r, -1, "too few vertices", "3 vertices or more", std::to_string(ring.size())};
      return;
    }
    for (std::size_t i = 0; i < ring.size() && !found; ++i)
      if (!std::isfinite(ring[i][0]) || !std::isfinite(ring[i][1]))
        found = PolygonProblem{r, static_cast<int>(i), "vertex not finite", "finite coordinates [m]", text(ring[i])};
    if (!found && signed_area(ring) == 0)
      found = PolygonProblem{r, -1, "ring without area", "vertices not all on one line", "no area"};
  });
  if (found) return found;

  // Edges by ring and first vertex; neighbours in a ring share a vertex.
  struct Edge {
    int ring, vertex;
    Point a, b;
    std::size_t ring_size;
  };
  std::vector<Edge> edges;
  for_each_ring(polygon, [&](int r, const Polygon::Ring& ring) {
    for (std::size_t i = 0; i < ring.size(); ++i)
      edges.push_back({r, static_cast<int>(i), ring[i], ring[(i + 1) % ring.size()], ring.size()});
  });
  for (std::size_t e = 0; e < edges.size(); ++e)
    for (std::size_t f = e + 1; f < edges.size(); ++f) {
      const Edge &p = edges[e], &q = edges[f];
      if (p.ring == q.ring) {
        const auto n = static_cast<int>(p.ring_size);
        const bool next = (p.vertex + 1) % n == q.vertex, previous = (q.vertex + 1) % n == p.vertex;
        if (next || previous) {
          // Neighbours meet at their shared vertex only: not folded back along each other.
          const Point& shared = next ? p.b : p.a;
          const Point& other_p = next ? p.a : p.b;
          const Point& other_q = next ? q.b : q.a;
          if (orientation(other_p, shared, other_q) == 0 && on_segment(other_p, other_q, shared) == false)
            return PolygonProblem{p.ring, next ? q.vertex : p.vertex, "edges folded back on each other",
                                  "a polygon whose edges do not overlap", "vertex " + text(shared)};
          continue;
        }
      }
      if (segments_meet(p.a, p.b, q.a, q.b)) {
        const std::string ring = q.ring < 0 ? "the outer ring" : "hole " + std::to_string(q.ring);
        return PolygonProblem{p.ring, p.vertex, p.ring == q.ring ? "self-intersecting polygon" : "rings cross",
                              "edges that meet only their neighbours at their shared vertices",
                              "edge " + text(p.a) + "-" + text(p.b) + " meets the edge " + text(q.a) + "-" +
                                  text(q.b) + " of " + ring};
      }
    }
  // No edges meet: a ring lies wholly inside or outside another; one vertex tells.
  for (std::size_t k = 0; k < polygon.holes.size(); ++k) {
    const Point& v = polygon.holes[k][0];
    if (!ring_contains(polygon.outer, v[0], v[1]))
      return PolygonProblem{static_cast<int>(k), -1, "hole outside the polygon", "a hole inside the outer ring",
                            "vertex " + text(v) + " outside it"};
    for (std::size_t j = 0; j < polygon.holes.size(); ++j)
      if (j != k && ring_contains(polygon.holes[j], v[0], v[1]))
        return PolygonProblem{static_cast<int>(k), -1, "hole inside another hole", "holes apart from each other",
                              "inside hole " + std::to_string(j)};
  }
  return std::nullopt;
}

double polygon_area(const Polygon& polygon) {
  double area = std::abs(signed_area(polygon.outer));
  for (const Polygon::Ring& hole : polygon.holes) area -= std::abs(signed_area(hole));
  return area;
}

bool polygon_contains(const Polygon& polygon, double u, double v) {
  bool inside = false;
  for_each_ring(polygon, [&](int, const Polygon::Ring& ring) { inside = inside != ring_contains(ring, u, v); });
  return inside;
}

namespace {

// Where the line of coordinate `at` along axis k crosses the edges: the other
// coordinate, sorted; for k = 1 by ring_contains's own expression.
void line_crossings(const Polygon& polygon, int k, double at, std::vector<double>& out) {
  const int o = 1 - k;
  out.clear();
  for_each_ring(polygon, [&](int, const Polygon::Ring& ring) {
    for (std::size_t i = 0, j = ring.size() - 1; i < ring.size(); j = i++) {
      const Point& a = ring[i];
      const Point& b = ring[j];
      if ((a[k] > at) != (b[k] > at)) out.push_back(a[o] + (at - a[k]) * (b[o] - a[o]) / (b[k] - a[k]));
    }
  });
  std::sort(out.begin(), out.end());
}

}  // namespace

void crossings_at(const Polygon& polygon, double u, std::vector<double>& v) { line_crossings(polygon, 0, u, v); }

void row_crossings(const Polygon& polygon, double v, std::vector<double>& u) { line_crossings(polygon, 1, v, u); }

std::array<double, 4> polygon_bounds(const Polygon& polygon) {
  std::array<double, 4> box{polygon.outer[0][0], polygon.outer[0][1], polygon.outer[0][0], polygon.outer[0][1]};
  for (const Point& p : polygon.outer) {
    box[0] = std::min(box[0], p[0]);
    box[1] = std::min(box[1], p[1]);
    box[2] = std::max(box[2], p[0]);
    box[3] = std::max(box[3], p[1]);
  }
  return box;  // the holes lie inside the outer ring
}

}  // namespace suffuse::detail
