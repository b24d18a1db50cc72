// shape/gimp: uniform GIMP (Bardenhagen & Kober 2004). Each point is a box of
// its initial size; its weight on a node is the linear hat function averaged
// over the box. Weights and gradients are continuous when a point crosses a
// cell face, which removes the cell-crossing noise of shape/linear.
// Support: 3 nodes per axis (9 in 2D, 27 in 3D) while the half-size is at
// most half a cell (2 on an axis of one cell). Where a point's box reaches past the grid, the weight of
// the missing node is lumped on the boundary node of that axis (a ghost node
// moving with it), so the weights still sum to 1 and the gradients to 0: a
// uniform flow through a grid face has no spurious divergence there.
#include <algorithm>
#include <cmath>
#include <suffuse/plugin.hpp>

namespace {

using suffuse::GridGeometry;
using suffuse::NodeId;

// 1D uGIMP weight and derivative for node distance r, cell size h, half-size
// lp (with 1/h and 1/(h lp) given). All three pieces are formed and one is
// selected: the piece changes from node to node, and a branch on it is
// mispredicted about as often as not.
inline void gimp_1d(double r, double h, double lp, double inv_h, double inv_hlp, double& s, double& ds) {
  const double a = std::abs(r), sign = r < 0 ? -1.0 : 1.0, t = h + lp - a;
  const double s_inside = 1 - (r * r + lp * lp) * (0.5 * inv_hlp), ds_inside = -r * inv_hlp;
  const double s_linear = 1 - a * inv_h, ds_linear = -sign * inv_h;
  const double s_edge = t * t * (0.25 * inv_hlp), ds_edge = -sign * t * (0.5 * inv_hlp);
  const bool inside = a < lp, linear = a < h - lp, edge = a < h + lp;
  s = inside ? s_inside : linear ? s_linear : edge ? s_edge : 0.0;
  ds = inside ? ds_inside : linear ? ds_linear : edge ? ds_edge : 0.0;
}

// Points are evaluated in blocks, axis by axis: first the nearest node and
// the three nodes' factors of every point of the block, a loop across points
// that vectorises (built for AVX2 too, chosen when the library is loaded);
// then per point the rare lumping at the grid's edge. The same operations
// on the same values as one point at a time: the same bits.
constexpr std::size_t block = 64;

// One axis of a block: the nearest node minus one, and the factors of it and
// the next two nodes.
struct AxisFactors {
  int base[block];
  double s[3][block], ds[3][block];
};

#if defined(__x86_64__) && defined(__GNUC__)
#define SUFFUSE_GIMP_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SUFFUSE_GIMP_CLONES
#endif

SUFFUSE_GIMP_CLONES void gimp_axis(const double* x, const double* size, std::size_t n, double o, double h,
                                   double inv_h, AxisFactors& out) {
  for (std::size_t j = 0; j < n; ++j) {
    const double lp = std::min(0.5 * size[j], 0.5 * h), inv_hlp = 1 / (h * lp);
    // The nearest node: floor(xi + 1/2), from a truncation without floor's
    // library call (the correction is for a point off the grid, which an
    // output frame may still project).
    const double c = (x[j] - o) * inv_h + 0.5;
    const int t = static_cast<int>(c), base = t - (c < t ? 1 : 0) - 1;
    out.base[j] = base;
    for (int k = 0; k < 3; ++k) gimp_1d(x[j] - (o + (base + k) * h), h, lp, inv_h, inv_hlp, out.s[k][j], out.ds[k][j]);
  }
}

// Per axis: the nearest node and its two neighbours, with the weight of a
// node past the grid lumped on its neighbour towards the grid, then shifted
// so that the support's three nodes (two on a one-cell axis) are all in the
// grid: a node past the grid's edge is replaced by the node on the other side
// of the support, with zero factors.
template <int D>
void evaluate_gimp(const GridGeometry& grid, const double* x, const double* size, std::size_t n, NodeId* first,
                   double* weights, double* derivatives) {
  const auto& o = grid.origin();
  const auto& h = grid.cell_size();
  const auto& nodes = grid.nodes_per_axis();
  const double inv_h[3] = {1 / h[0], 1 / h[1], 1 / h[2]};
  int start[3] = {0, 0, 0};
  double *s = weights, *ds = derivatives;
  AxisFactors axis[D];
  double xa[block], sa[block];
  for (std::size_t p0 = 0; p0 < n; p0 += block) {
    const std::size_t count = std::min(block, n - p0);
    for (int a = 0; a < D; ++a) {
      for (std::size_t j = 0; j < count; ++j) xa[j] = x[(p0 + j) * D + a], sa[j] = size[(p0 + j) * D + a];
      gimp_axis(xa, sa, count, o[a], h[a], inv_h[a], axis[a]);
    }
    for (std::size_t j = 0; j < count; ++j) {
      for (int a = 0; a < D; ++a) {
        const AxisFactors& f = axis[a];
        const int base = f.base[j];
        const int m = std::min(3, nodes[a]);
        if (base >= 0 && base + 2 < nodes[a]) {  // nearly every point
          start[a] = base;
          for (int k = 0; k < 3; ++k) s[k] = f.s[k][j], ds[k] = f.ds[k][j];
          s += m, ds += m;
          continue;
        }
        double s1[3], d1[3];
        for (int k = 0; k < 3; ++k) s1[k] = f.s[k][j], d1[k] = f.ds[k][j];
        bool valid[3];
        for (int k = 0; k < 3; ++k) valid[k] = base + k >= 0 && base + k < nodes[a];
        // Outermost first, so a weight passed inwards is passed on again if
        // the next node is missing too. A point a cell and a half or more past
        // the grid (an output frame may project one) reaches no node: its
        // weight has nowhere to go and is dropped.
        for (int k : {0, 1, 2, 1}) {
          if (valid[k] || (s1[k] == 0 && d1[k] == 0)) continue;
          const int into = base + k < 0 ? k + 1 : k - 1;  // the neighbour towards the grid
          if (into >= 0 && into < 3) s1[into] += s1[k], d1[into] += d1[k];
          s1[k] = d1[k] = 0;
        }
        start[a] = std::clamp(base, 0, nodes[a] - m);
        for (int k = 0; k < m; ++k) s[k] = ds[k] = 0;
        for (int k = 0; k < 3; ++k)
          if (valid[k]) s[base + k - start[a]] = s1[k], ds[base + k - start[a]] = d1[k];
        s += m, ds += m;
      }
      first[p0 + j] = static_cast<NodeId>(grid.node_index(start[0], start[1], D == 3 ? start[2] : 0));
    }
  }
}

class GimpShape final : public suffuse::ShapeFunction {
 public:
  static suffuse::ParameterSchema schema() { return {}; }
  explicit GimpShape(const suffuse::PluginArgs&) {}

  int support(int nodes) const override { return nodes < 3 ? nodes : 3; }

  void evaluate(const GridGeometry& grid, std::span<const double> positions, std::span<const double> sizes,
                std::span<NodeId> first_nodes, std::span<double> weights,
                std::span<double> derivatives) const override {
    const std::size_t n = positions.size() / grid.dim();
    if (grid.dim() == 2)
      evaluate_gimp<2>(grid, positions.data(), sizes.data(), n, first_nodes.data(), weights.data(),
                       derivatives.data());
    else
      evaluate_gimp<3>(grid, positions.data(), sizes.data(), n, first_nodes.data(), weights.data(),
                       derivatives.data());
  }
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::ShapeFunction, GimpShape>(
      "shape/gimp", "Uniform GIMP: point-domain-averaged linear shape functions, free of cell-crossing noise");
}
