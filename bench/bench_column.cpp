// Throughput of the explicit MPM step on ~100,000-point columns, dry
// (share/scenes/bench_column.json), saturated (bench_saturated_column.json) and
// eroding (bench_suffusion_column.json). items_per_second is the number
// of material-point updates per second.
#include <benchmark/benchmark.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

namespace {

void run_scene(benchmark::State& state, const char* file, const char* shape) {
  const int threads = static_cast<int>(state.range(0));
  std::ifstream in(std::string(SUFFUSE_SOURCE_DIR) + "/share/scenes/" + file);
  std::stringstream text;
  text << in.rdbuf();
  auto j = nlohmann::json::parse(text.str());
  j["shape_function"]["type"] = shape;
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::Scene scene = suffuse::parse_scene(j.dump(), file, ".", registry, loader);
  suffuse::Simulation sim(scene, registry, threads);
  for (auto _ : state) sim.step();
  state.SetItemsProcessed(static_cast<std::int64_t>(state.iterations() * sim.points().size()));
  state.counters["points"] = static_cast<double>(sim.points().size());
}

void column(benchmark::State& state, const char* shape) { run_scene(state, "bench_column.json", shape); }
void saturated_column(benchmark::State& state, const char* shape) {
  run_scene(state, "bench_saturated_column.json", shape);
}
void suffusion_column(benchmark::State& state, const char* shape) {
  run_scene(state, "bench_suffusion_column.json", shape);
}

}  // namespace

BENCHMARK_CAPTURE(column, linear, "shape/linear")->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK_CAPTURE(column, gimp, "shape/gimp")->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK_CAPTURE(saturated_column, linear, "shape/linear")->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK_CAPTURE(saturated_column, gimp, "shape/gimp")->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK_CAPTURE(suffusion_column, linear, "shape/linear")->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK_CAPTURE(suffusion_column, gimp, "shape/gimp")->Arg(1)->Arg(2)->ArgName("threads")->Unit(benchmark::kMillisecond)->MinTime(2.0)->UseRealTime();
BENCHMARK_MAIN();
