// Results depend neither on the thread count nor on the instruction set:
// the scatter sums in chunks of points fixed by the points alone
// (executor.hpp), every other loop is per point or per node, and the vector
// kernels round each lane as the scalar code would (kernel_isa.hpp). Whole
// runs on 1, 2 and 3 threads and on the portable and AVX2 kernels, compared
// bit for bit in every point field and the mass ledger, on scenes of several
// scatter chunks and enough nodes that the node loops split too (a loop
// splits where each thread gets Executor::min_items_per_thread points or
// nodes; the kernel-level checks are in test_kernels.cpp and
// test_vector_kernels.cpp). Compared bit for bit: +0 and -0 differ.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

#include "parallel/executor.hpp"
#include "test_support.hpp"

namespace {

using suffuse::test::KernelChoice;
using suffuse::test::read_json;
using suffuse::test::scene_from;
using suffuse::test::source_dir;

// Unless the user chose the portable kernels (as under valgrind).
bool machine_has_avx2() {
  const char* chosen = std::getenv("SUFFUSE_KERNELS");
  if (chosen && std::string(chosen) == "portable") return false;
  const KernelChoice automatic("auto");
  return suffuse::detail::kernel_isa_for_this_machine() == suffuse::detail::KernelIsa::avx2;
}

void expect_the_same_for_any_thread_count(const nlohmann::json& j, int steps) {
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  const KernelChoice portable("portable");
  suffuse::Simulation serial(scene, registry, 1);
  for (int k = 0; k < steps; ++k) serial.step();
  const auto& a = serial.points();
  ASSERT_GT(a.size(), 3 * suffuse::detail::Executor::min_scatter_chunk) << "the scene must span several chunks";
  ASSERT_GE(serial.grid().node_count(), 2 * suffuse::detail::Executor::min_items_per_thread)
      << "the node loops must split between two threads";
  struct Run {
    int threads;
    const char* isa;
  };
  std::vector<Run> runs{{2, "portable"}, {3, "portable"}};
  if (machine_has_avx2()) runs.insert(runs.end(), {{1, "avx2"}, {2, "avx2"}});
  else std::cout << "this processor has no AVX2: only the portable kernels are compared\n";
  for (const auto [threads, isa] : runs) {
    const KernelChoice chosen(isa);
    suffuse::Simulation parallel(scene, registry, threads);
    for (int k = 0; k < steps; ++k) parallel.step();
    const auto& b = parallel.points();
    ASSERT_EQ(a.field_count(), b.field_count());
    for (suffuse::FieldId f = 0; f < a.field_count(); ++f) {
      const auto x = a.values(f), y = b.values(f);
      std::size_t differ = 0;
      for (std::size_t i = 0; i < x.size(); ++i) differ += std::memcmp(&x[i], &y[i], sizeof(double)) != 0;
      EXPECT_EQ(differ, 0u) << a.info(f).name << " on " << threads << " threads, " << isa;
    }
    EXPECT_EQ(serial.time(), parallel.time());
    if (!scene.saturated()) continue;
    const auto la = serial.mass_ledger(), lb = parallel.mass_ledger();
    EXPECT_EQ(la.fines_discharged(), lb.fines_discharged()) << threads << " threads, " << isa;
    EXPECT_EQ(la.fines_imbalance(), lb.fines_imbalance()) << threads << " threads, " << isa;
    EXPECT_EQ(la.liquid_imbalance(), lb.liquid_imbalance()) << threads << " threads, " << isa;
  }
}

// The eroding 2D bench column at a quarter of its resolution: 6,240 two-phase
// points (four chunks), GIMP, erosion and transport every step; the grid
// reaches 3 m above it, so that its 2,120 nodes split between two threads.
TEST(Threads, ErodingColumnIsBitForBitTheSame) {
  auto j = read_json(source_dir() / "share/scenes/bench_suffusion_column.json");
  j["grid"]["cell_size"] = {0.25, 0.25};
  j["grid"]["cells"] = {39, 52};
  expect_the_same_for_any_thread_count(j, 40);
}

// The dry 3D bench column at twice its cell size: 25,088 points, trilinear.
TEST(Threads, DryColumnIn3DIsBitForBitTheSame) {
  auto j = read_json(source_dir() / "share/scenes/bench_column_3d.json");
  j["grid"]["cell_size"] = {0.625, 0.625, 0.625};
  j["grid"]["cells"] = {14, 14, 17};
  expect_the_same_for_any_thread_count(j, 20);
}

// The dry 2D bench column, cut to 16 cells wide: 10,240 points, GIMP.
TEST(Threads, DryGimpColumnIsBitForBitTheSame) {
  auto j = read_json(source_dir() / "share/scenes/bench_column.json");
  j["grid"]["cells"][0] = 16;
  j["bodies"][0]["max"][0] = 16 * j["grid"]["cell_size"][0].get<double>();
  expect_the_same_for_any_thread_count(j, 20);
}

// The eroding 3D bench column at twice its cell size: two-phase, trilinear.
TEST(Threads, ErodingColumnIn3DIsBitForBitTheSame) {
  auto j = read_json(source_dir() / "share/scenes/bench_suffusion_column_3d.json");
  for (auto& h : j["grid"]["cell_size"]) h = 2 * h.get<double>();
  for (auto& n : j["grid"]["cells"]) n = n.get<int>() / 2;
  expect_the_same_for_any_thread_count(j, 20);
}

TEST(Threads, AnUnknownKernelChoiceIsRefusedByName) {
  const KernelChoice wrong("avx9");
  try {
    suffuse::detail::kernel_isa_for_this_machine();
    FAIL() << "no error";
  } catch (const suffuse::Error& e) {
    EXPECT_NE(std::string(e.what()).find("SUFFUSE_KERNELS: expected auto, portable or avx2, found 'avx9'"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
