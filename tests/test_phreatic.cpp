// Unconfined seepage: pores that drain above the phreatic surface
// (docs/phreatic.md), against closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace {

using nlohmann::json;
using suffuse::test::scene_from;

// A rectangular dam L = 1 m long and 1 m high with vertical faces on an
// impervious, fixed base; still water at H1 = 0.8 m upstream (x < 0.2) and
// H2 = 0.2 m downstream (x > 1.2). Quasi-static steps until the flow is
// steady.
json rectangular_dam(double h) {
  json scene = json::parse(R"({
    "dimension": 2, "gravity": [0.0, -9.81], "damping": 0.0,
    "grid": { "origin": [0.0, 0.0], "cell_size": [0.05, 0.05], "cells": [28, 24] },
    "shape_function": { "type": "shape/gimp" },
    "materials": {
      "sand": { "type": "phase/linear_elastic", "density": 2650.0, "youngs_modulus": 1.0e8, "poisson_ratio": 0.3,
                "permeability": { "type": "permeability/constant", "hydraulic_conductivity": 1.0e-4 },
                "phreatic": { "drainage_head": 0.02, "residual_conductivity": 1.0e-3 } } },
    "liquids": { "water": { "type": "phase/pore_liquid", "density": 1000.0, "bulk_modulus": 2.2e9 } },
    "bodies": [ { "name": "dam", "material": "sand", "liquid": "water", "porosity": 0.3, "water_table": 0.5,
                  "min": [0.2, 0.0], "max": [1.2, 1.0], "points_per_cell": 2 } ],
    "boundary_conditions": [
      { "type": "bc/velocity", "face": "bottom", "vx": 0.0, "vy": 0.0 },
      { "type": "bc/water_level", "level": 0.8, "to": 0.2 },
      { "type": "bc/water_level", "level": 0.2, "from": 1.2 } ],
    "time": { "end": 30000.0, "integration": "quasi_static", "dt": 5000.0 },
    "outputs": []
  })");
  scene["grid"]["cell_size"] = {h, h};
  scene["grid"]["cells"] = {static_cast<int>(std::lround(1.4 / h)), static_cast<int>(std::lround(1.2 / h))};
  return scene;
}

// The flow per metre [m^2/s] through the vertical strip of two cells about
// x: sum V q_x over the strip's width.
double flow_through(const suffuse::Simulation& sim, double x0, double h) {
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* V = pts.data(pts.core().volume);
  const double* q = pts.data(pts.id("darcy_flux"));
  double sum = 0;
  for (std::size_t p = 0; p < pts.size(); ++p)
    if (std::abs(x[2 * p] - x0) < h) sum += V[p] * q[2 * p];
  return sum / (2 * h);
}

// The flow through the dam's middle against Dupuit and Charny's discharge
// q = k (H1^2 - H2^2) / (2 L), exact for this problem (Charny 1951), within
// 2%; the phreatic surface leaves the downstream face above H2, through a
// seepage face; the pores above it drained, no pore pressure below zero,
// and the pore liquid's ledger closed.
TEST(Phreatic, RectangularDamPassesTheDupuitCharnyDischarge) {
  const double h = 0.05, k = 1e-4, H1 = 0.8, H2 = 0.2, L = 1.0, downstream_face = 1.2;
  suffuse::Registry registry;
  const suffuse::Scene s = scene_from(rectangular_dam(h), registry);
  suffuse::Simulation sim(s, registry);
  while (sim.time() < s.end_time - 0.5 * sim.dt()) sim.step();
  const double exact = k * (H1 * H1 - H2 * H2) / (2 * L);
  const double q = flow_through(sim, 0.7, h);
  EXPECT_NEAR(q, exact, 0.02 * exact) << "flow through the middle [m^2/s]";
  // Steady: the same flow through every section (0.1% apart).
  EXPECT_NEAR(flow_through(sim, 0.4, h), q, 1e-3 * q);
  EXPECT_NEAR(flow_through(sim, 1.0, h), q, 1e-3 * q);
  ::testing::Test::RecordProperty("discharge_error", std::to_string(q / exact - 1));

  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* flux = pts.data(pts.id("darcy_flux"));
  const double* S = pts.data(pts.id("saturation"));
  const double* p = pts.data(pts.id("pore_pressure"));
  double exit = 0, lowest_pressure = 0, wettest_top = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double xi = x[2 * i], y = x[2 * i + 1];
    lowest_pressure = std::min(lowest_pressure, p[i]);
    if (y > 1.0 - h) wettest_top = std::max(wettest_top, S[i]);
    // The last column of points: saturated and leaving through the face.
    if (xi > downstream_face - h / 2 && S[i] == 1 && flux[2 * i] > 0) exit = std::max(exit, y);
  }
  EXPECT_GT(exit, H2 + h) << "highest saturated point leaving through the downstream face [m]";
  EXPECT_GE(lowest_pressure, 0.0) << "no suction";
  EXPECT_LT(wettest_top, 1e-3) << "saturation of the dam's top";
  EXPECT_LT(sim.mass_ledger().liquid_imbalance(), 1e-12);
  ::testing::Test::RecordProperty("seepage_exit", std::to_string(exit));
}

}  // namespace
