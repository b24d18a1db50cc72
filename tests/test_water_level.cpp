// Still water on the bodies (bc/water_level): its pressure on a submerged
// slope, against the same slope dry under its buoyant weight.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <utility>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace {

using nlohmann::json;
using suffuse::test::scene_from;

// A saturated elastic slope (1:2, 1.0 m high at its left, 0.5 m at its
// right) on a fixed base between rollers, porosity 0.4, grains 2650 kg/m^3,
// under still water at 1.4 m: its pores at the hydrostatic pressure and
// its skeleton at k0 = 0.5 at the start, which is not the slope's
// equilibrium (the skeleton settles into it).
json submerged_slope() {
  return json::parse(R"({
    "dimension": 2, "gravity": [0.0, -9.81], "damping": 0.1,
    "grid": { "origin": [0.0, 0.0], "cell_size": [0.1, 0.1], "cells": [40, 16] },
    "shape_function": { "type": "shape/gimp" },
    "materials": {
      "sand": { "type": "phase/linear_elastic", "density": 2650.0, "youngs_modulus": 1.0e7, "poisson_ratio": 0.3,
                "permeability": { "type": "permeability/constant", "hydraulic_conductivity": 0.01 } } },
    "liquids": { "water": { "type": "phase/pore_liquid", "density": 1000.0, "bulk_modulus": 1.0e8 } },
    "bodies": [
      { "name": "slope", "material": "sand", "liquid": "water", "porosity": 0.4, "water_table": 1.4, "k0": 0.5,
        "polygon": [[0, 0], [4, 0], [4, 0.5], [2.5, 0.5], [1.5, 1.0], [0, 1.0]], "points_per_cell": 2 } ],
    "boundary_conditions": [
      { "type": "bc/velocity", "face": "bottom", "vx": 0.0, "vy": 0.0 },
      { "type": "bc/velocity", "face": "left", "vx": 0.0 },
      { "type": "bc/velocity", "face": "right", "vx": 0.0 },
      { "type": "bc/water_level", "level": 1.4 } ],
    "time": { "end": 1.0, "cfl": 0.5 },
    "outputs": []
  })");
}

// The slope's scene with level ground instead: a column one cell wide, 1 m
// deep, under the same water.
json level_ground() {
  json scene = submerged_slope();
  scene["grid"]["cells"] = {1, 16};
  scene["bodies"][0].erase("polygon");
  scene["bodies"][0]["min"] = {0.0, 0.0}, scene["bodies"][0]["max"] = {0.1, 1.0};
  return scene;
}

struct SlopeState {
  std::vector<double> position, stress, pressure, darcy_flux;
};

SlopeState run(const json& scene) {
  suffuse::Registry registry;
  const suffuse::Scene s = scene_from(scene, registry);
  suffuse::Simulation sim(s, registry);
  while (sim.time() < s.end_time - 0.5 * sim.dt()) sim.step();
  const auto& pts = sim.points();
  auto values = [&](suffuse::FieldId id) {
    const auto v = pts.values(id);
    return std::vector<double>(v.begin(), v.end());
  };
  SlopeState state{values(pts.core().position), values(pts.core().stress), {}, {}};
  if (pts.find("pore_pressure")) state.pressure = values(pts.id("pore_pressure")), state.darcy_flux = values(pts.id("darcy_flux"));
  return state;
}

// The pore pressure's largest departure from the hydrostatic gamma_w
// (level - y), over gamma_w level, and the largest Darcy flux [m/s].
std::pair<double, double> departure_from_still_water(const SlopeState& s, double level) {
  double pressure = 0, flux = 0;
  for (std::size_t p = 0; p < s.pressure.size(); ++p) {
    const double hydrostatic = 9810.0 * (level - s.position[2 * p + 1]);
    pressure = std::max(pressure, std::abs(s.pressure[p] - hydrostatic) / (9810.0 * level));
    flux = std::max(flux, std::hypot(s.darcy_flux[2 * p], s.darcy_flux[2 * p + 1]));
  }
  return {pressure, flux};
}

// The same scene dry under the buoyant weight (1 - n)(rho_s - rho_w) g: no
// liquid, no water level.
json dry_buoyant_twin(const json& submerged) {
  json dry = submerged;
  dry.erase("liquids");
  dry["materials"]["sand"].erase("permeability");
  dry["materials"]["sand"]["density"] = (1 - 0.4) * (2650.0 - 1000.0);
  dry["bodies"][0].erase("liquid"), dry["bodies"][0].erase("porosity"), dry["bodies"][0].erase("water_table");
  dry["boundary_conditions"].erase(3);
  return dry;
}

// The largest difference of effective stress between the submerged slope
// and its dry twin, over the largest stress.
double stress_difference(const SlopeState& wet, const SlopeState& buoyant) {
  double largest = 0, difference = 0;
  for (std::size_t i = 0; i < buoyant.stress.size(); ++i) largest = std::max(largest, std::abs(buoyant.stress[i]));
  for (std::size_t i = 0; i < wet.stress.size(); ++i)
    difference = std::max(difference, std::abs(wet.stress[i] - buoyant.stress[i]) / largest);
  return difference;
}

// The submerged slope's effective stress is its dry twin's (within 1% of
// the largest), its pore pressure hydrostatic (0.1% of gamma_w level), and
// nothing flows (1e-4 m/s against the drained slope's 0.01 m/s).
void expect_buoyant_weight_carried(const json& submerged) {
  const SlopeState wet = run(submerged), buoyant = run(dry_buoyant_twin(submerged));
  ASSERT_EQ(wet.stress.size(), buoyant.stress.size());
  const double stress = stress_difference(wet, buoyant);
  const auto [pressure, flux] = departure_from_still_water(wet, 1.4);
  EXPECT_LT(stress, 0.01) << "largest difference of effective stress / largest stress";
  EXPECT_LT(pressure, 0.001) << "largest departure from hydrostatic / gamma_w level";
  EXPECT_LT(flux, 1e-4) << "largest Darcy flux [m/s] (0.01 m/s out of the drained slope)";
  ::testing::Test::RecordProperty("stress_difference", std::to_string(stress));
  ::testing::Test::RecordProperty("pressure_difference", std::to_string(pressure));
  ::testing::Test::RecordProperty("darcy_flux", std::to_string(flux));
}

const double buoyant_unit_weight = (1 - 0.4) * (2650.0 - 1000.0) * 9.81;  // gamma' [N/m^3]

// Level ground 1 m deep under 0.4 m of still water: sigma'_yy = -gamma'
// (1 - y), the pore pressure hydrostatic, nothing flowing. Without the
// condition the ground's surface is drained (p = 0 on it): the water above
// weighs on nothing, and the pores empty through the surface at the
// conductivity's rate. Measured (0.5 s): stress 8e-16,
// pressure 8e-15, flux 4e-17 m/s (equilibrium to round-off); drained 0.2857.
TEST(WaterLevel, SubmergedGroundCarriesItsBuoyantWeight) {
  json scene = level_ground();
  scene["time"]["end"] = 0.5;
  const SlopeState wet = run(scene);
  double stress = 0;
  for (std::size_t p = 0; p < wet.pressure.size(); ++p)
    stress = std::max(stress, std::abs(wet.stress[6 * p + 1] + buoyant_unit_weight * (1.0 - wet.position[2 * p + 1])) /
                                  buoyant_unit_weight);
  const auto [pressure, flux] = departure_from_still_water(wet, 1.4);
  EXPECT_LT(stress, 0.01) << "largest departure of sigma'_yy from -gamma' depth / gamma' (1 m)";
  EXPECT_LT(pressure, 0.001) << "largest departure from hydrostatic / gamma_w level";
  EXPECT_LT(flux, 1e-4) << "largest Darcy flux [m/s] (0.01 m/s out of the drained ground)";

  // The base opened to the same water (a head of 1.4 m on the bottom face,
  // the liquid free to cross it): the level does not press on the grid's
  // faces, the face's condition does, once: still nothing flows.
  json open_base = scene;
  open_base["boundary_conditions"][0] = {{"type", "bc/velocity"}, {"face", "bottom"}, {"vx", 0.0}, {"vy", 0.0},
                                         {"phase", "solid"}};
  open_base["boundary_conditions"].push_back({{"type", "bc/pore_pressure"}, {"face", "bottom"}, {"head", 1.4}});
  const auto [base_pressure, base_flux] = departure_from_still_water(run(open_base), 1.4);
  EXPECT_LT(base_pressure, 0.001) << "open base: largest departure from hydrostatic / gamma_w level";
  EXPECT_LT(base_flux, 1e-6) << "open base: largest Darcy flux [m/s]";

  scene["boundary_conditions"].erase(3);
  const double open_pressure = departure_from_still_water(run(scene), 1.4).first;
  EXPECT_NEAR(open_pressure, 0.4 / 1.4, 0.01) << "drained: the water table falls to the surface, p = gamma_w (1 - y)";

}

// The slope under still water: its effective stress is that of the same
// slope dry under its buoyant weight (1 - n)(rho_s - rho_w) g (the
// buoyant-weight solution of the slope, from the dry solver), the pore
// pressure stays hydrostatic. The skeleton starts at k0, not the slope's
// equilibrium, and settles into it; the pore water it moves drains within
// the second. Measured (1 s, 7,278 steps, 3,200 points): stress 0.20%,
// pressure 5.2e-5, flux 2.7e-5 m/s (1.5e-5 at 2 s).
TEST(WaterLevel, SubmergedSlopeCarriesItsBuoyantWeight) {
  expect_buoyant_weight_carried(submerged_slope());
}

// A flood over level ground: the water rises from the ground's surface
// (1 m) to 1.4 m over 0.2 s and stays. Its pressure is carried by the
// pores, not the skeleton: at 0.5 s the pore pressure is gamma_w (1.4 - y),
// the effective stress -gamma' (1 - y) as before the flood, and the water
// that entered through the submerged surface (the ledger's free-surface
// account) is what the pore liquid's compression took in, n V gamma_w 0.4
// / K_L, with the ledger closed. Measured: pressure 3.0e-7, stress 3.9e-7,
// water in 1.56958e-3 kg/m against 1.56960e-3 (1.3e-5), ledger 2e-22.
// Before the transport let water in through a submerged surface: none
// entered, while the momentum balance had pressed it in.
TEST(WaterLevel, RisingFloodFeedsThePoresThroughTheSurface) {
  json scene = level_ground();
  scene["bodies"][0]["water_table"] = 1.0;
  scene["boundary_conditions"][3]["level"] = {{0.0, 1.0}, {0.2, 1.4}};
  scene["time"]["end"] = 0.5;
  suffuse::Registry registry;
  const suffuse::Scene s = scene_from(scene, registry);
  suffuse::Simulation sim(s, registry);
  while (sim.time() < s.end_time - 0.5 * sim.dt()) sim.step();
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* sigma = pts.data(pts.core().stress);
  const double* p = pts.data(pts.id("pore_pressure"));
  double pressure = 0, stress = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    pressure = std::max(pressure, std::abs(p[i] - 9810.0 * (1.4 - x[2 * i + 1])) / (9810.0 * 1.4));
    stress = std::max(stress, std::abs(sigma[6 * i + 1] + buoyant_unit_weight * (1.0 - x[2 * i + 1])) / buoyant_unit_weight);
  }
  EXPECT_LT(pressure, 0.001) << "largest departure from gamma_w (1.4 - y) / gamma_w 1.4";
  EXPECT_LT(stress, 0.01) << "largest departure of sigma'_yy from -gamma' depth / gamma' (1 m)";
  const suffuse::MassLedger ledger = sim.mass_ledger();
  double entered = 0;
  for (const suffuse::BoundaryDischarge& b : ledger.boundaries)
    if (b.face == "free_surface") entered = b.liquid_in - b.liquid_out;
  const double compression = 0.1 * 1.0 * 0.4 * 9810.0 * 0.4 / 1.0e8 * 1000.0;  // n V dp / K_L rho_w [kg/m]
  EXPECT_NEAR(entered, compression, 1e-3 * compression) << "water in through the submerged surface [kg/m]";
  EXPECT_LT(ledger.liquid_imbalance(), 1e-12);
}

// Quasi-static steps (1 s each) of the level ground flooded from 1 m to
// 1.4 m over 4 s: below the level a free surface holds the water's
// pressure where the surface is (its node's pressure extrapolated from the
// node inside, as a drained surface's to zero), and the water's load comes
// as in explicit steps. At every step's end the pore pressure is
// gamma_w (L(t) - y) and the effective stress -gamma' (1 - y): the flood
// is carried by the pores. Measured: pressure 1.4e-4, stress 2.0e-4 (the
// Newton tolerance's), water in 0.950 of the compression.
TEST(WaterLevel, QuasiStaticStepsFollowAHydrograph) {
  json scene = level_ground();
  scene["bodies"][0]["water_table"] = 1.0;
  scene["boundary_conditions"][3]["level"] = {{0.0, 1.0}, {4.0, 1.4}};
  scene["time"] = {{"end", 6.0}, {"integration", "quasi_static"}, {"dt", 1.0}};
  scene.erase("damping");
  suffuse::Registry registry;
  const suffuse::Scene s = scene_from(scene, registry);
  suffuse::Simulation sim(s, registry);
  double pressure = 0, stress = 0;
  while (sim.time() < s.end_time - 0.5 * sim.dt()) {
    sim.step();
    const double level = std::min(1.4, 1.0 + 0.1 * sim.time());
    const auto& pts = sim.points();
    const double* x = pts.data(pts.core().position);
    const double* sigma = pts.data(pts.core().stress);
    const double* p = pts.data(pts.id("pore_pressure"));
    for (std::size_t i = 0; i < pts.size(); ++i) {
      pressure = std::max(pressure, std::abs(p[i] - 9810.0 * (level - x[2 * i + 1])) / (9810.0 * 1.4));
      stress = std::max(stress, std::abs(sigma[6 * i + 1] + buoyant_unit_weight * (1.0 - x[2 * i + 1])) / buoyant_unit_weight);
    }
  }
  EXPECT_EQ(sim.steps(), 6u);
  EXPECT_LT(pressure, 1e-3) << "largest departure from gamma_w (L(t) - y) / gamma_w 1.4, every step";
  EXPECT_LT(stress, 1e-3) << "largest departure of sigma'_yy from -gamma' depth / gamma' (1 m), every step";
  const suffuse::MassLedger ledger = sim.mass_ledger();
  EXPECT_LT(ledger.liquid_imbalance(), 1e-12);
  // The water in through the surface: the transport reads the quasi-static
  // Darcy flux at the surface node as the mean over the top cell, half a
  // cell (h / 2L = 5%) below the surface in a flux growing linearly with
  // depth: first order (2.5% at h = 0.05 m).
  double entered = 0;
  for (const suffuse::BoundaryDischarge& b : ledger.boundaries)
    if (b.face == "free_surface") entered = b.liquid_in - b.liquid_out;
  const double compression = 0.1 * 1.0 * 0.4 * 9810.0 * 0.4 / 1.0e8 * 1000.0;  // n V dp / K_L rho_w [kg/m]
  EXPECT_NEAR(entered / compression, 1 - 0.1 / 2, 0.005) << "water in through the submerged surface / compression";
}

// The slope under still water in one quasi-static step: its effective
// stress is the dry slope's under its buoyant weight, also in one step.
// Measured: stress 0.082%, pressure 5.4e-4, flux 1.6e-5 m/s.
TEST(WaterLevel, QuasiStaticSubmergedSlopeCarriesItsBuoyantWeight) {
  json submerged = submerged_slope();
  submerged["time"] = {{"end", 1.0}, {"integration", "quasi_static"}, {"dt", 1.0}};
  submerged.erase("damping");
  expect_buoyant_weight_carried(submerged);
}

// A head prescribed on the grid's faces beside water levels that reach the
// same faces: both say the same water, and the levee section at rest stays
// at rest over quasi-static steps. The levels' pressure on the bodies'
// sides along the grid's faces was given back only while their points'
// edges lay on the face to 1e-6 of a cell; once the levee's weight had
// spread and moved them off it, the faces' nodes read the water's pressure
// twice (2 gamma_w (9 m - y)), and at the third step the sand's pore
// pressure stood up to 0.91 gamma_w 9 m off hydrostatic (now 0.003).
TEST(WaterLevel, QuasiStaticHeadOnAFaceBesideALevelStaysAtRest) {
  const std::filesystem::path scenes = suffuse::test::source_dir() / "share/scenes";
  json levee = suffuse::test::read_json(scenes / "levee_section.json");
  for (json& bc : levee["boundary_conditions"])
    if (bc["type"] == "bc/water_level") bc["level"] = 9.0;  // still water at the landside ground
  for (const char* face : {"left", "right"})
    levee["boundary_conditions"].push_back({{"type", "bc/pore_pressure"}, {"face", face}, {"head", 9.0}});
  levee["time"]["end"] = 2850.0;  // three steps: 600, 900 and 1350 s
  levee["outputs"] = json::array();
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::Scene scene = suffuse::parse_scene(levee.dump(), (scenes / "levee_section.json").string(), scenes,
                                                    registry, loader);
  suffuse::Simulation sim(scene, registry);
  while (sim.time() < scene.end_time - 0.5 * sim.dt()) sim.step();
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* p = pts.data(pts.id("pore_pressure"));
  double worst = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (x[2 * i + 1] < 9.0) worst = std::max(worst, std::abs(p[i] - 9810.0 * (9.0 - x[2 * i + 1])) / (9810.0 * 9.0));
  EXPECT_LT(worst, 0.01) << "largest departure from hydrostatic below the ground / gamma_w 9 m";
  RecordProperty("pressure_difference", std::to_string(worst));
}

// Levels that cannot stand together, or on nothing, are refused before the
// first step, naming the condition.
TEST(WaterLevel, LevelsThatCannotStandAreRefused) {
  using suffuse::test::setup_error;
  json overlapping = submerged_slope();
  overlapping["boundary_conditions"][3]["to"] = 2.0;
  overlapping["boundary_conditions"].push_back({{"type", "bc/water_level"}, {"level", 0.8}, {"from", 1.5}});
  EXPECT_EQ(setup_error(overlapping),
            "/boundary_conditions/4 (bc/water_level): its stretch of x [1.5, inf] overlaps that of "
            "/boundary_conditions/3 (bc/water_level) [-inf, 2]; expected water levels on separate stretches (from, "
            "to), the level interpolated between them");
  json two_waters = submerged_slope();
  two_waters["boundary_conditions"][3]["to"] = 1.0;
  two_waters["boundary_conditions"].push_back(
      {{"type", "bc/water_level"}, {"level", 0.8}, {"from", 3.0}, {"unit_weight", 10000.0}});
  EXPECT_EQ(setup_error(two_waters),
            "/boundary_conditions/4 (bc/water_level): unit_weight 10000 N/m^3 differs from that of "
            "/boundary_conditions/3 (bc/water_level) (9810); expected one water");
  json dry = dry_buoyant_twin(submerged_slope());
  dry["boundary_conditions"].push_back(submerged_slope()["boundary_conditions"][3]);
  EXPECT_EQ(setup_error(dry),
            "/boundary_conditions/3 (bc/water_level): a water level presses on saturated bodies and feeds their "
            "pores; expected a body with \"liquid\", found dry bodies only");
}

}  // namespace
