// Unconfined seepage: pores that drain above the phreatic surface
// (docs/phreatic.md), against closed forms.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <complex>
#include <filesystem>
#include <utility>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

#include "mixture/drainage.hpp"
#include "test_support.hpp"

namespace {

using nlohmann::json;
using suffuse::test::flow_through;
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
                "phreatic": { "drainage_head": 0.01, "residual_conductivity": 1.0e-3 } } },
    "liquids": { "water": { "type": "phase/pore_liquid", "density": 1000.0, "bulk_modulus": 2.2e9 } },
    "bodies": [ { "name": "dam", "material": "sand", "liquid": "water", "porosity": 0.3, "water_table": 0.5,
                  "min": [0.2, 0.0], "max": [1.2, 1.0], "points_per_cell": 2 } ],
    "boundary_conditions": [
      { "type": "bc/velocity", "face": "bottom", "vx": 0.0, "vy": 0.0 },
      { "type": "bc/water_level", "level": 0.8, "to": 0.2 },
      { "type": "bc/water_level", "level": 0.2, "from": 1.2 } ],
    "time": { "end": 20000.0, "integration": "quasi_static", "dt": 5000.0 },
    "outputs": []
  })");
  scene["grid"]["cell_size"] = {h, h};
  scene["grid"]["cells"] = {static_cast<int>(std::lround(1.4 / h)), static_cast<int>(std::lround(1.2 / h))};
  return scene;
}

// The highest saturated point of the dam's last column of points that
// leaves through its downstream face [m].
double seepage_exit(const suffuse::Simulation& sim, double face, double h) {
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* flux = pts.data(pts.id("darcy_flux"));
  const double* S = pts.data(pts.id("saturation"));
  double exit = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (x[2 * i] > face - h / 2 && S[i] == 1 && flux[2 * i] > 0) exit = std::max(exit, x[2 * i + 1]);
  return exit;
}

// The pore pressure's lowest value [Pa] and the largest saturation of the
// points in the dam's top cell.
std::pair<double, double> lowest_pressure_and_wettest_top(const suffuse::Simulation& sim, double top, double h) {
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* S = pts.data(pts.id("saturation"));
  const double* p = pts.data(pts.id("pore_pressure"));
  double lowest = 0, wettest = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    lowest = std::min(lowest, p[i]);
    if (x[2 * i + 1] > top - h) wettest = std::max(wettest, S[i]);
  }
  return {lowest, wettest};
}

// The dam under a river at H1 = 0.8 m that falls to 0.4 m between 20,000 s
// and 40,000 s. Steady before the fall: the flow through the middle against
// Dupuit and Charny's discharge q = k (H1^2 - H2^2) / (2 L), exact for this
// problem (Charny 1951), within 2%, the same through every section; the
// phreatic surface leaves the downstream face above H2 + h, through a
// seepage face; no pore pressure below zero, the dam's top drained. 20,000 s
// after the fall: the flow is Dupuit and Charny's for the low river within
// 3% (the fringe's error, about 0.59 h_d / y, is twice as large in the
// thinner flow), and the seepage face has come down. The pore liquid's
// ledger closes.
TEST(Phreatic, RectangularDamFollowsDupuitCharnyThroughAFallingRiver) {
  const double h = 0.05, k = 1e-4, H2 = 0.2, L = 1.0, face = 1.2;
  suffuse::Registry registry;
  json scene = rectangular_dam(h);
  scene["boundary_conditions"][1]["level"] = {{0.0, 0.8}, {20000.0, 0.8}, {40000.0, 0.4}};
  scene["time"]["end"] = 60000.0;
  const suffuse::Scene s = scene_from(scene, registry);
  suffuse::Simulation sim(s, registry);
  double high_flow = 0, high_exit = 0, steady_change = 0;
  std::pair<double, double> high_state;
  while (sim.time() < s.end_time - 0.5 * sim.dt()) {
    sim.step();
    if (sim.time() > 20000.0) continue;  // the last step before the river falls
    high_flow = flow_through(sim, 0.7, h), high_exit = seepage_exit(sim, face, h);
    high_state = lowest_pressure_and_wettest_top(sim, 1.0, h);
    steady_change = std::max(std::abs(flow_through(sim, 0.4, h) / high_flow - 1),
                             std::abs(flow_through(sim, 1.0, h) / high_flow - 1));
  }
  const double high = k * (0.8 * 0.8 - H2 * H2) / (2 * L), low = k * (0.4 * 0.4 - H2 * H2) / (2 * L);
  EXPECT_NEAR(high_flow, high, 0.02 * high) << "flow through the middle [m^2/s] under the high river";
  EXPECT_LT(steady_change, 1e-3) << "the same flow through every section";
  EXPECT_GT(high_exit, H2 + h) << "highest saturated point leaving through the downstream face [m]";
  EXPECT_GE(high_state.first, 0.0) << "no suction";
  EXPECT_LT(high_state.second, 0.05) << "saturation of the dam's top";
  const double low_flow = flow_through(sim, 0.7, h), low_exit = seepage_exit(sim, face, h);
  EXPECT_NEAR(low_flow, low, 0.03 * low) << "flow through the middle [m^2/s] under the low river";
  EXPECT_GT(high_exit, low_exit + h) << "the seepage face comes down with the river";
  EXPECT_LT(sim.mass_ledger().liquid_imbalance(), 1e-12);
  ::testing::Test::RecordProperty("high_error", std::to_string(high_flow / high - 1));
  ::testing::Test::RecordProperty("low_error", std::to_string(low_flow / low - 1));
  ::testing::Test::RecordProperty("exits", std::to_string(high_exit) + " " + std::to_string(low_exit));
  ::testing::Test::RecordProperty("top_saturation", std::to_string(high_state.second));
}

// A homogeneous levee 1 m high on an impervious base, slopes 1:2, crest
// 0.4 m wide, its upstream toe at x = 0.2; still water H = 0.8 m upstream
// (it meets the slope at x = 1.8), none downstream; a horizontal toe drain
// along the base from x = 3.6 (the focus) past the downstream toe (4.6).
json levee_with_toe_drain(double h) {
  json scene = rectangular_dam(h);
  scene["grid"]["cells"] = {static_cast<int>(std::lround(5.0 / h)), static_cast<int>(std::lround(1.1 / h))};
  scene["bodies"][0].erase("min"), scene["bodies"][0].erase("max");
  scene["bodies"][0]["name"] = "levee";
  scene["bodies"][0]["water_table"] = 0.4;
  scene["bodies"][0]["polygon"] = {{0.2, 0.0}, {4.6, 0.0}, {2.6, 1.0}, {2.2, 1.0}};
  scene["boundary_conditions"] = json::parse(R"([
    { "type": "bc/velocity", "face": "bottom", "vx": 0.0, "vy": 0.0, "phase": "solid" },
    { "type": "bc/pore_pressure", "face": "bottom", "pressure": 0.0,
      "box_min": [3.6, 0.0], "box_max": [5.0, 0.0], "name": "toe_drain" },
    { "type": "bc/water_level", "level": 0.8, "to": 1.8 },
    { "type": "bc/water_level", "level": 0.0, "from": 2.6 } ])");
  scene["time"]["end"] = 60000.0;
  return scene;
}

// The phreatic surface's height at x: above the highest saturated point of
// the column of points about x, its pressure head (hydrostatic there).
double phreatic_height(const suffuse::Simulation& sim, double x0, double h) {
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* p = pts.data(pts.id("pore_pressure"));
  double top = 0, head = 0;
  for (std::size_t i = 0; i < pts.size(); ++i)
    if (std::abs(x[2 * i] - x0) < h / 2 && p[i] > 0 && x[2 * i + 1] > top) top = x[2 * i + 1], head = p[i] / 9810.0;
  return top + head;
}

// Casagrande's toe-drain levee: Kozeny's parabola from the focus F at the
// drain's start, through the entry point A' 0.3 m upstream of where the
// water meets the slope (m = H cot(beta), the wetted slope's run):
// y0 = sqrt(d^2 + H^2) - d, d the distance from A' to F, q = k y0. The
// entry correction is empirical, and for this slope it is short: the flow
// comes out 9.5% above k y0 at h = 0.1 m, 10.5% at 0.05 m (with h_d =
// 0.02 m: 12.4% at 0.05 m and 12.9% at 0.025 m: grid-converged; the same
// solver meets Kozeny's exact problem, below, within 1%); the flow
// matches a shift of about 0.15 m instead, between Mikhailov's 0.2 m and
// no shift (Browzin and Fukuchi 2020 find the 0.3 m rule inaccurate). So
// the flow is asserted between k y0 and 15% above it, and the phreatic
// surface within 4% of H of the parabola near the drain, where the entry
// correction does not reach.
TEST(Phreatic, ToeDrainLeveeFollowsKozenysParabolaNearTheDrain) {
  const double h = 0.1, k = 1e-4, H = 0.8, x_F = 3.6, x_A = 1.8, m = H * 2;
  suffuse::Registry registry;
  const suffuse::Scene s = scene_from(levee_with_toe_drain(h), registry);
  suffuse::Simulation sim(s, registry);
  while (sim.time() < s.end_time - 0.5 * sim.dt()) sim.step();
  const double d = x_F - (x_A - 0.3 * m), y0 = std::sqrt(d * d + H * H) - d;
  const double q = flow_through(sim, 2.8, h);
  EXPECT_GT(q, k * y0) << "flow under the downstream slope [m^2/s]";
  EXPECT_LT(q, 1.15 * k * y0) << "flow under the downstream slope [m^2/s]";
  EXPECT_NEAR(flow_through(sim, 2.2, h), q, 1e-3 * q);
  for (const double x : {3.0, 3.4})
    EXPECT_NEAR(phreatic_height(sim, x, h), std::sqrt(y0 * y0 + 2 * y0 * (x_F - x)), 0.04 * H)
        << "phreatic surface at x = " << x;
  EXPECT_LT(sim.mass_ledger().liquid_imbalance(), 1e-12);
  ::testing::Test::RecordProperty("discharge_over_casagrande", std::to_string(q / (k * y0) - 1));
}

// Kozeny's exact solution (Kozeny 1931; Harr, Groundwater and Seepage,
// 1962): flow to a horizontal drain (y = 0, x > x_F) through a body on an
// impervious base whose upstream face is the equipotential h = H, the
// parabola y^2 = (H^2 / y0)(2 (x - x_F) + H^2 / y0). The head is
// h = sqrt(y0) Im sqrt(2 (x - x_F + i y)), the phreatic surface the basic
// parabola y^2 = y0^2 - 2 y0 (x - x_F), the flow q = k y0. Here H = 0.8 m,
// y0 = 0.25 m, x_F = 1.5 m; above the water the face goes on to a crest at
// 1 m, and a 1:1 slope comes down past the drain's start.
double kozeny_head(double x, double y, double x_F, double y0) {
  const std::complex<double> z(x - x_F, y);
  return std::sqrt(y0) * std::sqrt(2.0 * z).imag();
}

json kozeny_levee(double h, double drainage_head) {
  const double H = 0.8, y0 = 0.25, x_F = 1.5;
  json scene = levee_with_toe_drain(h);
  scene["grid"]["cells"] = {static_cast<int>(std::lround(2.4 / h)), static_cast<int>(std::lround(1.1 / h))};
  json polygon = json::array();
  for (double y = 1.0; y > -1e-9; y -= 0.025)  // the upstream face, top down
    polygon.push_back({x_F + y * y * y0 / (2 * H * H) - H * H / (2 * y0), std::max(y, 0.0)});
  polygon.push_back({x_F + 0.6, 0.0});
  polygon.push_back({x_F - 0.4, 1.0});
  scene["bodies"][0]["polygon"] = polygon;
  scene["bodies"][0]["water_table"] = H;
  scene["materials"]["sand"]["phreatic"]["drainage_head"] = drainage_head;
  const double meets = x_F + y0 / 2 - H * H / (2 * y0);  // where the water meets the face
  scene["boundary_conditions"][1]["box_min"] = {x_F, 0.0};
  scene["boundary_conditions"][1]["box_max"] = {2.4, 0.0};
  scene["boundary_conditions"][2]["to"] = meets;
  scene["boundary_conditions"][3]["from"] = x_F - 0.4;
  return scene;
}

// The flow through three sections within 2% of k y0, the phreatic surface
// within 2.5% of H of the basic parabola, and the pore pressure within 2%
// of gamma_w H of Kozeny's beyond 0.1 m of the focus, where the flow is
// singular (up to 3.5% beside it).
TEST(Phreatic, KozenysDrainFlowIsExact) {
  const double h = 0.05, k = 1e-4, H = 0.8, y0 = 0.25, x_F = 1.5;
  suffuse::Registry registry;
  const suffuse::Scene s = scene_from(kozeny_levee(h, 0.005), registry);
  suffuse::Simulation sim(s, registry);
  while (sim.time() < s.end_time - 0.5 * sim.dt()) sim.step();
  for (const double x : {0.6, 0.9, 1.2}) {
    EXPECT_NEAR(flow_through(sim, x, h), k * y0, 0.02 * k * y0) << "flow [m^2/s] through x = " << x;
    EXPECT_NEAR(phreatic_height(sim, x, h), std::sqrt(y0 * y0 - 2 * y0 * (x - x_F)), 0.025 * H)
        << "phreatic surface [m] at x = " << x;
  }
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* p = pts.data(pts.id("pore_pressure"));
  double worst = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    if (std::hypot(x[2 * i] - x_F, x[2 * i + 1]) < 0.1) continue;
    const double exact = 9810.0 * std::max(0.0, kozeny_head(x[2 * i], x[2 * i + 1], x_F, y0) - x[2 * i + 1]);
    worst = std::max(worst, std::abs(p[i] - exact) / (9810.0 * H));
  }
  EXPECT_LT(worst, 0.02) << "largest departure of the pore pressure from Kozeny's / gamma_w H";
  EXPECT_LT(sim.mass_ledger().liquid_imbalance(), 1e-12);
  ::testing::Test::RecordProperty("discharge_error", std::to_string(flow_through(sim, 0.9, h) / (k * y0) - 1));
  ::testing::Test::RecordProperty("pressure_error", std::to_string(worst));
}

// A restarted run continues as the run it continues, bit for bit: each
// step's seepage faces start from the points' state (docs/phreatic.md), not
// from a set the checkpoint would have to hold.
TEST(Phreatic, RestartContinuesBitForBit) {
  namespace fs = std::filesystem;
  suffuse::Registry registry;
  json scene_json = levee_with_toe_drain(0.1);
  scene_json["time"]["end"] = 20000.0;
  suffuse::Scene scene = scene_from(scene_json, registry);
  scene.name = "phreatic_restart";
  const fs::path a_dir = fs::temp_directory_path() / "suffuse_phreatic_restart_a";
  const fs::path b_dir = fs::temp_directory_path() / "suffuse_phreatic_restart_b";
  fs::remove_all(a_dir), fs::remove_all(b_dir);
  suffuse::Simulation a(scene, registry, 1);
  suffuse::RunOptions options;
  options.output_dir = a_dir;
  options.checkpoint_interval = 10000.0;
  bool copied = false;
  options.on_step = [&](const suffuse::Progress&) {
    if (copied || !fs::exists(a_dir / "phreatic_restart.checkpoint")) return;
    fs::copy(a_dir, b_dir, fs::copy_options::recursive);
    copied = true;
  };
  a.run(options);
  ASSERT_TRUE(copied);
  suffuse::Simulation b(scene, registry, 1);
  suffuse::RunOptions resume;
  resume.output_dir = b_dir;
  resume.restart = b_dir / "phreatic_restart.checkpoint";
  b.run(resume);
  EXPECT_EQ(b.steps(), a.steps());
  for (const char* field : {"position", "pore_pressure", "saturation", "darcy_flux"}) {
    const auto va = a.points().values(a.points().id(field)), vb = b.points().values(b.points().id(field));
    ASSERT_EQ(va.size(), vb.size());
    for (std::size_t i = 0; i < va.size(); ++i) ASSERT_EQ(va[i], vb[i]) << field << " [" << i << "]";
  }
  EXPECT_EQ(suffuse::test::slurp(b_dir / "phreatic_restart.checkpoint"),
            suffuse::test::slurp(a_dir / "phreatic_restart.checkpoint"));
}

// The retention curve's derivatives Newton's matrix uses (dS/dpsi, dk_r/dS)
// against central differences, on both sides of psi = 0 and far into the
// drained range; the potential inverts the saturation; S is 1/2 one
// drainage head above the phreatic surface.
TEST(Phreatic, RetentionCurveDerivativesAndInverse) {
  const suffuse::detail::Drainage d(suffuse::DrainageSpec{0.02, 1e-3});
  const double rho = 1000.0, scale = d.pressure_scale(rho);
  EXPECT_DOUBLE_EQ(d.saturation(-scale, rho), 0.5);
  for (const double psi : {-50 * scale, -3 * scale, -scale, -0.3 * scale, -0.01 * scale, 0.5 * scale}) {
    const double e = 1e-6 * scale;
    const double dS = (d.saturation(psi + e, rho) - d.saturation(psi - e, rho)) / (2 * e);
    EXPECT_NEAR(d.capacity(psi, rho), dS, 1e-6 / scale) << "dS/dpsi at psi = " << psi;
    const double S = d.saturation(psi, rho), h = 1e-6;
    const double dk = S > h ? (d.relative_conductivity(S + h) - d.relative_conductivity(S - h)) / (2 * h) : 0.0;
    if (S > h && S < 1 - h) {
      EXPECT_NEAR(d.conductivity_slope(S), dk, 1e-8) << "dk_r/dS at S = " << S;
    }
    if (psi < 0) {
      EXPECT_NEAR(d.potential(0.0, S, rho), psi, 1e-9 * std::abs(psi)) << "psi from S";
    }
  }
  EXPECT_EQ(d.potential(1234.0, 1.0, rho), 1234.0);
}

// The initial stress of a levee whose pores drain above its water table
// (k0): its soil weighs what the quasi-static step weighs, the grains and
// the water its pores hold, S = 1 / (1 + ((y - wt) / h_d)^2) of them above
// the table, so at rest it stays at rest. Against the closed form
// sigma'_v(y) = int_y^H ((1 - n) rho_s + n rho_w S) g dy - gamma_w (wt - y)+,
// the integral of S being h_d atan((y - wt) / h_d) (the drained pores
// weighed full before: 1,426 Pa too much below the table); and one
// quasi-static step from it moves no point more than 1e-6 of the dam's
// height (measured 2.5e-8 m; 8.0e-6 m when the drained pores were weighed
// full).
TEST(Phreatic, DrainedPoresWeighWhatTheyHold) {
  json scene = rectangular_dam(0.05);
  scene["bodies"][0]["k0"] = 0.5;
  scene["boundary_conditions"] = {{{"type", "bc/velocity"}, {"face", "bottom"}, {"vx", 0.0}, {"vy", 0.0}},
                                  {{"type", "bc/velocity"}, {"face", "left"}, {"vx", 0.0}},
                                  {{"type", "bc/velocity"}, {"face", "right"}, {"vx", 0.0}}};
  scene["bodies"][0]["min"] = {0.0, 0.0};
  scene["bodies"][0]["max"] = {1.4, 1.0};
  scene["time"] = {{"end", 100.0}, {"integration", "quasi_static"}, {"dt", 100.0}};
  suffuse::Registry registry;
  suffuse::Simulation sim(scene_from(scene, registry), registry, 1);
  const double n = 0.3, rho_s = 2650, rho_w = 1000, g = 9.81, H = 1.0, wt = 0.5, h_d = 0.01;
  auto held = [&](double lo, double hi) {  // int S dy over [lo, hi] at or above the table
    return h_d * (std::atan((hi - wt) / h_d) - std::atan((lo - wt) / h_d));
  };
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* s = pts.data(pts.core().stress);
  double worst = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double y = x[2 * i + 1], above = std::max(y, wt);
    const double total = (1 - n) * rho_s * g * (H - y) + n * rho_w * g * (std::max(0.0, wt - y) + held(above, H));
    const double effective = total - rho_w * g * std::max(0.0, wt - y);
    worst = std::max({worst, std::abs(-s[6 * i + 1] - effective), std::abs(-s[6 * i] - 0.5 * effective)});
  }
  EXPECT_LT(worst, 1e-9 * (1 - n) * rho_s * g * H) << "sigma'_v and sigma'_h against the closed form [Pa]";
  sim.step();
  const double* u = pts.data(pts.core().displacement);
  double moved = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) moved = std::max(moved, std::hypot(u[2 * i], u[2 * i + 1]));
  EXPECT_LT(moved, 1e-6 * H) << "largest displacement after one step [m]";
  // Without gravity the water is at rest everywhere, the pores full: no
  // weight, no stress (not 0 / 0).
  json weightless = scene;
  weightless["gravity"] = {0.0, 0.0};
  suffuse::Registry r2;
  suffuse::Simulation still(scene_from(weightless, r2), r2, 1);
  const auto stress = still.points().values(still.points().core().stress);
  EXPECT_TRUE(std::all_of(stress.begin(), stress.end(), [](double v) { return v == 0; })) << "no gravity";
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", moved);
  RecordProperty("largest_displacement_m", text);
}

}  // namespace
