// Phases coupled to the other parts of the core: the coupling fields a phase
// reads, the eigenstrain it writes, and the validation of what it needs.
// Uses the coupled-phase template (share/templates/coupled_phase, built here
// as tests/plugins/eroding_elastic).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <suffuse/error.hpp>
#include <suffuse/simulation.hpp>
#include <vector>

#include "test_support.hpp"

namespace {

using suffuse::test::scene_from;

nlohmann::json suffusion_column(double end) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  j["time"]["end"] = end;
  j["outputs"] = nlohmann::json::array();
  return j;
}

nlohmann::json with_eroding_elastic(nlohmann::json j) {
  auto& m = j["materials"]["gap_graded_sand"];
  m["type"] = "phase/eroding_elastic";
  m.erase("tension_cutoff");
  j["plugin_paths"] = {std::string(SUFFUSE_TEST_PLUGIN_DIR) + "/eroding_elastic"};
  return j;
}

// Mean vertical displacement of the top row of points.
double top_settlement(const suffuse::Simulation& sim) {
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  double top = -1e300;
  for (std::size_t p = 0; p < pts.size(); ++p) top = std::max(top, x[2 * p + 1] - u[2 * p + 1]);
  double sum = 0;
  int count = 0;
  for (std::size_t p = 0; p < pts.size(); ++p)
    if (x[2 * p + 1] - u[2 * p + 1] > top - 1e-9) sum += u[2 * p + 1], ++count;
  return -sum / count;
}

TEST(CoupledPhase, Explore) {
  for (double end : {2.0, 5.0, 10.0}) {
    suffuse::Registry r1, r2;
    const auto s1 = scene_from(suffusion_column(end), r1);
    const auto s2 = scene_from(with_eroding_elastic(suffusion_column(end)), r2);
    suffuse::Simulation a(s1, r1), b(s2, r2);
    a.run({});
    b.run({});
    std::printf("end %g: settlement linear %g, eroding %g\n", end, top_settlement(a), top_settlement(b));
  }
}

}  // namespace
