// How phase/suffosion's "implicit" integration converges with the step in a
// quasi-static run (docs/levee.md, How accurate its steps are): the flood
// levee's week is too long to run twice in CI, so its gravel is run here in
// the suffusion column, at its scene's step controls and at a quarter of
// them, and Newton's iterations are watched on the way.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <suffuse/simulation.hpp>
#include <vector>

#include "test_support.hpp"

namespace {

using suffuse::test::read_json;
using suffuse::test::source_dir;

// The flood levee's gravel (share/scenes/levee_flood.json: phase/suffosion
// integrated implicitly around Mohr-Coulomb whose friction follows the
// state, erosion/fines_limited above a critical gradient, Kozeny-Carman)
// in the quasi-static suffusion column (suffusion_column_1h.json) in ten
// cells of 4 cm, one wide: 0.4 m, 20 kPa on its top, water at 2.2 GPa,
// the head at its base raised from 0.4 to 0.6 m (a gradient of 0.5, five
// times the critical one). Its conductivity is the column's sand's (1e-2
// m/s) and its erosion coefficient 10 1/m, so that the fines wash out in a
// minute, not a week.
// The steps are the levee's, scaled to the column's time (`dt` 0.05 s,
// `max_dt` 2 s, `eroded_fraction_tolerance` 0.01), times `scale`.
nlohmann::json eroding_gravel_column(double scale) {
  const auto levee = read_json(source_dir() / "share/scenes/levee_flood.json");
  auto j = read_json(source_dir() / "share/scenes/suffusion_column_1h.json");
  auto gravel = levee["materials"]["sandy_gravel"];
  gravel["permeability"]["hydraulic_conductivity"] = 0.01;
  gravel["erosion"]["lambda"] = 10.0;
  j["materials"] = {{"gravel", gravel}};
  j["liquids"]["water"]["bulk_modulus"] = levee["liquids"]["water"]["bulk_modulus"];
  j["grid"]["cells"] = {1, 10};
  j["grid"]["cell_size"] = {0.04, 0.04};
  auto& body = j["bodies"][0];
  body["material"] = "gravel";
  body["porosity"] = 0.333;
  body["max"] = {0.04, 0.4};
  for (auto& bc : j["boundary_conditions"]) bc.erase("concentration");  // clear water in
  j["boundary_conditions"].push_back(
      {{"type", "bc/traction"}, {"box_min", {0.0, 0.4}}, {"box_max", {0.04, 0.4}}, {"traction", {0.0, -20e3}}});
  j["time"] = {{"end", 60.0},
               {"integration", "quasi_static"},
               {"dt", 0.05 * scale},
               {"max_dt", 2.0 * scale},
               {"eroded_fraction_tolerance", 0.01 * scale},
               {"max_iterations", levee["time"]["max_iterations"]}};
  j["outputs"] = nlohmann::json::array();
  return j;
}

struct ColumnRun {
  std::vector<double> time, settlement, eroded;  // after each step: the top's, and the fines washed out [kg/m]
  std::vector<std::vector<double>> residuals;   // each step's Newton residuals
  double initial_fines = 0;
};

ColumnRun run_column(double scale) {
  suffuse::Registry registry;
  const suffuse::Scene scene = suffuse::test::scene_from(eroding_gravel_column(scale), registry);
  suffuse::Simulation sim(scene, registry);
  ColumnRun run;
  run.initial_fines = sim.mass_ledger().initial_fines;
  while (sim.time() < scene.end_time - 1e-9) {
    sim.step();
    const auto& pts = sim.points();
    const double* x = pts.data(pts.core().position);
    const double* u = pts.data(pts.core().displacement);
    double top = 0, top_y = 0;
    for (std::size_t p = 0; p < pts.size(); ++p) top_y = std::max(top_y, x[2 * p + 1] - u[2 * p + 1]);
    int n = 0;
    for (std::size_t p = 0; p < pts.size(); ++p)
      if (x[2 * p + 1] - u[2 * p + 1] > top_y - 1e-9) top -= u[2 * p + 1], ++n;
    run.time.push_back(sim.time());
    run.settlement.push_back(top / n);
    run.eroded.push_back(sim.mass_ledger().eroded);
    run.residuals.push_back(sim.newton_residuals());
  }
  const suffuse::MassLedger ledger = sim.mass_ledger();
  EXPECT_LT(ledger.fines_imbalance(), 1e-12);
  EXPECT_LT(ledger.liquid_imbalance(), 1e-12);
  EXPECT_LT(ledger.solid_imbalance(), 1e-12);
  return run;
}

// `values` at `t`, linear between the steps.
double at(const std::vector<double>& time, const std::vector<double>& values, double t) {
  const auto after = std::lower_bound(time.begin(), time.end(), t - 1e-12);
  if (after == time.begin()) return values.front() * t / time.front();
  if (after == time.end()) return values.back();
  const std::size_t k = after - time.begin();
  return values[k - 1] + (values[k] - values[k - 1]) * (t - time[k - 1]) / (time[k] - time[k - 1]);
}

TEST(SuffosionSteps, ErodingGravelColumnConvergesWithTheStep) {
  const ColumnRun run = run_column(1.0), quarter = run_column(0.25);
  ASSERT_GE(quarter.time.size(), 3 * run.time.size()) << "a quarter of the step takes about four times the steps";
  for (const double t : {10.0, 20.0, 30.0, 40.0, 50.0, 60.0}) {
    const double s = at(run.time, run.settlement, t), s4 = at(quarter.time, quarter.settlement, t);
    const double f = at(run.time, run.eroded, t), f4 = at(quarter.time, quarter.eroded, t);
    std::printf("t %4.0f s: settlement %.4e m (quarter step %.4e, %+.2f%%), fines eroded %.5f kg/m (%.5f, %+.2f%%)\n",
                t, s, s4, 100 * (s / s4 - 1), f, f4, 100 * (f / f4 - 1));
  }
  std::printf("steps %zu and %zu\n", run.time.size(), quarter.time.size());
  const double s = run.settlement.back(), s4 = quarter.settlement.back();
  const double f = run.eroded.back(), f4 = quarter.eroded.back();
  EXPECT_GT(f4, 0.1 * run.initial_fines) << "the column lost a tenth of its fines at least";
  EXPECT_GT(s4, 1e-3) << "and settled a millimetre";
  EXPECT_NEAR(s / s4, 1.0, 0.02) << "settlement at the end";
  EXPECT_NEAR(f / f4, 1.0, 0.02) << "fines eroded at the end";
  // Newton near the solution: from 1e-3 of the forces to the tolerance
  // (1e-8) squaring the residual takes two or three iterations (1e-3, 1e-6
  // C, 1e-12 C^3, C about 100), a contraction of 0.01 three, one of 0.1
  // (an elastic tangent's) five. Asserted: at most four, a margin of one
  // over the slowest measured. Most steps end in two; the slowest tail,
  // 9.2e-4 1.6e-5 1.5e-7 1.3e-9, contracts by 0.01 in its last two, for a
  // reason not identified (the column has no spin; points changing between
  // yield, slack and the apex near the solution are the suspects). Far
  // from it the iterations bring the ground's load back onto the eroding
  // points: up to twenty of them (docs/time-integration.md).
  std::size_t most_near = 0;
  int steps_iterated = 0;
  for (const ColumnRun* r : {&run, &quarter})
    for (const auto& seq : r->residuals) {
      if (seq.size() < 3) continue;  // converged at its first iteration
      const auto near = std::find_if(seq.begin(), seq.end(), [](double v) { return v < 1e-3; });
      if (near == seq.end()) continue;
      most_near = std::max(most_near, static_cast<std::size_t>(seq.end() - near - 1));
      ++steps_iterated;
    }
  std::printf("Newton: %d steps iterated more than once; at most %zu iterations from 1e-3 of the forces\n",
              steps_iterated, most_near);
  EXPECT_GT(steps_iterated, 10);
  EXPECT_LE(most_near, 4u);
  RecordProperty("settlement_relative_difference", suffuse::test::text(s / s4 - 1));
  RecordProperty("fines_relative_difference", suffuse::test::text(f / f4 - 1));
  RecordProperty("newton_iterations_from_1e-3", suffuse::test::text(static_cast<double>(most_near)));
}

}  // namespace
