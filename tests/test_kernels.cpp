// The step's kernels on their own: the scatter with 1, 2 and 3 threads, the
// TVD limiter of the transport, the erosion limiter at the ultimate fines
// content, and the soil-mechanics measures of the tensor header.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <suffuse/tensor.hpp>
#include <vector>

#include "parallel/executor.hpp"
#include "transport/species_kernels.hpp"

namespace {

using suffuse::detail::Executor;
using suffuse::detail::ScatterTargets;

// Ten arrays over 700 entries, with 1 to 3 values per entry (more arrays
// than any stage scatters into); each point adds known amounts to two
// entries near its neighbours' (as points that follow the grid do), so each
// chunk's range starts and ends inside the arrays. Spanning: in the second
// chunk every 97th point adds to the first and the last entry instead (a
// chunk spanning all), so the scatter takes its buffers; otherwise the even
// chunks' ranges are disjoint, and so are the odd ones', and the chunks add
// straight into the arrays.
struct ScatterCase {
  static constexpr std::size_t entries = 700;
  std::vector<std::vector<double>> arrays;
  std::vector<suffuse::NodeId> index;
  std::size_t points;
  explicit ScatterCase(std::size_t points, bool spanning = true) : points(points) {
    for (int k = 0; k < 10; ++k) arrays.emplace_back(entries * (1 + k % 3), 0.0);
    const std::size_t chunk = Executor::min_scatter_chunk;
    for (std::size_t p = 0; p < points; ++p) {
      const auto near = static_cast<std::int64_t>((p / 10) % entries);
      const bool far = spanning && p / chunk == 1 && p % 97 == 0;
      index.push_back(far ? 0 : near);
      index.push_back(far ? static_cast<std::int64_t>(entries) - 1 : (near + 1) % static_cast<std::int64_t>(entries));
    }
  }
  static double amount(std::size_t p, std::size_t k, int slot) {
    return slot == 0 ? 1.0 + 0.001 * static_cast<double>(p) : 0.5 + 1e-7 * static_cast<double>(k * p);
  }
  void add(std::size_t p, std::size_t k, double* out) const {
    const std::size_t m = arrays[k].size() / entries;
    for (int slot = 0; slot < 2; ++slot)
      for (std::size_t c = 0; c < m; ++c) out[static_cast<std::size_t>(index[2 * p + slot]) * m + c] += amount(p, k, slot);
  }
  // With the chunks' ranges given (as the shape functions' are) or found by the scatter.
  std::vector<std::vector<double>> run(int threads, bool given_ranges) {
    for (auto& a : arrays) std::fill(a.begin(), a.end(), 0.0);
    Executor exec(threads);
    suffuse::detail::ScatterRanges ranges;
    exec.chunk_ranges(index.data(), 2, points, ranges);
    ScatterTargets targets(index.data(), 2, entries, given_ranges ? &ranges : nullptr);
    for (auto& a : arrays) targets.add(a);
    exec.scatter(points, targets, [&](std::size_t b, std::size_t e, double* const* out) {
      for (std::size_t p = b; p < e; ++p)
        for (std::size_t k = 0; k < arrays.size(); ++k) add(p, k, out[k]);
    });
    return arrays;
  }
};

// Every contribution arrives, and the sums are bit for bit the same for 1,
// 2 and 3 threads, with the ranges given or not: in one chunk (500 points)
// and in several (3.2 chunks, the first entry of most ranges above 0), with
// buffers (a chunk spanning all) and without.
TEST(Kernels, ScatterAddsEveryContributionTheSameForAnyThreadCount) {
  for (const bool spanning : {true, false}) {
    for (std::size_t points : {std::size_t{500}, 3 * Executor::min_scatter_chunk + 501}) {
      ScatterCase c(points, spanning);
      suffuse::detail::ScatterRanges found;
      Executor(1).chunk_ranges(c.index.data(), 2, points, found);
      if (points > Executor::min_scatter_chunk) {
        EXPECT_EQ(Executor::parities_are_disjoint(found.chunks), !spanning) << "the case must take the path it names";
      }
      std::vector<std::vector<double>> expected;
      for (const auto& a : c.arrays) expected.emplace_back(a.size(), 0.0);
      for (std::size_t p = 0; p < points; ++p)
        for (std::size_t k = 0; k < expected.size(); ++k) c.add(p, k, expected[k].data());
      const auto serial = c.run(1, false);
      for (std::size_t k = 0; k < serial.size(); ++k)
        for (std::size_t i = 0; i < serial[k].size(); ++i)
          ASSERT_NEAR(serial[k][i], expected[k][i], 1e-12 * std::abs(expected[k][i]))
              << points << " points, array " << k << ", entry " << i << ", spanning " << spanning;
      for (int threads : {1, 2, 3})
        for (bool given : {false, true})
          EXPECT_EQ(c.run(threads, given), serial)
              << points << " points, " << threads << " threads, ranges given " << given << ", spanning " << spanning;
    }
  }
  // The chunks' ranges: the first one's near its points, the second's all.
  Executor exec(1);
  ScatterCase c(3 * Executor::min_scatter_chunk + 501);
  suffuse::detail::ScatterRanges ranges;
  exec.chunk_ranges(c.index.data(), 2, c.points, ranges);
  ASSERT_EQ(ranges.chunks.size(), 4u);
  EXPECT_EQ(ranges.chunks[1].first, 0u);
  EXPECT_EQ(ranges.chunks[1].last, ScatterCase::entries);
  EXPECT_GT(ranges.chunks[2].first, 0u);
  EXPECT_LT(ranges.chunks[2].last - ranges.chunks[2].first, ScatterCase::entries / 2);
}

// The chunk length follows the grid: a chunk spans about two layers of
// cells (points over the cells along the last axis), never fewer points than
// the minimum.
TEST(Kernels, ScatterChunksSpanTwoLayersOfCells) {
  EXPECT_EQ(Executor(1, 40).scatter_chunk(640), Executor::min_scatter_chunk);
  EXPECT_EQ(Executor(2, 40).scatter_chunk(3'200'000), 160'000u);
  EXPECT_EQ(Executor(3, 40).scatter_chunk(3'200'001), 160'002u);
  EXPECT_EQ(Executor(1).scatter_chunk(100'000'000), Executor::min_scatter_chunk);
}

// A loop is split only where each thread gets min_items_per_thread points
// or nodes: a parallel region costs about a pass over a thousand points, and
// splitting every pass of the default column (640 points) had made two
// threads run it at half the speed of one. Every item is visited once.
TEST(Kernels, SmallLoopsRunOnOneThread) {
  Executor exec(2);
  auto chunks = [&](std::size_t n, std::size_t items_per_unit) {
    std::vector<std::size_t> begins(2, n + 1), visits(n, 0);
    exec.for_chunks(n, [&](int t, std::size_t b, std::size_t e) {
      begins[static_cast<std::size_t>(t)] = b;
      for (std::size_t i = b; i < e; ++i) ++visits[i];
    }, items_per_unit);
    EXPECT_EQ(visits, std::vector<std::size_t>(n, 1)) << n << " units";
    return std::count_if(begins.begin(), begins.end(), [&](std::size_t b) { return b <= n; });
  };
  const std::size_t m = Executor::min_items_per_thread;
  EXPECT_EQ(chunks(640, 1), 1);
  EXPECT_EQ(chunks(2 * m - 1, 1), 1);
  EXPECT_EQ(chunks(2 * m, 1), 2);
  EXPECT_EQ(chunks(1, 100 * m), 1) << "one unit is never split";
  EXPECT_EQ(chunks(2, Executor::min_scatter_chunk), 2) << "two scatter chunks: one per thread";
  EXPECT_EQ(Executor(3).threads_for(3 * m - 1, 1), 2);
  EXPECT_EQ(Executor(1).threads_for(100 * m, 1), 1);
}

TEST(Kernels, ScatterTargetsRefuseMoreThanTheirCapacity) {
  std::vector<std::vector<double>> arrays(ScatterTargets::capacity + 1, std::vector<double>(3));
  ScatterTargets targets(nullptr, 1, 3);
  for (int k = 0; k < ScatterTargets::capacity; ++k) targets.add(arrays[k]);
  EXPECT_THROW(targets.add(arrays.back()), suffuse::Error);
}

// MUSCL with van Leer: second order on a linear profile, upwind at an
// extremum and without an upstream value, never a new extremum (TVD), at most
// twice the upwind value.
TEST(Kernels, VanLeerFaceValueIsTotalVariationDiminishing) {
  using T = suffuse::detail::Transport<2>;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  EXPECT_DOUBLE_EQ(T::limited(2.0, 3.0, 1.0), 2.5);  // linear: the face midpoint
  EXPECT_DOUBLE_EQ(T::limited(2.0, 1.0, 1.0), 2.0);  // a maximum at the upwind node
  EXPECT_DOUBLE_EQ(T::limited(2.0, 3.0, nan), 2.0);  // no upstream value
  EXPECT_DOUBLE_EQ(T::limited(2.0, 2.0, 1.0), 2.0);  // flat ahead
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.0, 10.0);
  for (int k = 0; k < 100000; ++k) {
    const double far = u(rng), up = u(rng), down = u(rng);
    const double v = T::limited(up, down, far);
    ASSERT_GE(v, std::min(up, down)) << far << " " << up << " " << down;
    ASSERT_LE(v, std::max(up, down)) << far << " " << up << " " << down;
    ASSERT_LE(v, 2 * up);
  }
}

// A rate far too large for the step erodes exactly down to f_c_inf; a
// negative one deposits at most the suspended fines; mass moves, none is made.
TEST(Kernels, ErosionStopsAtTheUltimateFinesContent) {
  std::vector<double> solid = {2.0, 2.0, 2.0}, fines = {0.5, 0.5, 0.05}, suspended = {0.0, 0.1, 0.0},
                      liquid = {1.0, 1.0, 1.0}, eroded = {0.0, 0.0, 0.0}, volume = {1e-3, 1e-3, 1e-3},
                      n = {0.3, 0.3, 0.3}, rho_s = {2650, 2650, 2650}, f_inf = {0.1, 0.1, 0.1};
  std::vector<double> rate = {1e6, -1e6, 1e6};
  const suffuse::detail::SpeciesPoints pt{solid.data(),  fines.data(), suspended.data(), liquid.data(),
                                          eroded.data(), volume.data(), n.data(),        rho_s.data()};
  const double total0 = solid[0] + liquid[0], dt = 1.0;
  suffuse::detail::apply_erosion(0, 3, dt, pt, f_inf.data(), rate.data());
  EXPECT_NEAR(fines[0] / solid[0], 0.1, 1e-14) << "eroded down to f_c_inf, not below";
  EXPECT_NEAR(solid[0] + liquid[0], total0, 1e-14 * total0);
  EXPECT_DOUBLE_EQ(eroded[0], 2.0 - solid[0]);
  EXPECT_NEAR(n[0] - 0.3, eroded[0] / (2650 * 1e-3), 1e-14) << "the porosity grows by the eroded volume";
  EXPECT_NEAR(rate[0], eroded[0] / (2650 * 1e-3 * dt), 1e-12) << "the rate applied is reported";
  EXPECT_DOUBLE_EQ(suspended[1], 0.0) << "deposition takes at most the suspended fines";
  EXPECT_DOUBLE_EQ(solid[1], 2.1);
  EXPECT_DOUBLE_EQ(fines[2], 0.05) << "already below f_c_inf: nothing to erode";
  EXPECT_DOUBLE_EQ(rate[2], 0.0);
}

// Soil-mechanics measures, compression positive: triaxial compression with
// sigma_1 = 300 kPa, sigma_2 = sigma_3 = 100 kPa (tension positive storage).
TEST(Kernels, TensorMeasuresOfATriaxialState) {
  namespace t = suffuse::tensor;
  const double s[6] = {-100e3, -300e3, -100e3, 0, 0, 0};
  EXPECT_DOUBLE_EQ(t::mean_stress(s), 500e3 / 3);
  EXPECT_NEAR(t::deviatoric_stress(s), 200e3, 1e-9);
  EXPECT_NEAR(t::stress_ratio(s), 1.2, 1e-15);
  EXPECT_NEAR(t::lode_angle(s), M_PI / 6, 1e-7) << "triaxial compression";
  const double extension[6] = {-300e3, -100e3, -300e3, 0, 0, 0};
  EXPECT_NEAR(t::lode_angle(extension), -M_PI / 6, 1e-7);
  const double e[6] = {0.001, -0.002, 0.001, 0, 0, 0};  // isochoric shortening
  EXPECT_DOUBLE_EQ(t::volumetric_strain(e), 0.0);
  EXPECT_NEAR(t::deviatoric_strain(e), 0.002, 1e-15);
  const double shear[6] = {0, 0, 0, 0, 0, 50e3};
  EXPECT_NEAR(t::deviatoric_stress(shear), std::sqrt(3.0) * 50e3, 1e-9);
  EXPECT_EQ(t::stress_ratio(shear), 0.0) << "no confinement, no ratio";
  EXPECT_EQ(t::voigt_index(0, 1), 5);
  EXPECT_EQ(t::voigt_index(2, 1), 3);
  EXPECT_EQ(t::voigt_index(0, 2), 4);
}

}  // namespace
