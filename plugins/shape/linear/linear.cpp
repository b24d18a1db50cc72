// shape/linear: bilinear (2D) and trilinear (3D) shape functions on the
// regular grid, C0 across cell faces (the classic MPM choice; cell-crossing
// noise is what shape/gimp would reduce).
#include <algorithm>
#include <cmath>
#include <suffuse/plugin.hpp>

namespace {

using suffuse::GridGeometry;
using suffuse::NodeId;

template <int D>
void evaluate_linear(const GridGeometry& grid, const double* x, std::size_t n, NodeId* ids, double* w,
                     double* dw) {
  constexpr int npp = 1 << D;
  const auto& o = grid.origin();
  const auto& h = grid.cell_size();
  const auto& cells = grid.cells();
  for (std::size_t p = 0; p < n; ++p) {
    int c[3] = {0, 0, 0};
    double xi[D], inv_h[D];
    for (int a = 0; a < D; ++a) {
      const double s = (x[p * D + a] - o[a]) / h[a];
      // A truncation is the floor here (s >= 0 up to round-off, and the
      // clamp takes care of that), without floor's library call.
      c[a] = std::clamp(static_cast<int>(s), 0, cells[a] - 1);
      xi[a] = s - c[a];
      inv_h[a] = 1.0 / h[a];
    }
    for (int k = 0; k < npp; ++k) {
      int off[3] = {k & 1, (k >> 1) & 1, (k >> 2) & 1};
      double n1[D], d1[D];
      for (int a = 0; a < D; ++a) {
        n1[a] = off[a] ? xi[a] : 1.0 - xi[a];
        d1[a] = (off[a] ? 1.0 : -1.0) * inv_h[a];
      }
      const std::size_t slot = p * npp + k;
      ids[slot] = grid.node_index(c[0] + off[0], D > 1 ? c[1] + off[1] : 0, D > 2 ? c[2] + off[2] : 0);
      double weight = 1;
      for (int a = 0; a < D; ++a) weight *= n1[a];
      w[slot] = weight;
      for (int a = 0; a < D; ++a) {
        double g = d1[a];
        for (int b = 0; b < D; ++b)
          if (b != a) g *= n1[b];
        dw[slot * D + a] = g;
      }
    }
  }
}

class LinearShape final : public suffuse::ShapeFunction {
 public:
  static suffuse::ParameterSchema schema() { return {}; }
  explicit LinearShape(const suffuse::PluginArgs&) {}

  int nodes_per_point(int dim) const override { return 1 << dim; }

  void evaluate(const GridGeometry& grid, std::span<const double> positions, std::span<const double> /*sizes*/,
                std::span<NodeId> node_ids, std::span<double> weights,
                std::span<double> gradients) const override {
    const std::size_t n = positions.size() / grid.dim();
    if (grid.dim() == 2)
      evaluate_linear<2>(grid, positions.data(), n, node_ids.data(), weights.data(), gradients.data());
    else
      evaluate_linear<3>(grid, positions.data(), n, node_ids.data(), weights.data(), gradients.data());
  }
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::ShapeFunction, LinearShape>(
      "shape/linear", "Bilinear (2D) / trilinear (3D) nodal shape functions of the background grid");
}
