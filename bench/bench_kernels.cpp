// Each stage kernel of the explicit step on its own, on synthetic data: a 2D
// grid of 316 x 316 cells holding 2 x 2 points per cell (399,424 points, as
// bodies are made: row after row), interpolated by shape/linear or
// shape/gimp. items_per_second is points per second through the kernel, so a
// kernel's share of a step is its time over the step's (docs/performance.md).
// Run: ./build/bin/bench_kernels [--benchmark_filter=gimp]
#include <benchmark/benchmark.h>

#include <random>
#include <suffuse/phase.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/points.hpp>
#include <suffuse/shape_function.hpp>
#include <vector>

#include "mpm/domain.hpp"
#include "parallel/executor.hpp"
#include "mpm/solid_kernels.hpp"
#include "transport/species_kernels.hpp"
#include "mixture/two_phase_kernels.hpp"

namespace {

using namespace suffuse::detail;

constexpr int D = 2, cells = 316;
constexpr double h = 0.05;

// Points, nodal arrays and the interpolation of one step.
struct Synthetic {
  suffuse::Registry registry;
  suffuse::GridGeometry grid{D, {0.0, 0.0, 0.0}, {h, h, h}, {cells, cells, 1}};
  std::size_t n = 0, nodes = grid.node_count();
  Interpolation shape;
  std::vector<double> x, size, mass, volume, velocity, stress, L, strain, porosity, pressure, scalar;
  std::vector<double> node_mass, node_vector, node_vector2, node_force, node_scalar, node_scalar2;

  explicit Synthetic(const char* shape_name) {
    suffuse::PluginLoader loader(registry);
    loader.load_directory(suffuse::PluginLoader::bundled_plugin_directory());
    const auto shape = registry.create<suffuse::ShapeFunction>(shape_name, {suffuse::Parameters{}, D, "/shape_function"});
    for (int a = 0; a < D; ++a) {
      this->shape.nodes[a] = shape->support(grid.nodes_per_axis()[a]);
      this->shape.per_point += this->shape.nodes[a];
    }
    this->shape.stride = {1, grid.node_index(0, 1, 0), 0};
    std::mt19937 rng(1);
    std::uniform_real_distribution<double> jitter(-0.05 * h, 0.05 * h), unit(-1, 1);
    for (int j = 0; j < 2 * cells; ++j)
      for (int i = 0; i < 2 * cells; ++i) {
        x.push_back((i + 0.5) * h / 2 + jitter(rng));
        x.push_back((j + 0.5) * h / 2 + jitter(rng));
      }
    n = x.size() / D;
    size.assign(n * D, h / 2);
    mass.assign(n, 1.0);
    volume.assign(n, h * h / 4);
    porosity.assign(n, 0.3);
    for (auto* v : {&velocity, &stress, &pressure, &scalar, &L}) {
      const std::size_t m = v == &velocity ? n * D : v == &stress ? n * 6 : v == &L ? n * D * D : n;
      for (std::size_t k = 0; k < m; ++k) v->push_back(unit(rng));
    }
    strain.assign(n * 6, 0.0);
    this->shape.first.resize(n);
    this->shape.weights.resize(n * this->shape.per_point);
    this->shape.derivatives.resize(n * this->shape.per_point);
    shape->evaluate(grid, x, size, this->shape.first, this->shape.weights, this->shape.derivatives);
    node_mass.assign(nodes, 1.0);
    node_scalar.assign(nodes, 1.0);
    node_scalar2.assign(nodes, 0.5);
    for (auto* v : {&node_vector, &node_vector2, &node_force}) {
      v->resize(nodes * D);
      for (double& e : *v) e = unit(rng);
    }
    Executor(1).chunk_ranges(this->shape.first.data(), 1, n, this->shape.chunks, this->shape.view().extent());
  }
  PointSupports supports() const { return shape.view(); }
};

void done(benchmark::State& state, const Synthetic& s) {
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * s.n));
}

void shape_functions(benchmark::State& state, const char* shape_name) {
  Synthetic s(shape_name);
  const auto shape = s.registry.create<suffuse::ShapeFunction>(shape_name, {suffuse::Parameters{}, D, "/shape_function"});
  for (auto _ : state) {
    shape->evaluate(s.grid, s.x, s.size, s.shape.first, s.shape.weights, s.shape.derivatives);
    benchmark::DoNotOptimize(s.shape.weights.data());
  }
  done(state, s);
}

// The kernels written on Lanes<L> run on this machine's instruction set
// (SUFFUSE_KERNELS=portable compares the baseline).
template <class Kernel>
void vector_kernel(const Kernel& kernel) {
  static const KernelIsa isa = kernel_isa_for_this_machine();
  run_vector_kernel(isa, D, kernel);
}

// The dry points-to-grid scatter through the executor (chunked sums).
void p2g_dry(benchmark::State& state, const char* shape_name) {
  Synthetic s(shape_name);
  Executor exec(static_cast<int>(state.range(0)), Executor::default_layers, kernel_isa_for_this_machine());
  const double g[D] = {0, -9.81};
  std::vector<double> block(s.nodes * dry_block);
  for (auto _ : state) {
    std::fill(block.begin(), block.end(), 0.0);
    ScatterTargets targets = s.shape.targets(s.nodes);
    targets.add(block);
    exec.scatter(s.n, targets, [&](std::size_t b, std::size_t e, double* const* out) {
      exec.vector_kernel(D, [&]<int Dim, int L>() {
        p2g_kernel<Dim, L>(b, e, s.supports(), s.mass.data(), s.volume.data(),
                           s.velocity.data(), s.stress.data(), g, 1.0, out[0]);
      });
    });
    exec.for_chunks(s.nodes, [&](int, std::size_t b, std::size_t e) {
      unpack_dry_block<D>(b, e, block.data(), s.node_mass.data(), s.node_vector.data(), s.node_force.data());
    });
    benchmark::DoNotOptimize(s.node_force.data());
  }
  done(state, s);
}

// The saturated scatter: eight nodal arrays, from one block per node.
void p2g_two_phase(benchmark::State& state, const char* shape_name) {
  Synthetic s(shape_name);
  std::vector<std::vector<double>> out(8);
  for (int k = 0; k < 8; ++k) out[k].assign(s.nodes * (k == 1 || k == 2 || k == 4 || k == 5 ? D : 1), 0.0);
  std::vector<double> block(s.nodes * saturated_block<D>);
  const std::vector<double> rho_w(s.n, 1000.0), conductivity(s.n, 1e-3);
  const SaturatedPoints pt{s.mass.data(),     s.volume.data(), s.velocity.data(), s.stress.data(),
                           s.porosity.data(), s.pressure.data(), s.velocity.data(), s.mass.data(),
                           conductivity.data(), rho_w.data(), nullptr};
  const SaturatedNodes nodes{out[0].data(), out[1].data(), out[2].data(), out[3].data(),
                             out[4].data(), out[5].data(), out[6].data(), out[7].data()};
  const double g[D] = {0, -9.81};
  for (auto _ : state) {
    std::fill(block.begin(), block.end(), 0.0);
    vector_kernel([&]<int Dim, int L>() {
      p2g_saturated<Dim, L>(0, s.n, s.supports(), pt, g, 1.0, block.data());
    });
    unpack_saturated_block<D>(0, s.nodes, block.data(), nodes);
    benchmark::DoNotOptimize(out[2].data());
  }
  done(state, s);
}

void g2p(benchmark::State& state, const char* shape_name) {
  Synthetic s(shape_name);
  std::vector<double> u(s.n * D, 0.0);
  for (auto _ : state) {
    g2p_kernel<D>(0, s.n, 1e-6, s.supports(), s.node_vector.data(), s.node_vector2.data(),
                  s.x.data(), u.data(), s.velocity.data());
    benchmark::DoNotOptimize(s.velocity.data());
  }
  done(state, s);
}

void remap(benchmark::State& state, const char* shape_name) {
  Synthetic s(shape_name);
  for (auto _ : state) {
    std::fill(s.node_vector.begin(), s.node_vector.end(), 0.0);
    vector_kernel([&]<int Dim, int L>() {
      remap_kernel<Dim, L>(0, s.n, s.supports(), s.mass.data(), 1.0, s.velocity.data(),
                           s.node_vector.data());
    });
    benchmark::DoNotOptimize(s.node_vector.data());
  }
  done(state, s);
}

void velocity_gradient(benchmark::State& state, const char* shape_name) {
  Synthetic s(shape_name);
  for (auto _ : state) {
    velocity_gradient_kernel<D, true>(0, s.n, 1e-9, s.supports(), s.node_vector.data(), s.L.data(),
                                      s.strain.data(), s.volume.data());
    benchmark::DoNotOptimize(s.L.data());
  }
  done(state, s);
}

// Gathers of the transport: each point's share of the nodal changes.
void transport_share(benchmark::State& state, const char* shape_name) {
  Synthetic s(shape_name);
  std::vector<double> block(s.nodes * share_block, 0.0), amount(s.n, 1.0);
  share_rates(0, s.nodes, 0, s.node_scalar.data(), s.node_scalar.data(), s.node_vector.data(), block.data());
  double* const amounts[3] = {amount.data(), nullptr, nullptr};
  for (auto _ : state) {
    vector_kernel([&]<int Dim, int L>() {
      g2p_share<Dim, L>(0, s.n, s.supports(), s.volume.data(), s.porosity.data(), block.data(),
                   amounts);
    });
    benchmark::DoNotOptimize(amount.data());
  }
  done(state, s);
}

// A phase's stress update through its plugin, on every point.
void stress_update(benchmark::State& state, bool tension_cutoff) {
  Synthetic s("shape/linear");
  suffuse::PointSet points(D);
  std::map<std::string, suffuse::ParamValue> values{
      {"density", 2000.0}, {"youngs_modulus", 1e7}, {"poisson_ratio", 0.3}, {"tension_cutoff", tension_cutoff}};
  const suffuse::Parameters p = s.registry.find("phase/linear_elastic")->schema().complete(values);
  const auto phase = s.registry.create<suffuse::Phase>("phase/linear_elastic", {p, D, "/materials/soil"});
  phase->add_fields(points);
  points.append(s.n);
  double* L = points.data(points.core().velocity_gradient);
  double* sigma = points.data(points.core().stress);
  for (std::size_t k = 0; k < s.n; ++k) {
    for (int c = 0; c < D * D; ++c) L[k * D * D + c] = 1e-6 * s.L[k * D * D + c];
    for (int c = 0; c < 6; ++c) sigma[k * 6 + c] = c < 3 ? -1e5 : 1e3 * s.stress[k * 6 + c];
  }
  for (auto _ : state) {
    phase->update_stress(suffuse::StressBatch{points, {0, s.n}, 1.0, {}, 1.0, false});
    benchmark::DoNotOptimize(sigma);
  }
  done(state, s);
}

}  // namespace

#define SHAPES(kernel)                                                             \
  BENCHMARK_CAPTURE(kernel, linear, "shape/linear")->Unit(benchmark::kMillisecond); \
  BENCHMARK_CAPTURE(kernel, gimp, "shape/gimp")->Unit(benchmark::kMillisecond)

SHAPES(shape_functions);
BENCHMARK_CAPTURE(p2g_dry, linear, "shape/linear")->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK_CAPTURE(p2g_dry, gimp, "shape/gimp")->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->UseRealTime();
SHAPES(p2g_two_phase);
SHAPES(g2p);
SHAPES(remap);
SHAPES(velocity_gradient);
SHAPES(transport_share);
BENCHMARK_CAPTURE(stress_update, linear_elastic, false)->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(stress_update, linear_elastic_cutoff, true)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();
