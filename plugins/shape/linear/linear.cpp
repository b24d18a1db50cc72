// shape/linear: bilinear (2D) and trilinear (3D) shape functions on the
// regular grid, C0 across cell faces (the classic MPM choice; cell-crossing
// noise is what shape/gimp would reduce).
#include <algorithm>
#include <cmath>
#include <suffuse/plugin.hpp>

namespace {

using suffuse::GridGeometry;
using suffuse::NodeId;

// Per axis: the cell's two nodes, weights 1 - xi and xi, derivatives
// -1/h and 1/h.
template <int D>
void evaluate_linear(const GridGeometry& grid, const double* x, std::size_t n, NodeId* first, double* w,
                     double* dw) {
  const auto& o = grid.origin();
  const auto& h = grid.cell_size();
  const auto& cells = grid.cells();
  for (std::size_t p = 0; p < n; ++p) {
    int c[3] = {0, 0, 0};
    double *s1 = w + p * 2 * D, *d1 = dw + p * 2 * D;
    for (int a = 0; a < D; ++a) {
      const double s = (x[p * D + a] - o[a]) / h[a];
      // A truncation is the floor here (s >= 0 up to round-off, and the
      // clamp takes care of that), without floor's library call.
      c[a] = std::clamp(static_cast<int>(s), 0, cells[a] - 1);
      const double xi = s - c[a], inv_h = 1.0 / h[a];
      s1[2 * a] = 1.0 - xi, s1[2 * a + 1] = xi;
      d1[2 * a] = -inv_h, d1[2 * a + 1] = inv_h;
    }
    first[p] = static_cast<NodeId>(grid.node_index(c[0], D > 1 ? c[1] : 0, D > 2 ? c[2] : 0));
  }
}

class LinearShape final : public suffuse::ShapeFunction {
 public:
  static suffuse::ParameterSchema schema() { return {}; }
  explicit LinearShape(const suffuse::PluginArgs&) {}

  int support(int /*nodes*/) const override { return 2; }

  void evaluate(const GridGeometry& grid, std::span<const double> positions, std::span<const double> /*sizes*/,
                std::span<NodeId> first_nodes, std::span<double> weights,
                std::span<double> derivatives) const override {
    const std::size_t n = positions.size() / grid.dim();
    if (grid.dim() == 2)
      evaluate_linear<2>(grid, positions.data(), n, first_nodes.data(), weights.data(), derivatives.data());
    else
      evaluate_linear<3>(grid, positions.data(), n, first_nodes.data(), weights.data(), derivatives.data());
  }
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::ShapeFunction, LinearShape>(
      "shape/linear", "Bilinear (2D) / trilinear (3D) nodal shape functions of the background grid");
}
