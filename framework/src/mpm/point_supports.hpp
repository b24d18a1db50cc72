#pragma once
// The nodes each point reaches, with the weight and gradient of each, formed
// from the shape function's 1D factors (shape_function.hpp) where a kernel
// uses them: per point a first node, m_0 + ... + m_{D-1} 1D weights and as
// many derivatives, instead of m_0 ... m_{D-1} node ids, weights and
// gradients. A point's
// nodes are visited in slot order, the first axis fastest, as the scatters'
// sums depend on it.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "suffuse/grid.hpp"

namespace suffuse::detail {

struct PointSupports {
  const NodeId* first = nullptr;  // per point: its support's first node
  const double* weights = nullptr;      // per point: per_point 1D weights, axis by axis
  const double* derivatives = nullptr;  // and their derivatives
  int per_point = 0;
  std::array<int, 3> nodes{1, 1, 1};        // support nodes along each axis (1 past the dimension)
  std::array<std::int64_t, 3> stride{};     // node index step along each axis
  int nodes_per_point() const { return nodes[0] * nodes[1] * nodes[2]; }
  // The last node of a support less its first.
  std::int64_t extent() const {
    return (nodes[0] - 1) * stride[0] + (nodes[1] - 1) * stride[1] + (nodes[2] - 1) * stride[2];
  }
};

// The loops over a point's nodes, for MX x MY (x MZ) nodes known when
// compiled (fully unrolled: 2 for bi/trilinear, 3 for GIMP) or, with 0, as
// the supports say. Weight: f(node, N); with a gradient: f(node, N, grad).
template <int D, int MX, int MY, int MZ, bool Gradient, class F>
[[gnu::always_inline]] inline void visit_nodes(const PointSupports& s, std::size_t p, F& f) {
  const std::size_t at = p * static_cast<std::size_t>(s.per_point);
  const int mx = MX ? MX : s.nodes[0], my = MY ? MY : s.nodes[1], mz = D == 2 ? 1 : MZ ? MZ : s.nodes[2];
  const double *sx = s.weights + at, *sy = sx + mx, *sz = sy + my;
  const double *dx = s.derivatives + at, *dy = dx + mx, *dz = dy + my;
  std::size_t row = static_cast<std::size_t>(s.first[p]);
  const std::int64_t next_layer = s.stride[2] - my * s.stride[1];
#pragma GCC unroll 3
  for (int k = 0; k < mz; ++k, row += next_layer)
#pragma GCC unroll 3
    for (int j = 0; j < my; ++j, row += s.stride[1])
#pragma GCC unroll 3
      for (int i = 0; i < mx; ++i) {
        if constexpr (D == 2) {
          if constexpr (Gradient) {
            const double grad[2] = {dx[i] * sy[j], dy[j] * sx[i]};
            f(row + i, sx[i] * sy[j], grad);
          } else {
            f(row + i, sx[i] * sy[j]);
          }
        } else {
          if constexpr (Gradient) {
            const double grad[3] = {dx[i] * sy[j] * sz[k], dy[j] * sx[i] * sz[k], dz[k] * sx[i] * sy[j]};
            f(row + i, sx[i] * sy[j] * sz[k], grad);
          } else {
            f(row + i, sx[i] * sy[j] * sz[k]);
          }
        }
      }
}

// The common supports with their loops unrolled; a run's supports are the
// same for every point, so the branch is always taken the same way.
template <int D, bool Gradient, class F>
[[gnu::always_inline]] inline void visit_point(const PointSupports& s, std::size_t p, F& f) {
  const bool cube2 = s.nodes[0] == 2 && s.nodes[1] == 2 && (D == 2 || s.nodes[2] == 2);
  const bool cube3 = s.nodes[0] == 3 && s.nodes[1] == 3 && (D == 2 || s.nodes[2] == 3);
  if (cube2)
    visit_nodes<D, 2, 2, 2, Gradient>(s, p, f);
  else if (cube3)
    visit_nodes<D, 3, 3, 3, Gradient>(s, p, f);
  else
    visit_nodes<D, 0, 0, 0, Gradient>(s, p, f);
}

// f(node, N, grad) for each node of point p, grad holding D components.
template <int D, class F>
[[gnu::always_inline]] inline void for_each_node(const PointSupports& s, std::size_t p, F&& f) {
  visit_point<D, true>(s, p, f);
}

// f(node, N) for each node of point p.
template <int D, class F>
[[gnu::always_inline]] inline void for_each_weight(const PointSupports& s, std::size_t p, F&& f) {
  visit_point<D, false>(s, p, f);
}

// f(node, grad) for each node of point p.
template <int D, class F>
[[gnu::always_inline]] inline void for_each_gradient(const PointSupports& s, std::size_t p, F&& f) {
  auto g = [&](std::size_t node, double, const double* grad) { f(node, grad); };
  visit_point<D, true>(s, p, g);
}

// The supports written out node by node (ids, weights, gradients), for the
// quasi-static assembly, which reads them many times per step.
struct ExpandedSupports {
  int npp = 0;  // nodes per point
  std::vector<NodeId> ids;
  std::vector<double> weights, gradients;
};
void expand_supports(const PointSupports& s, int dim, std::size_t points, ExpandedSupports& out);

}  // namespace suffuse::detail
