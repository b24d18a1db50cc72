// The factor of safety by shear strength reduction (docs/slope-stability.md)
// against Griffiths and Lane's (1999) first example and Bishop and
// Morgenstern's charts; what a run writes of it; what it refuses.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <suffuse/simulation.hpp>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

nlohmann::json slope_scene(double cell) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/slope_stability.json");
  j["grid"]["cell_size"] = {cell, cell};
  j["grid"]["cells"] = {static_cast<int>(std::lround(33 / cell)), static_cast<int>(std::lround(12 / cell))};
  j["outputs"] = nlohmann::json::array();
  return j;
}

std::vector<double> field(const suffuse::Simulation& sim, const char* name) {
  const auto v = sim.points().values(sim.points().id(name));
  return {v.begin(), v.end()};
}

// Griffiths and Lane's first example (share/scenes/slope_stability.json): a
// 2:1 slope, H = 10 m, phi' = 20 degrees, c'/(gamma H) = 0.05, psi = 0, on a
// firm base at its toe. Bishop and Morgenstern's charts give 1.38
// (../shared/reference/physics.md, section 7); on the scene's grid (H/40)
// the factor is 1.419 (H/20: 1.513, H/10: 1.80: linear shape functions lock
// in the isochoric flow of psi = 0, and the factor falls towards the charts'
// as the grid is refined). Within 5% of 1.38, bracketed to the tolerance;
// the state afterwards is the state before, bit for bit; the mechanism is a
// band from the toe to the crest.
TEST(SlopeStability, GriffithsAndLanesSlopeHasBishopAndMorgensternsFactor) {
  auto j = slope_scene(0.25);
  j["factor_of_safety"]["tolerance"] = 0.02;
  // The solves that hold here take 4 to 20 iterations; those that fail run
  // to their stall, about 40, or to this (a fifth of the test's time).
  j["factor_of_safety"]["max_iterations"] = 30;
  suffuse::Registry registry;
  const suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.step();  // the geostatic state in equilibrium under gravity
  const auto stress = field(sim, "stress"), position = field(sim, "position");
  const suffuse::SafetyFactor f = sim.factor_of_safety();
  RecordProperty("factor_of_safety", std::to_string(f.factor));
  RecordProperty("newton_iterations", std::to_string(f.newton_iterations));
  EXPECT_NEAR(f.factor, 1.38, 0.05 * 1.38);
  EXPECT_GT(f.failed_at, f.factor);
  EXPECT_LE(f.failed_at - f.factor, 0.02 + 1e-12);
  EXPECT_EQ(field(sim, "stress"), stress);
  EXPECT_EQ(field(sim, "position"), position);
  // The band of the mechanism: it slides on the firm base from the toe and
  // rises to the crest behind its edge (x = 20 m); the soil beyond stays
  // still. The most strained point is near the toe, the most strained of
  // the crest (y > 9 m) behind its edge, and nothing near the far side
  // (x > 30 m) strains a tenth as much.
  const auto shear = field(sim, "safety_shear_strain");
  std::size_t most = 0, crest = 0;
  double far = 0;
  for (std::size_t p = 0; p < shear.size(); ++p) {
    const double x = position[2 * p], y = position[2 * p + 1];
    if (shear[p] > shear[most]) most = p;
    if (y > 9 && (shear[p] > shear[crest] || position[2 * crest + 1] <= 9)) crest = p;
    if (x > 30) far = std::max(far, shear[p]);
  }
  ASSERT_GT(shear[most], 0);
  EXPECT_LT(position[2 * most], 8.0) << "near the toe, at y = " << position[2 * most + 1];
  EXPECT_LT(position[2 * most + 1], 3.0);
  EXPECT_GT(position[2 * crest], 20.0) << "behind the crest's edge";
  EXPECT_LT(position[2 * crest], 30.0);
  EXPECT_GT(shear[crest], 0.2 * shear[most]) << "the band reaches the crest";
  EXPECT_LT(far, 0.1 * shear[most]) << "the soil beyond the mechanism";
}

// An evaluation leaves the run as it found it: the steps after it are the
// steps of a run without it, bit for bit. Its solves hold the loads and
// constraints of its time: a face the run moves (the far side pushed in at
// 1 cm/s) stays where it is, so the soil beside it does not strain (each
// solve moving it another step's worth strained it by about 1e-2).
TEST(SlopeStability, EvaluationLeavesTheRunAsItWas) {
  auto j = slope_scene(1.0);
  suffuse::test::boundary_condition(j, {{"type", "bc/velocity"}, {"face", "right"}})["vx"] = -0.01;
  suffuse::Registry registry;
  const suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  suffuse::Simulation evaluated(scene, registry), plain(scene, registry);
  evaluated.step();
  plain.step();
  EXPECT_GT(evaluated.factor_of_safety().factor, 1.5);
  evaluated.step();
  plain.step();
  for (const char* name : {"stress", "position", "velocity", "plastic_strain", "strain"})
    EXPECT_EQ(field(evaluated, name), field(plain, name)) << name;
  const auto shear = field(evaluated, "safety_shear_strain"), x = field(evaluated, "position");
  double largest = 0, beside = 0;
  for (std::size_t p = 0; p < shear.size(); ++p) {
    largest = std::max(largest, shear[p]);
    if (x[2 * p] > 31) beside = std::max(beside, shear[p]);
  }
  EXPECT_LT(beside, 0.1 * largest) << "the soil beside the moving face";
}

// An evaluation holds the pore pressures of the step's own equilibrium, so
// that its solve at full strength starts near it: Griffiths and Lane's
// slope on 1 m cells, drained above a water table 4 m above its base (h_d =
// 0.05 m, K = 1e-7 m/s, water at 2.2 GPa), after its first step. The solve
// at F = 1 starts 7.3e-3 of the forces off balance (the configuration moved
// at the step's end: 4.2e-3 on the dry slope pushed at its side), below 1e-2
// asserted. Holding the points' pressures projected to the nodes, it
// started at 2.6e-2; at a seepage exit such a solve stalled and reported a
// factor below 1 for a levee whose factor is 1.80 (docs/slope-stability.md,
// Limits).
TEST(SlopeStability, EvaluationStartsFromTheStepsEquilibrium) {
  auto j = slope_scene(1.0);
  suffuse::test::drain_slope(j, 4.0);
  j["factor_of_safety"] = {{"max_factor", 1.0001}};
  suffuse::Registry registry;
  const suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.step();
  const suffuse::SafetyFactor f = sim.factor_of_safety();
  RecordProperty("start_residual", std::to_string(f.start_residual));
  EXPECT_EQ(f.factor, 1.0001);
  EXPECT_GT(f.start_residual, 0.0);
  EXPECT_LT(f.start_residual, 1e-2);
}

// A run with /factor_of_safety writes one row per evaluation (after the
// first step, each interval, the end), each bracketed to the tolerance, and a
// restarted run keeps the rows up to its checkpoint and goes on. Without a phase that
// reduces its strength the scene is refused before a step.
TEST(SlopeStability, RunWritesItsFactorsAndRestartsThem) {
  const fs::path out = fs::path(testing::TempDir()) / "suffuse_slope_run";
  fs::remove_all(out);
  fs::create_directories(out);
  auto j = slope_scene(1.0);
  j["time"]["end"] = 2.0;
  j["time"]["checkpoint_interval"] = 1.0;
  j["factor_of_safety"] = {{"interval", 1.0}, {"tolerance", 0.05}};
  std::ofstream(out / "slope.json") << j.dump(2);
  const std::string run = std::string(SUFFUSE_EXECUTABLE) + " run " + (out / "slope.json").string() + " --output " +
                          out.string() + " > " + (out / "log.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(run.c_str()), 0) << suffuse::test::slurp(out / "log.txt");
  EXPECT_NE(suffuse::test::slurp(out / "log.txt").find("factor of safety (strength reduction, 2 evaluations)"),
            std::string::npos)
      << suffuse::test::slurp(out / "log.txt");
  auto table = suffuse::test::read_csv(out / "slope.factor_of_safety.csv");
  ASSERT_EQ(table.rows.size(), 2u);
  for (std::size_t r = 0; r < 2; ++r) {
    EXPECT_DOUBLE_EQ(table.rows[r][table.column("time")], static_cast<double>(r + 1));
    const double factor = table.rows[r][table.column("factor_of_safety")];
    const double failed = table.rows[r][table.column("failed_at")];
    EXPECT_GT(factor, 1.3) << "row " << r;
    EXPECT_GT(failed, factor);
    EXPECT_LE(failed - factor, 0.05 + 1e-12);
    EXPECT_GT(table.rows[r][table.column("solves")], 3);
  }
  // Extended to 3 s from its end checkpoint (with another tolerance: the
  // controls change no step): rows 1, 2 as they were, then 3.
  const auto first = table.rows;
  j["time"]["end"] = 3.0;
  j["factor_of_safety"]["tolerance"] = 0.04;
  std::ofstream(out / "slope.json") << j.dump(2);
  const std::string restart = std::string(SUFFUSE_EXECUTABLE) + " run " + (out / "slope.json").string() +
                              " --output " + out.string() + " --restart " + (out / "slope.checkpoint").string() +
                              " > " + (out / "log2.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(restart.c_str()), 0) << suffuse::test::slurp(out / "log2.txt");
  table = suffuse::test::read_csv(out / "slope.factor_of_safety.csv");
  ASSERT_EQ(table.rows.size(), 3u);
  for (std::size_t r = 0; r < 2; ++r) EXPECT_EQ(table.rows[r], first[r]) << "row " << r;
  EXPECT_DOUBLE_EQ(table.rows[2][table.column("time")], 3.0);
  EXPECT_LE(table.rows[2][table.column("failed_at")] - table.rows[2][table.column("factor_of_safety")], 0.04 + 1e-12);

  auto elastic = slope_scene(1.0);
  elastic["materials"]["soil"] = {{"type", "phase/linear_elastic"}, {"density", 2000.0}, {"youngs_modulus", 1e8}};
  EXPECT_EQ(suffuse::test::setup_error(elastic),
            "/factor_of_safety: no material's phase reduces its strength, so no factor of safety exists "
            "(phase/mohr_coulomb does, and phase/suffosion around it)");
}

}  // namespace
