// A quasi-static run that counts its structure as failed (/failure;
// docs/slope-stability.md, Failure): a load that finds no equilibrium, and a
// factor of safety below the limit, each stop the run at the time of its
// last equilibrium, with every output and a checkpoint there.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

constexpr double cohesion = 10e3;

// A uniform strip load, B = 1 m, on weightless Tresca clay (c = 10 kPa, E =
// 10 MPa, nu = 0.3), half of it by symmetry on a 2 x 1 m block of 10 cm cells,
// the load rising by c per second. Prandtl's limit, (2 + pi) c, is reached at
// 5.14 s.
nlohmann::json strip_load_scene() {
  return nlohmann::json::parse(R"({
    "dimension": 2, "gravity": [0.0, 0.0],
    "grid": {"origin": [0.0, 0.0], "cell_size": [0.1, 0.1], "cells": [20, 11]},
    "shape_function": {"type": "shape/linear"},
    "materials": {"clay": {"type": "phase/mohr_coulomb", "density": 1000.0, "youngs_modulus": 1e7,
      "poisson_ratio": 0.3, "friction_angle": 0.0, "cohesion": 10000.0, "tensile_strength": 1e9}},
    "bodies": [{"name": "clay", "material": "clay", "min": [0.0, 0.0], "max": [2.0, 1.0], "points_per_cell": 2}],
    "boundary_conditions": [
      {"type": "bc/traction", "box_min": [0.0, 1.0], "box_max": [0.5, 1.0], "traction": [0.0, -10000.0],
       "factor": [[0, 0], [10, 10]]},
      {"type": "bc/velocity", "face": "left", "vx": 0.0},
      {"type": "bc/velocity", "face": "right", "vx": 0.0},
      {"type": "bc/velocity", "face": "bottom", "vx": 0.0, "vy": 0.0}],
    "time": {"end": 10.0, "integration": "quasi_static", "dt": 0.25},
    "failure": {},
    "outputs": [{"type": "writer/vtk_particles", "interval": 1.0}]})");
}

fs::path fresh(const char* name) {
  const fs::path out = fs::path(testing::TempDir()) / name;
  fs::remove_all(out);
  return out;
}

// The run stops at the last load with an equilibrium. On 10 cm cells that
// load is 6.25 c, 22% above Prandtl's 5.14 c (linear shape functions lock in
// Tresca's isochoric flow: 6.0 c on 5 cm cells, 5.52 c on 2.5 cm); asserted
// above Prandtl's and within 25% of it. The last frame and the checkpoint
// are at that time, and the checkpoint restarts: its run fails at once, at
// the same time.
TEST(Failure, StripLoadFindsNoEquilibriumNearPrandtlsLimit) {
  const fs::path out = fresh("suffuse_failure_strip");
  suffuse::Registry registry;
  const suffuse::Scene scene = suffuse::test::scene_from(strip_load_scene(), registry);
  suffuse::Simulation sim(scene, registry);
  suffuse::RunOptions options;
  options.output_dir = out;
  const suffuse::RunSummary s = sim.run(options);
  ASSERT_TRUE(s.failure.has_value());
  EXPECT_FALSE(s.interrupted);
  const double prandtl = (2 + std::numbers::pi) * cohesion, load = s.failure->time * cohesion;
  RecordProperty("failure_load_over_prandtl", std::to_string(load / prandtl));
  EXPECT_GT(load, prandtl);
  EXPECT_LT(load, 1.25 * prandtl);
  EXPECT_EQ(s.simulated_time, s.failure->time);
  EXPECT_NE(s.failure->reason.find("found no equilibrium"), std::string::npos) << s.failure->reason;
  const std::string pvd = suffuse::test::slurp(out / (scene.name + ".pvd"));
  std::ostringstream last;
  last << "timestep=\"" << s.failure->time << "\"";
  EXPECT_NE(pvd.find(last.str()), std::string::npos) << pvd;
  EXPECT_EQ(pvd.find(last.str()), pvd.rfind(last.str())) << "one frame at the failure";
  ASSERT_TRUE(fs::exists(out / (scene.name + ".checkpoint")));

  suffuse::Simulation again(scene, registry);
  options.restart = out / (scene.name + ".checkpoint");
  const suffuse::RunSummary r = again.run(options);
  ASSERT_TRUE(r.failure.has_value());
  EXPECT_EQ(r.failure->time, s.failure->time);
  EXPECT_EQ(r.steps, 0u);
}

// Without /failure the same load stops the run with an error that says so.
TEST(Failure, WithoutTheSectionALostEquilibriumIsAnError) {
  auto j = strip_load_scene();
  j.erase("failure");
  j["outputs"] = nlohmann::json::array();
  suffuse::Registry registry;
  const suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  try {
    sim.run({});
    FAIL() << "the run went on past the limit load";
  } catch (const suffuse::Error& e) {
    EXPECT_NE(std::string(e.what()).find("give the scene a /failure section"), std::string::npos) << e.what();
  }
}

// A factor of safety below /failure/factor_of_safety is a failure at its
// time: Griffiths and Lane's slope on 1 m cells has 1.80 after its first
// step (the first factor), so a limit of 2 fails it there, with a frame at
// that time and a checkpoint; a limit of 1.5 lets it run to its end.
TEST(Failure, FactorOfSafetyBelowTheLimitStopsTheRun) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/slope_stability.json");
  j["grid"]["cell_size"] = {1.0, 1.0};
  j["grid"]["cells"] = {33, 12};
  j["time"]["end"] = 2.0;
  j["factor_of_safety"] = {{"tolerance", 0.05}};
  j["outputs"] = {{{"type", "writer/vtk_particles"}, {"interval", 1.0}}};
  for (const double limit : {2.0, 1.5}) {
    j["failure"] = {{"factor_of_safety", limit}};
    const fs::path out = fresh("suffuse_failure_slope");
    suffuse::Registry registry;
    const suffuse::Scene scene = suffuse::test::scene_from(j, registry);
    suffuse::Simulation sim(scene, registry);
    suffuse::RunOptions options;
    options.output_dir = out;
    const suffuse::RunSummary s = sim.run(options);
    ASSERT_FALSE(s.factors_of_safety.empty());
    const double first = s.factors_of_safety.front().second.factor;
    ASSERT_NEAR(first, 1.80, 0.05);
    if (limit > first) {
      ASSERT_TRUE(s.failure.has_value()) << limit;
      EXPECT_EQ(s.failure->time, 1.0);
      EXPECT_EQ(s.steps, 1u);
      EXPECT_NE(s.failure->reason.find("fell below /failure/factor_of_safety = 2"), std::string::npos)
          << s.failure->reason;
      EXPECT_TRUE(fs::exists(out / (scene.name + ".checkpoint")));
      EXPECT_TRUE(fs::exists(out / (scene.name + "_000001.vtp")));
      EXPECT_FALSE(fs::exists(out / (scene.name + "_000002.vtp")));
    } else {
      EXPECT_FALSE(s.failure.has_value()) << s.failure->reason;
      EXPECT_EQ(s.simulated_time, 2.0);
    }
  }
}

}  // namespace
