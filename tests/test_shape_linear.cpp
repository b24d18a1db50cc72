// shape/linear: partition of unity, zero gradient sum, exact linear fields.
#include <gtest/gtest.h>

#include <random>
#include <suffuse/plugin_loader.hpp>

namespace {

struct Case {
  int dim;
};

class LinearShape : public ::testing::TestWithParam<int> {};

TEST_P(LinearShape, PartitionOfUnityAndLinearReproduction) {
  const int dim = GetParam();
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_directory(suffuse::PluginLoader::bundled_plugin_directory());
  suffuse::Parameters none;
  auto shape = registry.create<suffuse::ShapeFunction>("shape/linear", {none, dim, "/shape_function"});
  const suffuse::GridGeometry grid(dim, {-1.0, 0.5, 2.0}, {0.3, 0.2, 0.7}, {7, 9, 4});
  const int npp = shape->nodes_per_point(dim);
  ASSERT_EQ(npp, 1 << dim);

  const std::size_t n = 1000;
  std::mt19937 rng(42);
  std::vector<double> x(n * dim);
  for (std::size_t p = 0; p < n; ++p)
    for (int a = 0; a < dim; ++a) {
      std::uniform_real_distribution<double> u(grid.origin()[a], grid.upper(a));
      x[p * dim + a] = u(rng);
    }
  // Points exactly on the boundary faces and nodes must work too.
  for (int a = 0; a < dim; ++a) {
    x[a] = grid.origin()[a];
    x[dim + a] = grid.upper(a);
  }
  const std::vector<double> sizes(n * dim, 0.05);
  std::vector<std::int64_t> ids(n * npp);
  std::vector<double> w(n * npp), dw(n * npp * dim);
  shape->evaluate(grid, x, sizes, ids, w, dw);

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

INSTANTIATE_TEST_SUITE_P(Dimensions, LinearShape, ::testing::Values(2, 3));

}  // namespace
