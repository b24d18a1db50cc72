// Results do not depend on the thread count: the scatter sums in chunks of
// points fixed by the points alone (executor.hpp), every other loop is per
// point or per node. Whole runs on 1, 2 and 3 threads, compared bit for bit
// in every point field and the mass ledger, on scenes of several scatter
// chunks (the kernel-level check is in test_kernels.cpp).
#include <gtest/gtest.h>

#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

#include "executor.hpp"
#include "test_support.hpp"

namespace {

using suffuse::test::read_json;
using suffuse::test::scene_from;
using suffuse::test::source_dir;

void expect_the_same_for_any_thread_count(const nlohmann::json& j, int steps) {
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation serial(scene, registry, 1);
  for (int k = 0; k < steps; ++k) serial.step();
  const auto& a = serial.points();
  ASSERT_GT(a.size(), 3 * suffuse::detail::Executor::min_scatter_chunk) << "the scene must span several chunks";
  for (int threads : {2, 3}) {
    suffuse::Simulation parallel(scene, registry, threads);
    for (int k = 0; k < steps; ++k) parallel.step();
    const auto& b = parallel.points();
    ASSERT_EQ(a.field_count(), b.field_count());
    for (suffuse::FieldId f = 0; f < a.field_count(); ++f) {
      const auto x = a.values(f), y = b.values(f);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < x.size(); ++i) differ += !(x[i] == y[i] || (x[i] != x[i] && y[i] != y[i]));
      EXPECT_EQ(differ, 0u) << a.info(f).name << " on " << threads << " threads";
    }
    EXPECT_EQ(serial.time(), parallel.time());
    if (!scene.saturated()) continue;
    const auto la = serial.mass_ledger(), lb = parallel.mass_ledger();
    EXPECT_EQ(la.fines_discharged(), lb.fines_discharged()) << threads << " threads";
    EXPECT_EQ(la.fines_imbalance(), lb.fines_imbalance()) << threads << " threads";
    EXPECT_EQ(la.liquid_imbalance(), lb.liquid_imbalance()) << threads << " threads";
  }
}

// The eroding 2D bench column at a quarter of its resolution: 6,240 two-phase
// points (four chunks), GIMP, erosion and transport every step.
TEST(Threads, ErodingColumnIsBitForBitTheSame) {
  auto j = read_json(source_dir() / "share/scenes/bench_suffusion_column.json");
  j["grid"]["cell_size"] = {0.25, 0.25};
  j["grid"]["cells"] = {39, 42};
  expect_the_same_for_any_thread_count(j, 40);
}

// The dry 3D bench column at twice its cell size: 25,088 points, trilinear.
TEST(Threads, DryColumnIn3DIsBitForBitTheSame) {
  auto j = read_json(source_dir() / "share/scenes/bench_column_3d.json");
  j["grid"]["cell_size"] = {0.625, 0.625, 0.625};
  j["grid"]["cells"] = {14, 14, 17};
  expect_the_same_for_any_thread_count(j, 20);
}

}  // namespace
