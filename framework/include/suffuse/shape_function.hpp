#pragma once
// Shape functions map between material points and grid nodes.
#include <cstdint>
#include <span>

#include "suffuse/grid.hpp"

namespace suffuse {

class ShapeFunction {
 public:
  virtual ~ShapeFunction() = default;

  // Number of nodes each point connects to (4 and 8 for bi/trilinear).
  virtual int nodes_per_point(int dim) const = 0;

  // For a batch of n points (positions and sizes: n*dim; each point inside
  // the grid box; sizes are the edge lengths of the point's domain) fill
  // node_ids (n*npp), weights (n*npp) and gradients (n*npp*dim, d/dx_0 first).
  // Nodes a point does not reach must still be valid indices with zero weight
  // and gradient. Called once per step on large batches (one per thread):
  // never once per point.
  virtual void evaluate(const GridGeometry& grid, std::span<const double> positions,
                        std::span<const double> sizes, std::span<NodeId> node_ids,
                        std::span<double> weights, std::span<double> gradients) const = 0;
};

}  // namespace suffuse
