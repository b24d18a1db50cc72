#pragma once
// A polygon in a plane, the cross-section of a body (docs/geometry.md): an
// outer ring and any number of holes.
#include <array>
#include <vector>

namespace suffuse {

struct Polygon {
  // A ring: its vertices in order, either way round, not closed (the last
  // vertex joins the first).
  using Ring = std::vector<std::array<double, 2>>;
  Ring outer;
  std::vector<Ring> holes;
};

}  // namespace suffuse
