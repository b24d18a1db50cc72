// Shape functions: partition of unity, zero gradient sum, exact linear fields;
// supports inside the grid.
#include <gtest/gtest.h>

#include <map>
#include <memory>
#include <random>
#include <string>
#include <tuple>
#include <suffuse/plugin_loader.hpp>

#include "mpm/point_supports.hpp"

namespace {

// The bundled plugins, loaded for as long as a shape function made from them lives.
struct Bundled {
  suffuse::Registry registry;
  suffuse::PluginLoader loader{registry};
  Bundled() { loader.load_directory(suffuse::PluginLoader::bundled_plugin_directory()); }
  std::unique_ptr<suffuse::ShapeFunction> shape(const std::string& name, int dim) {
    return registry.create<suffuse::ShapeFunction>(name, {suffuse::Parameters{}, dim, "/shape_function"});
  }
};

// A shape function's values at points, node by node as the core forms them
// from the 1D factors (point_supports.hpp), after checking that every
// support lies in the grid.
struct Evaluated {
  int npp = 0;
  std::vector<suffuse::NodeId> ids;
  std::vector<double> w, dw;
};
Evaluated evaluate(const suffuse::ShapeFunction& shape, const suffuse::GridGeometry& grid,
                   const std::vector<double>& x, const std::vector<double>& sizes) {
  const int dim = grid.dim();
  const std::size_t n = x.size() / dim;
  suffuse::detail::PointSupports s;
  for (int a = 0; a < dim; ++a) {
    s.nodes[a] = shape.support(grid.nodes_per_axis()[a]);
    s.per_point += s.nodes[a];
  }
  s.stride = {1, grid.node_index(0, 1, 0), dim == 3 ? grid.node_index(0, 0, 1) : 0};
  std::vector<suffuse::NodeId> first(n);
  std::vector<double> weights(n * s.per_point), derivatives(n * s.per_point);
  shape.evaluate(grid, x, sizes, first, weights, derivatives);
  for (std::size_t p = 0; p < n; ++p) {
    const auto ijk = grid.node_ijk(first[p]);
    for (int a = 0; a < dim; ++a) {
      EXPECT_GE(ijk[a], 0) << "point " << p;
      EXPECT_LE(ijk[a] + s.nodes[a], grid.nodes_per_axis()[a]) << "point " << p << ", axis " << a;
    }
  }
  s.first = first.data(), s.weights = weights.data(), s.derivatives = derivatives.data();
  suffuse::detail::ExpandedSupports e;
  suffuse::detail::expand_supports(s, dim, n, e);
  return {e.npp, e.ids, e.weights, e.gradients};
}

using Case = std::tuple<std::string, int>;  // plugin, dimension

class ShapeFunctions : public ::testing::TestWithParam<Case> {};

TEST_P(ShapeFunctions, PartitionOfUnityAndLinearReproduction) {
  const auto& [name, dim] = GetParam();
  Bundled plugins;
  auto shape = plugins.shape(name, dim);
  const suffuse::GridGeometry grid(dim, {-1.0, 0.5, 2.0}, {0.3, 0.2, 0.7}, {7, 9, 4});
  for (int nodes : {2, 3, 8}) EXPECT_EQ(shape->support(nodes), name == "shape/linear" ? 2 : std::min(nodes, 3));

  const std::size_t n = 1000;
  std::mt19937 rng(42);
  // Point domains of a quarter to a full cell; GIMP keeps the partition of
  // unity while a point's domain lies inside the grid, so points are placed
  // half a size away from the boundary (linear: on it too).
  std::vector<double> x(n * dim), sizes(n * dim);
  for (std::size_t p = 0; p < n; ++p)
    for (int a = 0; a < dim; ++a) {
      const double h = grid.cell_size()[a];
      sizes[p * dim + a] = std::uniform_real_distribution<double>(0.25 * h, h)(rng);
      const double margin = name == "shape/linear" ? 0.0 : 0.5 * sizes[p * dim + a];
      std::uniform_real_distribution<double> u(grid.origin()[a] + margin, grid.upper(a) - margin);
      x[p * dim + a] = u(rng);
    }
  if (name == "shape/linear") {
    // Points exactly on the boundary faces and nodes must work too.
    for (int a = 0; a < dim; ++a) {
      x[a] = grid.origin()[a];
      x[dim + a] = grid.upper(a);
    }
  }
  const auto [npp, ids, w, dw] = evaluate(*shape, grid, x, sizes);
  ASSERT_EQ(npp, name == "shape/linear" ? (1 << dim) : (dim == 2 ? 9 : 27));

  // A linear field f(x) = c0 + c . x is reproduced exactly, and so is its gradient.
  const double c0 = 0.7, c[3] = {1.5, -2.25, 0.5};
  for (std::size_t p = 0; p < n; ++p) {
    double sum = 0, f = 0, grad_sum[3] = {}, grad_f[3] = {};
    for (int k = 0; k < npp; ++k) {
      const std::size_t s = p * npp + k;
      ASSERT_GE(ids[s], 0);
      ASSERT_LT(static_cast<std::size_t>(ids[s]), grid.node_count());
      EXPECT_GE(w[s], -1e-15);
      const auto xn = grid.node_position(ids[s]);
      double fn = c0;
      for (int a = 0; a < dim; ++a) fn += c[a] * xn[a];
      sum += w[s];
      f += w[s] * fn;
      for (int a = 0; a < dim; ++a) {
        grad_sum[a] += dw[s * dim + a];
        grad_f[a] += dw[s * dim + a] * fn;
      }
    }
    double exact = c0;
    for (int a = 0; a < dim; ++a) exact += c[a] * x[p * dim + a];
    EXPECT_NEAR(sum, 1.0, 1e-13);
    EXPECT_NEAR(f, exact, 1e-12);
    for (int a = 0; a < dim; ++a) {
      EXPECT_NEAR(grad_sum[a], 0.0, 1e-11);
      EXPECT_NEAR(grad_f[a], c[a], 1e-11);
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Plugins, ShapeFunctions,
                         ::testing::Combine(::testing::Values("shape/linear", "shape/gimp"), ::testing::Values(2, 3)),
                         [](const auto& info) {
                           return std::get<0>(info.param).substr(6) + "_" + std::to_string(std::get<1>(info.param)) +
                                  "d";
                         });

// GIMP weights are continuous when a point crosses a cell face; linear
// gradients jump there (the cell-crossing error GIMP removes).
TEST(ShapeFunctions, GimpIsContinuousAcrossCellFaces) {
  Bundled plugins;
  auto gimp = plugins.shape("shape/gimp", 2);
  const suffuse::GridGeometry grid(2, {0, 0, 0}, {1, 1, 1}, {4, 4, 1});
  const double eps = 1e-9;
  const std::vector<double> x = {2 - eps, 1.5, 2 + eps, 1.5}, sizes = {0.5, 0.5, 0.5, 0.5};
  const auto [npp, ids, w, dw] = evaluate(*gimp, grid, x, sizes);
  // Sum each node's weight and x-gradient over both points' stencils, per point.
  std::map<std::int64_t, double> w0, w1, g0, g1;
  for (int k = 0; k < 9; ++k) {
    w0[ids[k]] += w[k];
    g0[ids[k]] += dw[2 * k];
    w1[ids[9 + k]] += w[9 + k];
    g1[ids[9 + k]] += dw[2 * (9 + k)];
  }
  for (std::int64_t I = 0; I < static_cast<std::int64_t>(grid.node_count()); ++I) {
    EXPECT_NEAR(w0[I], w1[I], 1e-8) << "node " << I;
    EXPECT_NEAR(g0[I], g1[I], 1e-8) << "node " << I;
  }
}

// GIMP at the grid boundary: a point whose box reaches past the grid lumps
// the missing node's weight on the boundary node, so the weights still sum
// to 1 and the gradients to 0 (a uniform flow has no divergence there).
TEST(ShapeFunctions, GimpKeepsPartitionOfUnityAtTheGridBoundary) {
  Bundled plugins;
  auto gimp = plugins.shape("shape/gimp", 2);
  const suffuse::GridGeometry grid(2, {0, 0, 0}, {1, 1, 1}, {4, 4, 1});
  // Points in the first and last half cells, boxes of half a cell; the last
  // two, boxes of a cell, have left the grid by more than half a cell, as a
  // point may have in the output frame written after the step that moved it.
  const std::vector<double> x = {0.1, 2.0, 3.9, 0.05, 0.25, 3.75, 2.5, 0.2, -0.7, 2.0, 1.5, -0.6};
  std::vector<double> sizes(x.size(), 0.5);
  for (std::size_t k = 8; k < sizes.size(); ++k) sizes[k] = 1.0;
  const std::size_t n = x.size() / 2;
  const auto [npp, ids, w, dw] = evaluate(*gimp, grid, x, sizes);
  for (std::size_t p = 0; p < n; ++p) {
    double sum = 0, gx = 0, gy = 0;
    for (int k = 0; k < 9; ++k) {
      EXPECT_GE(w[9 * p + k], 0.0);
      sum += w[9 * p + k];
      gx += dw[2 * (9 * p + k)];
      gy += dw[2 * (9 * p + k) + 1];
    }
    EXPECT_NEAR(sum, 1.0, 1e-14) << "point " << p;
    EXPECT_NEAR(gx, 0.0, 1e-14) << "point " << p;
    EXPECT_NEAR(gy, 0.0, 1e-14) << "point " << p;
  }
}

// On an axis of one cell (a column one cell wide) GIMP spans the axis's two
// nodes, with the weight of the nodes past the grid lumped on them.
TEST(ShapeFunctions, GimpOnAnAxisOfOneCell) {
  Bundled plugins;
  auto gimp = plugins.shape("shape/gimp", 2);
  const suffuse::GridGeometry grid(2, {0, 0, 0}, {1, 1, 1}, {1, 4, 1});
  const std::vector<double> x = {0.25, 0.3, 0.75, 2.6, 0.5, 3.7}, sizes(6, 0.5);
  const auto [npp, ids, w, dw] = evaluate(*gimp, grid, x, sizes);
  ASSERT_EQ(npp, 6);
  for (std::size_t p = 0; p < 3; ++p) {
    double sum = 0, gx = 0, f = 0;
    for (int k = 0; k < npp; ++k) {
      const std::size_t q = p * npp + k;
      sum += w[q], gx += dw[2 * q], f += w[q] * grid.node_position(ids[q])[1];
    }
    EXPECT_NEAR(sum, 1.0, 1e-14) << "point " << p;
    EXPECT_NEAR(gx, 0.0, 1e-14) << "point " << p;
    EXPECT_NEAR(f, x[2 * p + 1], 1e-12) << "point " << p << ": y is reproduced";
  }
}

// A point a cell and a half or more past the grid (an output frame may
// project one before the next step refuses it) reaches no node: zero
// weights and gradients, its support still inside the grid.
TEST(ShapeFunctions, GimpPointFarPastTheGridReachesNoNode) {
  Bundled plugins;
  auto gimp = plugins.shape("shape/gimp", 2);
  const suffuse::GridGeometry grid(2, {0, 0, 0}, {1, 1, 1}, {4, 4, 1});
  const std::vector<double> x = {-2.0, 2.0, 2.0, 6.1}, sizes(4, 1.0);
  const auto [npp, ids, w, dw] = evaluate(*gimp, grid, x, sizes);
  for (std::size_t q = 0; q < w.size(); ++q) {
    EXPECT_EQ(w[q], 0.0);
    EXPECT_EQ(dw[2 * q], 0.0);
    EXPECT_EQ(dw[2 * q + 1], 0.0);
  }
}

}  // namespace
