#pragma once
// Shape functions map between material points and grid nodes.
#include <cstdint>
#include <span>

#include "suffuse/grid.hpp"

namespace suffuse {

// A shape function of the regular grid is a product of one 1D factor per
// axis (bi/trilinear and GIMP are), and a plugin gives only the factors: a
// 2D GIMP point is 6 weights and 6 derivatives instead of 9 weights and 18
// gradient components, and the core forms each node's weight and gradient
// where a kernel uses them (a kernel that needs only the weights reads only
// them).
class ShapeFunction {
 public:
  virtual ~ShapeFunction() = default;

  // Nodes a point's support spans along an axis of `nodes` nodes (at least
  // 2), the same for every point: 2 for bi/trilinear, 3 for GIMP (2 where
  // the axis has one cell).
  virtual int support(int nodes) const = 0;

  // For a batch of n points (positions and sizes: n*dim; each point inside
  // the grid box; sizes are the edge lengths of the point's domain) fill
  // - first_nodes[p]: the node of the point's support with the lowest index
  //   on every axis. The support is the box of m_a = support(nodes on axis
  //   a) nodes along each axis from it, all of them in the grid;
  // - weights[p * M ...], M = m_0 + ... + m_{dim-1}: for each axis a in
  //   turn, the 1D weights s_a[0..m_a) of its support nodes;
  // - derivatives[p * M ...]: likewise their derivatives ds_a (d/dx_a).
  // The core forms the weight of support node (i, j, k) as s_0[i] s_1[j]
  // s_2[k] and its gradient as (ds_0[i] s_1[j] s_2[k], ds_1[j] s_0[i] s_2[k],
  // ds_2[k] s_0[i] s_1[j]), multiplied in that order. A node a point does not
  // reach has zero factors. Called once per step on large batches (one per
  // thread): never once per point.
  virtual void evaluate(const GridGeometry& grid, std::span<const double> positions,
                        std::span<const double> sizes, std::span<NodeId> first_nodes,
                        std::span<double> weights, std::span<double> derivatives) const = 0;
};

}  // namespace suffuse
