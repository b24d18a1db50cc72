// shape/gimp: uniform GIMP (Bardenhagen & Kober 2004). Each point is a box of
// its initial size; its weight on a node is the linear hat function averaged
// over the box. Weights and gradients are continuous when a point crosses a
// cell face, which removes the cell-crossing noise of shape/linear.
// Support: 3 nodes per axis (9 in 2D, 27 in 3D) while the half-size is at
// most half a cell. Where a point's box reaches past the grid, the weight of
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

// Slot order: the first axis fastest (k = i + 3 j + 9 l), as the scatter
// sums depend on it.
template <int D>
void evaluate_gimp(const GridGeometry& grid, const double* x, const double* size, std::size_t n, NodeId* ids,
                   double* w, double* dw) {
  constexpr int npp = D == 2 ? 9 : 27;
  const auto& o = grid.origin();
  const auto& h = grid.cell_size();
  const auto& nodes = grid.nodes_per_axis();
  const double inv_h[3] = {1 / h[0], 1 / h[1], 1 / h[2]};
  const std::int64_t stride[3] = {1, grid.node_index(0, 1, 0), grid.node_index(0, 0, 1)};
  for (std::size_t p = 0; p < n; ++p) {
    double s1[3][3] = {}, d1[3][3] = {};
    bool valid[3][3] = {{true, true, true}, {true, true, true}, {true, true, true}};
    int node[3][3] = {};  // clamped to the grid: a missing node's slot names its neighbour, with weight 0
    bool interior = true;
    for (int a = 0; a < D; ++a) {
      const double lp = std::min(0.5 * size[p * D + a], 0.5 * h[a]), inv_hlp = 1 / (h[a] * lp);
      const double xi = (x[p * D + a] - o[a]) * inv_h[a];
      // The nearest node and its two neighbours: floor(xi + 1/2), from a
      // truncation without floor's library call (the correction is for a
      // point off the grid, which an output frame may still project).
      const double c = xi + 0.5;
      const int t = static_cast<int>(c), base = t - (c < t ? 1 : 0) - 1;
      for (int k = 0; k < 3; ++k) {
        const int i = base + k;
        gimp_1d(x[p * D + a] - (o[a] + i * h[a]), h[a], lp, inv_h[a], inv_hlp, s1[a][k], d1[a][k]);
      }
      for (int k = 0; k < 3; ++k) node[a][k] = base + k;
      if (base >= 0 && base + 2 < nodes[a]) continue;
      interior = false;
      for (int k = 0; k < 3; ++k) {
        valid[a][k] = node[a][k] >= 0 && node[a][k] < nodes[a];
        node[a][k] = std::clamp(node[a][k], 0, nodes[a] - 1);
      }
      // Outermost first, so a weight passed inwards is passed on again if
      // the next node is missing too.
      for (int k : {0, 1, 2, 1}) {
        if (valid[a][k] || (s1[a][k] == 0 && d1[a][k] == 0)) continue;
        const int into = base + k < 0 ? k + 1 : k - 1;  // the neighbour towards the grid
        s1[a][into] += s1[a][k];
        d1[a][into] += d1[a][k];
        s1[a][k] = d1[a][k] = 0;
      }
    }
    // The weight of slot (i, j, l) and its gradient, from the 1D factors.
    const auto put = [&](std::size_t slot, int i, int j, int l) {
      double* g = dw + slot * D;
      if constexpr (D == 2) {
        w[slot] = s1[0][i] * s1[1][j];
        g[0] = d1[0][i] * s1[1][j];
        g[1] = d1[1][j] * s1[0][i];
      } else {
        w[slot] = s1[0][i] * s1[1][j] * s1[2][l];
        g[0] = d1[0][i] * s1[1][j] * s1[2][l];
        g[1] = d1[1][j] * s1[0][i] * s1[2][l];
        g[2] = d1[2][l] * s1[0][i] * s1[1][j];
      }
    };
    std::size_t slot = p * npp;
    constexpr int layers = D == 3 ? 3 : 1;
    if (interior) {
      // Every node of the support is in the grid (nearly every point): the
      // ids step by the grid's strides, and no weight was lumped.
      const std::int64_t first = grid.node_index(node[0][0], node[1][0], D == 3 ? node[2][0] : 0);
      for (int l = 0; l < layers; ++l)
        for (int j = 0; j < 3; ++j)
          for (int i = 0; i < 3; ++i, ++slot) {
            ids[slot] = first + i + j * stride[1] + l * stride[2];
            put(slot, i, j, l);
          }
      continue;
    }
    for (int l = 0; l < layers; ++l)
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < 3; ++i, ++slot) {
          ids[slot] = grid.node_index(node[0][i], node[1][j], D == 3 ? node[2][l] : 0);
          if (valid[0][i] && valid[1][j] && (D == 2 || valid[2][l])) {
            put(slot, i, j, l);
          } else {
            w[slot] = 0;
            for (int a = 0; a < D; ++a) dw[slot * D + a] = 0;
          }
        }
  }
}

class GimpShape final : public suffuse::ShapeFunction {
 public:
  static suffuse::ParameterSchema schema() { return {}; }
  explicit GimpShape(const suffuse::PluginArgs&) {}

  int nodes_per_point(int dim) const override { return dim == 2 ? 9 : 27; }

  void evaluate(const GridGeometry& grid, std::span<const double> positions, std::span<const double> sizes,
                std::span<NodeId> node_ids, std::span<double> weights,
                std::span<double> gradients) const override {
    const std::size_t n = positions.size() / grid.dim();
    if (grid.dim() == 2)
      evaluate_gimp<2>(grid, positions.data(), sizes.data(), n, node_ids.data(), weights.data(), gradients.data());
    else
      evaluate_gimp<3>(grid, positions.data(), sizes.data(), n, node_ids.data(), weights.data(), gradients.data());
  }
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::ShapeFunction, GimpShape>(
      "shape/gimp", "Uniform GIMP: point-domain-averaged linear shape functions, free of cell-crossing noise");
}
