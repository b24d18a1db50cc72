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

// 1D uGIMP weight and derivative for node distance r, cell size h, half-size lp.
inline void gimp_1d(double r, double h, double lp, double& s, double& ds) {
  const double a = std::abs(r), sign = r < 0 ? -1.0 : 1.0;
  if (a < lp) {
    s = 1 - (r * r + lp * lp) / (2 * h * lp);
    ds = -r / (h * lp);
  } else if (a < h - lp) {
    s = 1 - a / h;
    ds = -sign / h;
  } else if (a < h + lp) {
    const double t = h + lp - a;
    s = t * t / (4 * h * lp);
    ds = -sign * t / (2 * h * lp);
  } else {
    s = 0;
    ds = 0;
  }
}

template <int D>
void evaluate_gimp(const GridGeometry& grid, const double* x, const double* size, std::size_t n, std::int64_t* ids,
                   double* w, double* dw) {
  constexpr int npp = D == 2 ? 9 : 27;
  const auto& o = grid.origin();
  const auto& h = grid.cell_size();
  const auto& nodes = grid.nodes_per_axis();
  for (std::size_t p = 0; p < n; ++p) {
    int base[3] = {0, 0, 0};
    double s1[3][3] = {}, d1[3][3] = {};
    bool valid[3][3] = {};
    for (int a = 0; a < D; ++a) {
      const double lp = std::min(0.5 * size[p * D + a], 0.5 * h[a]);
      const double xi = (x[p * D + a] - o[a]) / h[a];
      base[a] = static_cast<int>(std::lround(xi)) - 1;  // nearest node and its two neighbours
      for (int k = 0; k < 3; ++k) {
        const int node = base[a] + k;
        valid[a][k] = node >= 0 && node < nodes[a];
        gimp_1d(x[p * D + a] - (o[a] + node * h[a]), h[a], lp, s1[a][k], d1[a][k]);
      }
      // Outermost first, so a weight passed inwards is passed on again if
      // the next node is missing too.
      for (int k : {0, 1, 2, 1}) {
        if (valid[a][k] || (s1[a][k] == 0 && d1[a][k] == 0)) continue;
        const int into = base[a] + k < 0 ? k + 1 : k - 1;  // the neighbour towards the grid
        s1[a][into] += s1[a][k];
        d1[a][into] += d1[a][k];
        s1[a][k] = d1[a][k] = 0;
      }
    }
    for (int k = 0; k < npp; ++k) {
      const int off[3] = {k % 3, (k / 3) % 3, k / 9};
      const std::size_t slot = p * npp + k;
      bool inside = true;
      int ijk[3] = {0, 0, 0};
      for (int a = 0; a < D; ++a) {
        inside = inside && valid[a][off[a]];
        ijk[a] = std::clamp(base[a] + off[a], 0, nodes[a] - 1);
      }
      ids[slot] = grid.node_index(ijk[0], ijk[1], ijk[2]);
      if (!inside) {
        w[slot] = 0;
        for (int a = 0; a < D; ++a) dw[slot * D + a] = 0;
        continue;
      }
      double weight = 1;
      for (int a = 0; a < D; ++a) weight *= s1[a][off[a]];
      w[slot] = weight;
      for (int a = 0; a < D; ++a) {
        double g = d1[a][off[a]];
        for (int b = 0; b < D; ++b)
          if (b != a) g *= s1[b][off[b]];
        dw[slot * D + a] = g;
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
                std::span<std::int64_t> node_ids, std::span<double> weights,
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
