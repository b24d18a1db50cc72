// Saturated soil (two-phase single-point MPM) against analytical solutions.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <iostream>
#include <numbers>
#include <sstream>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace {

using suffuse::test::boundary_condition;
using suffuse::test::boundary_condition_index;
using suffuse::test::read_json;
using suffuse::test::scene_from;
using suffuse::test::source_dir;

using suffuse::test::terzaghi_pressure;

double terzaghi_degree(double Tv) {
  double s = 0;
  for (int m = 0; m < 200; ++m) {
    const double M = (2 * m + 1) * std::numbers::pi / 2;
    if (M * M * Tv > 50) break;
    s += 2 / (M * M) * std::exp(-M * M * Tv);
  }
  return 1 - s;
}

using suffuse::test::text;

// share/scenes/terzaghi.json: isochrones within 0.03 u_0 everywhere along the
// column and degree of consolidation within 0.03 at T_v = 0.05, 0.2, 0.5, 1;
// the same at every step of the windows 0.9 T_v to 1.1 T_v (except T_v = 0.05,
// see below), and the total vertical stress sigma'_yy - p of every point
// equal to the load (no gravity) over the windows of T_v = 0.2, 0.5 and 1.
TEST(TwoPhase, TerzaghiConsolidation) {
  auto j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["outputs"] = nlohmann::json::array();
  const double H = 1.0, s = 1e4;
  const double E = j["materials"]["soil"]["youngs_modulus"];  // = E_oed, Poisson's ratio 0
  const double K = j["materials"]["soil"]["permeability"]["hydraulic_conductivity"];
  const double n = j["bodies"][0]["porosity"];
  const double KL = j["liquids"]["water"]["bulk_modulus"];
  const double rho_w = j["liquids"]["water"]["density"];
  const double u0 = s * (KL / n) / (KL / n + E);
  ASSERT_NEAR(double(j["bodies"][0]["pore_pressure"]), u0, 0.01);  // the scene starts undrained
  const double cv = K * E / (rho_w * 9.81);

  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const auto& pts = sim.points();
  const suffuse::FieldId pressure = pts.id("pore_pressure");
  struct Errors {
    double isochrone = 0, degree = 0, total_stress = 0;
  };
  auto measure = [&](double Tv) {
    const double* x = pts.data(pts.core().position);
    const double* u = pts.data(pts.core().displacement);
    const double* p = pts.data(pressure);
    const double* sig = pts.data(pts.core().stress);
    Errors e;
    double mean = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double z = H - (x[2 * i + 1] - u[2 * i + 1]);  // initial depth below the drained top
      e.isochrone = std::max(e.isochrone, std::abs(p[i] - terzaghi_pressure(u0, z, H, Tv)) / u0);
      e.total_stress = std::max(e.total_stress, std::abs((sig[6 * i + 1] - p[i]) / -s - 1));
      mean += p[i] / static_cast<double>(pts.size());
    }
    e.degree = std::abs(1 - mean / u0 - terzaghi_degree(Tv));
    return e;
  };
  for (const double Tv : {0.05, 0.2, 0.5, 1.0}) {
    Errors window, at;
    while (sim.time() < 1.1 * Tv * H * H / cv - 0.5 * sim.dt()) {
      const bool at_Tv = sim.time() < Tv * H * H / cv - 0.5 * sim.dt();
      sim.step();
      const double tv = sim.time() * cv / (H * H);
      if (tv < 0.9 * Tv) continue;
      const Errors e = measure(tv);
      if (at_Tv && sim.time() >= Tv * H * H / cv - 0.5 * sim.dt()) at = e;  // the step that reaches T_v
      window.isochrone = std::max(window.isochrone, e.isochrone);
      window.degree = std::max(window.degree, e.degree);
      window.total_stress = std::max(window.total_stress, e.total_stress);
    }
    EXPECT_LT(at.isochrone, 0.03) << "T_v = " << Tv << ": largest isochrone error / u_0";
    EXPECT_LT(at.degree, 0.03) << "T_v = " << Tv;
    // Every step of the window. At T_v = 0.05 the drained, loaded top still
    // rings (a vibration of the top cells started by the sudden drainage at
    // t = 0, which neither FLIP nor the local damping of a steadily settling
    // surface removes) and the column's undrained wave has not died out:
    // known defect, measured 0.12 u_0 and 0.052 (docs/two-phase.md).
    const bool early = Tv < 0.1;
    EXPECT_LT(window.isochrone, early ? 0.13 : 0.03) << "T_v = " << Tv << " +- 10%: largest isochrone error / u_0";
    EXPECT_LT(window.degree, early ? 0.06 : 0.03) << "T_v = " << Tv << " +- 10%";
    // The load on the surface points moves with the settling surface: the
    // total stress of every point is the load within 5% (on nodes fixed in
    // space the top row carried 1.36 x the load at T_v = 0.2 and 1.90 x at 1;
    // at T_v = 0.05 the ringing above, measured 0.128).
    EXPECT_LT(window.total_stress, early ? 0.15 : 0.05) << "T_v = " << Tv << " +- 10%: total stress / load - 1";
    RecordProperty("isochrone_error_Tv_" + text(Tv), text(at.isochrone));
    RecordProperty("degree_error_Tv_" + text(Tv), text(at.degree));
    RecordProperty("isochrone_error_window_Tv_" + text(Tv), text(window.isochrone));
    RecordProperty("degree_error_window_Tv_" + text(Tv), text(window.degree));
    RecordProperty("total_stress_error_window_Tv_" + text(Tv), text(window.total_stress));
  }
}

// bc/traction on a dry column that settles 1.5 cells (30 kPa on E_oed = 1
// MPa, ramped over 0.1 s, damped): the load follows the surface points. On
// the nodes at the initial surface it would act on nodes the body has left.
TEST(TwoPhase, TractionFollowsTheSettlingSurface) {
  auto j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["outputs"] = nlohmann::json::array();
  j.erase("liquids");
  j["materials"]["soil"].erase("permeability");
  for (const char* key : {"liquid", "porosity", "pore_pressure", "stress"}) j["bodies"][0].erase(key);
  j["damping"] = 0.3;
  j["time"]["end"] = 0.6;
  const double s = 3e4, E = 1e6, H = 1.0;
  auto& load = suffuse::test::boundary_condition(j, {{"type", "bc/traction"}});
  load["traction"] = {0.0, -s};
  load["ramp_time"] = 0.1;
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});
  const auto& pts = sim.points();
  const double* sig = pts.data(pts.core().stress);
  const double* u = pts.data(pts.core().displacement);
  double worst = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) worst = std::max(worst, std::abs(sig[6 * i + 1] / -s - 1));
  const double settlement = -u[2 * (pts.size() - 1) + 1];
  EXPECT_GT(settlement, 1.4 * 0.02) << "more than a cell";
  EXPECT_NEAR(settlement / (s * H / E), 1.0, 0.05);
  EXPECT_LT(worst, 0.05) << "sigma_yy / load - 1, every point";
  RecordProperty("dry_settlement_ratio", text(settlement / (s * H / E)));
  RecordProperty("dry_stress_error", text(worst));
}

// bc/traction on the saturated Terzaghi column that settles one cell (20 kPa
// on E_oed = 1 MPa, at once, undrained start). The top points' faces end at
// a node that only their own uGIMP tails reach: the load must reach that
// node in the share its internal force does, or the node's equilibrium pulls
// the top points' stress off the load. With the load at the face stretched
// by the strain (0.17.0) the top pair ended at 0.77 and 1.22 of the load and
// stayed there; with the face where the shape function puts it, every point
// carries the load within 8% (uGIMP's own checkerboard of effective stress,
// frozen when points cross nodes as the column compresses).
TEST(TwoPhase, SaturatedColumnSettlingACellCarriesItsLoad) {
  auto j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["outputs"] = nlohmann::json::array();
  const double s = 2e4, E = 1e6, K_over_n = 1e8 / 0.4;
  const double u0 = s * K_over_n / (K_over_n + E);
  j["bodies"][0]["pore_pressure"] = u0;
  j["bodies"][0]["stress"][1] = -(s - u0);
  suffuse::test::boundary_condition(j, {{"type", "bc/traction"}})["traction"] = {0.0, -s};
  j["time"]["end"] = 2.5;  // T_v = 2.5: consolidated to 0.2% of u0
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});
  const auto& pts = sim.points();
  const double* sig = pts.data(pts.core().stress);
  const double* p = pts.data(pts.id("pore_pressure"));
  const double* u = pts.data(pts.core().displacement);
  double low = 1, high = 1, settlement = 0;
  for (std::size_t i = 0; i < pts.size(); ++i) {
    const double total = (sig[6 * i + 1] - p[i]) / -s;
    low = std::min(low, total), high = std::max(high, total);
    settlement = std::max(settlement, -u[2 * i + 1]);
  }
  EXPECT_GT(settlement, 0.95 * 0.02) << "settled about a cell";
  EXPECT_GT(low, 0.9) << "smallest total stress / load";
  EXPECT_LT(high, 1.1) << "largest total stress / load";
  RecordProperty("total_stress_low", text(low));
  RecordProperty("total_stress_high", text(high));
}

// Invalid saturated scenes are caught before anything is built.
TEST(TwoPhase, SaturatedSceneValidation) {
  auto j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["materials"]["soil"].erase("permeability");
  j["bodies"][0].erase("porosity");
  j["bodies"].push_back({{"material", "soil"}, {"min", {0.0, 0.0}}, {"max", {0.02, 0.1}}});  // dry: allowed
  j["bodies"].push_back({{"material", "soil"}, {"porosity", 0.3}, {"min", {0.0, 0.0}}, {"max", {0.02, 0.1}}});
  suffuse::Registry registry;
  try {
    scene_from(j, registry);
    FAIL() << "accepted";
  } catch (const suffuse::SceneError& e) {
    std::vector<std::string> pointers;
    for (const auto& d : e.diagnostics()) pointers.push_back(d.pointer);
    EXPECT_EQ(pointers, (std::vector<std::string>{"/bodies/0/porosity", "/materials/soil/permeability",
                                                  "/bodies/2/porosity"}))
        << e.what();
  }
}


// share/scenes/upward_seepage.json at t = 0.6 s (steady after ~0.15 s):
// Darcy flux K dh / L within 1%, pore pressure linear in height, vertical
// effective stress (gamma' - i gamma_w) z within 2%.
TEST(TwoPhase, SteadyUpwardSeepage) {
  auto j = read_json(source_dir() / "share/scenes/upward_seepage.json");
  j["outputs"] = nlohmann::json::array();
  const suffuse::test::UpwardSeepage seepage;
  const double L = seepage.L, rho_w = seepage.rho_w, gamma_w = seepage.gamma_w();
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});
  EXPECT_NEAR(sim.time(), 0.6, 1e-12);

  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  const double* s = pts.data(pts.core().stress);
  const double* p = pts.data(pts.id("pore_pressure"));
  const double* q = pts.data(pts.id("darcy_flux"));
  double q_mean = 0, q_worst = 0, p_worst = 0, s_worst = 0, s_worst_abs = 0;
  std::vector<double> layer_flux(100, 0.0);  // flux through each layer of points (0.01 m)
  const double q_exact = seepage.flux(), p_base = seepage.pressure(0);
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double y = x[2 * k + 1] - u[2 * k + 1], z = L - y;
    q_mean += q[2 * k + 1] / static_cast<double>(pts.size());
    layer_flux[static_cast<std::size_t>(y / 0.01)] += q[2 * k + 1] / 2;  // 2 points per layer
    p_worst = std::max(p_worst, std::abs(p[k] - seepage.pressure(y)) / p_base);
    const double sv = -seepage.effective_stress(z);
    if (z > 0.3 && z < 0.9) s_worst = std::max(s_worst, std::abs(s[6 * k + 1] - sv) / std::abs(sv));
    s_worst_abs = std::max(s_worst_abs, std::abs(s[6 * k + 1] - sv) / seepage.effective_stress(L));
  }
  // Flux through each cross-section, except the last five cells (0.1 m) below
  // the free top where the liquid leaves the body: points there deviate by up
  // to 42% (known defect of the outflow surface, see docs/two-phase.md).
  for (std::size_t layer = 0; layer < 90; ++layer)
    q_worst = std::max(q_worst, std::abs(layer_flux[layer] - q_exact) / q_exact);
  EXPECT_NEAR(q_mean / q_exact, 1.0, 0.01);
  EXPECT_LT(q_worst, 0.01) << "flux through the cross-sections below the outlet cells";
  // Linear in height: within 2% of the base pressure (a slow oscillation of
  // the lower points, up to 1.9% at t = 1 s, is not damped yet).
  EXPECT_LT(p_worst, 0.02);
  // Relative to the local value from 0.3 m depth (the stress at a point lags
  // the exact value by half a point spacing, 24 Pa here), and relative to the
  // base value everywhere.
  EXPECT_LT(s_worst, 0.02);
  EXPECT_LT(s_worst_abs, 0.02);
  // The liquid's transported mass agrees with its compressibility: below the
  // outlet cells, m_L / (n V) = rho_w (1 + (p - p_0) / K_L), p_0 the initial
  // hydrostatic pressure. The mass balance (upwind, on the nodes) and the
  // pressure equation (at the points) are two discretisations of one
  // balance; they differ by 2.6e-5 here, where Delta p / K_L reaches 3e-5.
  // A closed inlet would put the points near it 2% off.
  const double KL = j["liquids"]["water"]["bulk_modulus"];
  const double* carried = pts.data(pts.id("liquid_mass"));
  const double* porosity = pts.data(pts.id("porosity"));
  const double* volume = pts.data(pts.core().volume);
  double rho_worst = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double y = x[2 * k + 1] - u[2 * k + 1];
    if (y > 0.9) continue;
    const double p0 = gamma_w * (L - y);
    const double rho = carried[k] / (porosity[k] * volume[k]);
    rho_worst = std::max(rho_worst, std::abs(rho / (rho_w * (1 + (p[k] - p0) / KL)) - 1));
  }
  EXPECT_LT(rho_worst, 5e-5);
  const suffuse::MassLedger ledger = sim.mass_ledger();
  EXPECT_LT(ledger.liquid_imbalance(), 1e-12);
  EXPECT_GT(ledger.boundaries.front().liquid_in, 0.9 * q_exact * 0.6 * rho_w * 0.02) << "liquid entered at the base";
  RecordProperty("liquid_density_consistency", text(rho_worst));
  RecordProperty("darcy_flux_error", text(std::abs(q_mean / q_exact - 1)));
  RecordProperty("darcy_flux_worst_point_error", text(q_worst));
  RecordProperty("pressure_linearity_error", text(p_worst));
  RecordProperty("effective_stress_error", text(s_worst));
  RecordProperty("effective_stress_error_vs_base", text(s_worst_abs));
}


// Undrained compression wave: the terzaghi column with K = 1e-5 m/s (the
// liquid cannot move relative to the skeleton within the test) on a 1 cm
// grid, loaded at once at the top. The pressure front reaches 0.5 m depth
// after h / c_u, c_u = sqrt((E_oed + K_L/n) / rho_sat); arrival is taken where
// the pore pressure of the point there crosses half its undrained value.
struct WaveArrival {
  double arrival_ratio;   // arrival / (depth / c_u)
  double pressure_ratio;  // behind the front at 1.25 depth / c_u: mean p / u_0 from 0.1 m depth to the probe
  double darcy_ratio;     // the largest |q| there over the solid's speed s / (rho_sat c_u)
  double step_over_drag_limit;  // the step over the explicit drag limit 2 (1-n) rho_s K / (n g rho_sat)
  std::size_t steps;
};

// The column of share/scenes/terzaghi.json at rest, 1 m on 110 cells, loaded
// by 10 kPa at once on its top: the undrained pressure wave u_0 travels down
// at c_u = sqrt((E_oed + K_L / n) / rho_sat). Its arrival half-way down (the
// time the probe's pressure reaches u_0 / 2) and the pressure behind it.
WaveArrival undrained_wave(double conductivity, double liquid_modulus) {
  auto j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["outputs"] = nlohmann::json::array();
  j["damping"] = 0.0;
  j["materials"]["soil"]["permeability"]["hydraulic_conductivity"] = conductivity;
  j["liquids"]["water"]["bulk_modulus"] = liquid_modulus;
  j["bodies"][0]["pore_pressure"] = 0.0;
  j["bodies"][0]["stress"] = {0, 0, 0, 0, 0, 0};
  j["grid"]["cell_size"] = {0.01, 0.01};
  j["grid"]["cells"] = {1, 110};
  j["bodies"][0]["max"] = {0.01, 1.0};
  boundary_condition(j, {{"type", "bc/traction"}})["box_max"] = {0.01, 1.0};
  const double E = 1e6, KL = liquid_modulus, n = 0.4, rho_s = 2650, rho_sat = (1 - n) * rho_s + n * 1000, s = 1e4;
  const double cu = std::sqrt((E + KL / n) / rho_sat), u0 = s * (KL / n) / (KL / n + E);

  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  std::size_t probe = 0;
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (std::abs(x[2 * k + 1] - 0.5) < std::abs(x[2 * probe + 1] - 0.5)) probe = k;
  const double depth = 1.0 - x[2 * probe + 1];
  const double* p = pts.data(pts.id("pore_pressure"));
  const double* q = pts.data(pts.id("darcy_flux"));
  WaveArrival w{-1, 0, 0, sim.dt() / (2 * (1 - n) * rho_s * conductivity / (n * 9.81 * rho_sat)), 0};
  double before = 0, t_before = 0;
  while (sim.time() < 1.25 * depth / cu) {
    sim.step();
    ++w.steps;
    if (w.arrival_ratio < 0 && p[probe] >= 0.5 * u0)
      w.arrival_ratio = (t_before + (sim.time() - t_before) * (0.5 * u0 - before) / (p[probe] - before)) / (depth / cu);
    before = p[probe];
    t_before = sim.time();
  }
  double sum = 0;
  std::size_t count = 0;
  for (std::size_t k = 0; k < pts.size(); ++k)
    if (1.0 - x[2 * k + 1] > 0.1 && 1.0 - x[2 * k + 1] < depth) sum += p[k], ++count;
  w.pressure_ratio = sum / static_cast<double>(count) / u0;
  for (std::size_t k = 0; k < pts.size(); ++k) w.darcy_ratio = std::max(w.darcy_ratio, std::abs(q[2 * k + 1]));
  w.darcy_ratio /= s / (rho_sat * cu);
  return w;
}

TEST(TwoPhase, UndrainedWaveArrival) {
  const WaveArrival w = undrained_wave(1e-5, 1e8);
  ASSERT_GT(w.arrival_ratio, 0) << "the wave never arrived";
  EXPECT_NEAR(w.arrival_ratio, 1.0, 0.05);
  RecordProperty("wave_arrival_error", text(w.arrival_ratio - 1));
}

// A clay (K = 1e-8 m/s) with water at its real stiffness, 2.2 GPa: the
// automatic step follows the undrained wave alone and is 700 times the
// explicit drag limit (4e-9 s here), so the drag is semi-implicit
// (grid_update_saturated); the wave arrives as in the undrained continuum,
// the pressure behind it is u_0, and the water moves with the skeleton.
TEST(TwoPhase, UndrainedWaveInAClayWithRealWater) {
  const WaveArrival w = undrained_wave(1e-8, 2.2e9);
  std::cout << "clay, real water: " << w.steps << " steps of " << w.step_over_drag_limit
            << " explicit drag limits; arrival / (depth / c_u) = " << w.arrival_ratio
            << ", p / u_0 behind the front = " << w.pressure_ratio << ", largest |q| / v_s = " << w.darcy_ratio
            << "\n";
  EXPECT_GT(w.step_over_drag_limit, 100);
  ASSERT_GT(w.arrival_ratio, 0) << "the wave never arrived";
  EXPECT_NEAR(w.arrival_ratio, 1.0, 0.05);
  EXPECT_NEAR(w.pressure_ratio, 1.0, 0.03);
  EXPECT_LT(w.darcy_ratio, 1e-3);
}

// Top displacement of the upward-seepage column at 0.1, 0.2 and 0.3 s for a
// head difference dh, with a cohesionless (tension cutoff) skeleton.
std::vector<double> heave_history(double dh) {
  auto j = read_json(source_dir() / "share/scenes/upward_seepage.json");
  j["outputs"] = nlohmann::json::array();
  j["grid"]["cells"] = {1, 80};  // room above the column
  j["materials"]["sand"]["tension_cutoff"] = true;
  boundary_condition(j, {{"type", "bc/pore_pressure"}, {"face", "bottom"}})["head"] = 1.0 + dh;
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const auto& pts = sim.points();
  std::vector<double> top;
  for (const double t : {0.1, 0.2, 0.3}) {
    while (sim.time() < t - 0.5 * sim.dt()) sim.step();
    top.push_back(pts.data(pts.core().displacement)[2 * (pts.size() - 1) + 1]);
  }
  return top;
}

// Heave: below the critical gradient i_cr = (G_s - 1)(1 - n) = 0.99 the
// column comes to rest; above it (i = 1.2) the skeleton lifts and keeps rising.
TEST(TwoPhase, HeaveAboveTheCriticalGradient) {
  const std::vector<double> below = heave_history(0.5), above = heave_history(1.2);
  // i = 0.5: the elastic rebound of the unloading, then rest (0.25 mm).
  EXPECT_GT(below[1], 0.0);
  EXPECT_LT(below[1], 1e-3);
  EXPECT_NEAR(below[2], below[1], 1e-6) << "the column should be at rest";
  // i = 1.2: upward and growing, far beyond the elastic rebound.
  EXPECT_GT(above[0], 0.0);
  EXPECT_GT(above[1], above[0] + 1e-3);
  EXPECT_GT(above[2], above[1] + 5e-4);
  EXPECT_GT(above[2], 10 * below[2]);
  RecordProperty("heave_top_displacement_at_0.3s", text(above[2]));
  RecordProperty("rest_top_displacement_at_0.3s", text(below[2]));
}


// Fluidisation, against the closed forms of a fluidised bed
// (docs/time-integration.md, Fluidisation). The column of upward_seepage.json,
// cohesionless (tension cut-off), with Kozeny-Carman permeability (K0 at n0 =
// 0.4), fed from below 1.2 times the flux q_c = K0 i_cr(n0) it passes at the
// critical gradient i_cr(n) = (1 - n)(G_s - 1). A front climbs from the base:
// - below it the skeleton is fluidised (no effective stress) and at rest, at
//   the porosity n* whose critical flux K(n*) i_cr(n*) is the inflow q_in;
// - above it the soil, still at n0, rises as a block at v_b = q_in - q_c (the
//   mixture's volume flux is q_in everywhere, and the block passes q_c);
// - the front climbs at c = (1 - n0) v_b / (n* - n0): the solid's mass across
//   a moving discontinuity between soil at rest and the block (Kynch).
// Measured between 2 s and 7 s, while the front climbs from 0.08 m to
// 0.36 m; later, once the rising top has entered the next cell row, the pore
// pressure at the free surface drifts and the run stops (10.6 s), a limit the
// docs state.
TEST(TwoPhase, FluidisationFrontAsInAFluidisedBed) {
  const double n0 = 0.4, K0 = 0.01, Gs = 2.65, growth = 1.2;
  const double q_in = growth * K0 * (1 - n0) * (Gs - 1);
  // K(n) i_cr(n) = q_in with K = K0 (n^3 / (1 - n)^2) / (n0^3 / (1 - n0)^2):
  // n^3 / (1 - n) = q_in n0^3 / ((1 - n0)^2 K0 (Gs - 1)), by bisection.
  const double target = q_in * n0 * n0 * n0 / ((1 - n0) * (1 - n0) * K0 * (Gs - 1));
  double lo = n0, hi = 0.9;
  while (hi - lo > 1e-14) {
    const double m = (lo + hi) / 2;
    (m * m * m / (1 - m) < target ? lo : hi) = m;
  }
  const double n_star = (lo + hi) / 2;

  auto j = read_json(source_dir() / "share/scenes/upward_seepage.json");
  j["outputs"] = nlohmann::json::array();
  j["grid"]["cells"] = {1, 60};  // room above the column
  j["materials"]["sand"]["tension_cutoff"] = true;
  j["materials"]["sand"]["permeability"] = {
      {"type", "permeability/kozeny_carman"}, {"hydraulic_conductivity", K0}, {"reference_porosity", n0}};
  j["boundary_conditions"].erase(boundary_condition_index(j, {{"type", "bc/pore_pressure"}, {"face", "bottom"}}));
  j["boundary_conditions"].push_back(
      {{"type", "bc/inflow_flux"}, {"face", "bottom"}, {"flux", q_in}, {"ramp_time", 0.5}});
  j["time"]["end"] = 7.0;
  j["sort_points_at_spread"] = 0;  // the points keep their numbers: u_early and order index them
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  const double* n = pts.data(pts.id("porosity"));
  const std::size_t count = pts.size();
  // The points by height at the start (two per row).
  std::vector<std::size_t> order(count);
  for (std::size_t k = 0; k < count; ++k) order[k] = k;
  std::sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) { return x[2 * a + 1] < x[2 * b + 1]; });
  const std::size_t rows = count / 2;
  // The front: where the rows' mean porosity first falls below (n0 + n*) / 2,
  // counted from the base, interpolated between the rows' heights.
  const auto front = [&] {
    const double mid = (n0 + n_star) / 2;
    double y_below = 0, n_below = n_star;
    for (std::size_t r = 1; r < rows; ++r) {  // the first row is the base's
      const std::size_t a = order[2 * r], b = order[2 * r + 1];
      const double y = (x[2 * a + 1] + x[2 * b + 1]) / 2, nr = (n[a] + n[b]) / 2;
      if (nr < mid) return r == 1 ? y : y_below + (y - y_below) * (n_below - mid) / (n_below - nr);
      y_below = y, n_below = nr;
    }
    return 1.0;
  };
  // The front's speed: the least-squares slope of its position, each second
  // from 2 s to 7 s.
  std::vector<double> u_early(count), times, fronts;
  for (double t = 2.0; t < 7.5; t += 1.0) {
    if (t < 7.0)
      while (sim.time() < t - 0.5 * sim.dt()) sim.step();
    else
      sim.run({});  // to the end time exactly
    times.push_back(sim.time()), fronts.push_back(front());
    if (times.size() == 1)
      for (std::size_t k = 0; k < count; ++k) u_early[k] = u[2 * k + 1];
  }
  const double t1 = times.front(), t2 = times.back(), front1 = fronts.front(), front2 = fronts.back();
  ASSERT_NEAR(t2, 7.0, 1e-9);
  double t_mean = 0, f_mean = 0, tt = 0, tf = 0;
  for (std::size_t i = 0; i < times.size(); ++i) t_mean += times[i], f_mean += fronts[i];
  t_mean /= static_cast<double>(times.size()), f_mean /= static_cast<double>(times.size());
  for (std::size_t i = 0; i < times.size(); ++i)
    tt += (times[i] - t_mean) * (times[i] - t_mean), tf += (times[i] - t_mean) * (fronts[i] - f_mean);
  const double speed = tf / tt;

  // Fluidised: the points from 4 cm above the base to 10 cm under the front.
  // The block: from 10 cm above the front to 10 cm under the top.
  double n_sum = 0, n_worst = 0, block_n = 0;
  std::vector<std::size_t> block;
  int fluidised = 0;
  for (std::size_t k = 0; k < count; ++k) {
    const double y = x[2 * k + 1];
    if (y > 0.04 && y < front2 - 0.1) {
      n_sum += n[k], ++fluidised;
      n_worst = std::max(n_worst, std::abs(n[k] / n_star - 1));
    }
    if (y > front2 + 0.1 && y < 0.9) block.push_back(k), block_n += n[k];
  }
  ASSERT_GT(fluidised, 10);
  ASSERT_GT(block.size(), 10u);
  // The block lost its effective stress before the front came: its elastic
  // rebound left its points 5e-4 looser than n0 on average (measured, block_n),
  // 0.5% more permeable, which alone would take 2.5% from v_b: the tolerance.
  block_n /= static_cast<double>(block.size());
  const double v_block = q_in - K0 * (1 - n0) * (Gs - 1);
  double v_sum = 0, v_worst = 0;
  for (const std::size_t k : block) {
    const double v = (u[2 * k + 1] - u_early[k]) / (t2 - t1);
    v_sum += v;
    v_worst = std::max(v_worst, std::abs(v / v_block - 1));
  }
  const double n_mean = n_sum / fluidised, v_mean = v_sum / static_cast<double>(block.size());
  const double c = (1 - n0) * v_block / (n_star - n0);
  EXPECT_NEAR(n_mean / n_star, 1.0, 2e-3) << "mean porosity of the fluidised zone";
  EXPECT_LT(n_worst, 0.02) << "porosity of each fluidised point";
  EXPECT_NEAR(v_mean / v_block, 1.0, 0.025) << "mean velocity of the block";
  EXPECT_LT(v_worst, 0.035) << "velocity of each point of the block";
  // The front spans three rows of points; over single seconds its speed
  // runs 7.5% slow to 0.3% fast (measured), over the five 3.6% slow.
  EXPECT_NEAR(speed / c, 1.0, 0.06) << "the front's speed";
  EXPECT_LT(sim.mass_ledger().liquid_imbalance(), 1e-12);
  EXPECT_LT(sim.mass_ledger().solid_imbalance(), 1e-12);
  RecordProperty("n_star", text(n_star));
  RecordProperty("fluidised_porosity_error", text(n_mean / n_star - 1));
  RecordProperty("fluidised_porosity_worst", text(n_worst));
  RecordProperty("block_porosity", text(block_n));
  RecordProperty("block_velocity_error", text(v_mean / v_block - 1));
  RecordProperty("block_velocity_worst", text(v_worst));
  RecordProperty("front_speed_error", text(speed / c - 1));
  RecordProperty("front_at_2s", text(front1));
  RecordProperty("front_at_7s", text(front2));
}

// Permeability laws, evaluated as the solver does (one batch).
TEST(TwoPhase, PermeabilityLaws) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  loader.load_directory(suffuse::PluginLoader::bundled_plugin_directory());
  const suffuse::Parameters kc({{"hydraulic_conductivity", 1e-4}, {"reference_porosity", 0.35}});
  auto kozeny = registry.create<suffuse::PermeabilityLaw>("permeability/kozeny_carman", {kc, 2, "/x"});
  const std::vector<double> n = {0.35, 0.2, 0.5, 0.9};
  std::vector<double> K(n.size());
  kozeny->conductivity(n, K);
  for (std::size_t k = 0; k < n.size(); ++k) {
    const double exact = 1e-4 * std::pow(n[k], 3) / std::pow(1 - n[k], 2) * std::pow(1 - 0.35, 2) / std::pow(0.35, 3);
    EXPECT_NEAR(K[k], exact, 1e-12 * exact) << "n = " << n[k];
  }
  EXPECT_DOUBLE_EQ(K[0], 1e-4);  // K_0 at the reference porosity
  EXPECT_LT(K[1], K[0]);
  EXPECT_GT(K[2], K[0]);

  const suffuse::Parameters c({{"hydraulic_conductivity", 3e-5}});
  auto constant = registry.create<suffuse::PermeabilityLaw>("permeability/constant", {c, 2, "/x"});
  constant->conductivity(n, K);
  for (double k : K) EXPECT_EQ(k, 3e-5);
}


// Two threads give the numbers of one thread in a saturated run too. A scene
// this small runs its loops on one thread whatever the thread count
// (Executor::min_items_per_thread); test_threads.cpp compares the splits.
TEST(TwoPhase, ThreadsAgreeWithSerial) {
  auto j = read_json(source_dir() / "share/scenes/upward_seepage.json");
  j["outputs"] = nlohmann::json::array();
  j["time"]["end"] = 0.1;
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation serial(scene, registry, 1), parallel(scene, registry, 2);
  serial.run({});
  parallel.run({});
  for (const char* field : {"pore_pressure", "darcy_flux", "stress", "porosity"}) {
    const auto a = serial.points().values(serial.points().id(field));
    const auto b = parallel.points().values(parallel.points().id(field));
    double largest = 0;
    for (double v : a) largest = std::max(largest, std::abs(v));
    EXPECT_GT(largest, 0.0) << field;  // the field is not trivially zero
    EXPECT_EQ(suffuse::test::max_relative_difference(a, b), 0.0) << field;  // bit for bit
  }
}


// The upward-seepage column fed by a prescribed inflow flux q = 5 mm/s
// instead of a head: the same steady state, so the Darcy flux is q and the
// pore pressure is gamma_w (L - y) (1 + q / K) (i = q / K = 0.5).
TEST(TwoPhase, InflowFluxBoundary) {
  auto j = read_json(source_dir() / "share/scenes/upward_seepage.json");
  j["outputs"] = nlohmann::json::array();
  boundary_condition(j, {{"type", "bc/pore_pressure"}, {"face", "bottom"}}) = {{"type", "bc/inflow_flux"}, {"face", "bottom"}, {"flux", 0.005}, {"ramp_time", 0.05}};
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  const double* p = pts.data(pts.id("pore_pressure"));
  const double* q = pts.data(pts.id("darcy_flux"));
  const double L = 1.0, gamma_w = 9810, i = 0.5;
  double q_mean = 0, p_worst = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double y = x[2 * k + 1] - u[2 * k + 1];
    q_mean += q[2 * k + 1] / static_cast<double>(pts.size());
    p_worst = std::max(p_worst, std::abs(p[k] - gamma_w * (L - y) * (1 + i)) / (gamma_w * L * (1 + i)));
  }
  EXPECT_NEAR(q_mean / 0.005, 1.0, 0.01);
  EXPECT_LT(p_worst, 0.02);  // as for the head inlet
  RecordProperty("inflow_flux_error", text(std::abs(q_mean / 0.005 - 1)));
  RecordProperty("inflow_pressure_error", text(p_worst));
}


// A dry body and a saturated body in one scene, both in uniform motion and
// apart: momentum is conserved, the dry body has no pore pressure, nothing
// turns into NaN, and neither body is stressed.
TEST(TwoPhase, DryAndSaturatedBodiesTogether) {
  auto j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["outputs"] = nlohmann::json::array();
  j["boundary_conditions"] = nlohmann::json::array();
  j["grid"] = {{"cell_size", {0.05, 0.05}}, {"cells", {40, 20}}};
  j["bodies"] = {{{"name", "wet"}, {"material", "soil"}, {"liquid", "water"}, {"porosity", 0.4},
                  {"min", {0.2, 0.2}}, {"max", {0.6, 0.6}}, {"velocity", {0.5, 0.0}}},
                 {{"name", "dry"}, {"material", "soil"}, {"min", {1.2, 0.2}}, {"max", {1.6, 0.6}},
                  {"velocity", {-0.5, 0.25}}}};
  j["time"] = {{"end", 0.1}};
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const auto p0 = sim.total_momentum();
  sim.run({});
  const auto p1 = sim.total_momentum();
  for (int a = 0; a < 2; ++a) EXPECT_NEAR(p1[a], p0[a], 1e-10 * std::abs(p0[0] == 0 ? 1 : p0[0]));
  const auto& pts = sim.points();
  const double* p = pts.data(pts.id("pore_pressure"));
  const double* n = pts.data(pts.id("porosity"));
  const double* s = pts.data(pts.core().stress);
  for (std::size_t k = 0; k < pts.size(); ++k) {
    ASSERT_TRUE(std::isfinite(p[k]) && std::isfinite(s[6 * k + 1])) << "point " << k;
    if (n[k] == 0) {
      EXPECT_EQ(p[k], 0.0) << "dry point " << k;
    }
    EXPECT_LT(std::abs(p[k]), 1.0) << "point " << k;       // Pa, against K_L = 1e8 Pa
    EXPECT_LT(std::abs(s[6 * k + 1]), 1.0) << "point " << k;
  }
}

// A saturated box closed on every side, its liquid set moving by gravity
// against a pore pressure that starts at zero: the masses of solid and of
// liquid stay what they were to round-off, and nothing crosses a boundary.
TEST(TwoPhase, ClosedBoxConservesSolidAndLiquidMass) {
  nlohmann::json j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["outputs"] = nlohmann::json::array();
  j["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.02, 0.02}}, {"cells", {10, 10}}};
  j["gravity"] = {0.0, -9.81};
  j["bodies"][0]["min"] = {0.0, 0.0};
  j["bodies"][0]["max"] = {0.2, 0.2};
  j["bodies"][0]["stress"] = nlohmann::json::array({0, 0, 0, 0, 0, 0});
  j["bodies"][0]["pore_pressure"] = 0.0;
  j["boundary_conditions"] = nlohmann::json::array();
  for (const char* face : {"left", "right"}) j["boundary_conditions"].push_back({{"type", "bc/velocity"}, {"face", face}, {"vx", 0.0}});
  for (const char* face : {"bottom", "top"}) j["boundary_conditions"].push_back({{"type", "bc/velocity"}, {"face", face}, {"vy", 0.0}});
  j["time"] = {{"end", 0.05}};
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const suffuse::MassLedger start = sim.mass_ledger();
  sim.run({});
  const suffuse::MassLedger end = sim.mass_ledger();
  const auto& pts = sim.points();
  const double* q = pts.data(pts.id("darcy_flux"));
  double q_max = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) q_max = std::max(q_max, std::abs(q[2 * k + 1]));
  EXPECT_GT(q_max, 1e-5) << "the liquid moved relative to the skeleton";
  EXPECT_LT(std::abs(end.liquid - start.liquid) / start.liquid, 1e-13);
  EXPECT_EQ(end.solid, start.solid);
  for (const auto& b : end.boundaries) {
    EXPECT_EQ(b.liquid_out, 0.0) << b.face;
    EXPECT_EQ(b.liquid_in, 0.0) << b.face;
  }
  RecordProperty("liquid_mass_change", text(std::abs(end.liquid - start.liquid) / start.liquid));
  RecordProperty("largest_darcy_flux", text(q_max));
}

// Two conditions opening one face to the liquid would count its outflow
// twice: the run is refused, naming both.
TEST(TwoPhase, OneFaceOpenedTwiceIsRefusedNamingBoth) {
  auto j = read_json(source_dir() / "share/scenes/upward_seepage.json");
  j["outputs"] = nlohmann::json::array();
  const nlohmann::json top = suffuse::test::boundary_condition(j, {{"type", "bc/pore_pressure"}, {"face", "bottom"}});
  j["boundary_conditions"].push_back(top);
  const std::size_t last = j["boundary_conditions"].size() - 1;
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  try {
    suffuse::Simulation sim(scene, registry);
    ADD_FAILURE() << "accepted";
  } catch (const suffuse::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/boundary_conditions/" + std::to_string(last)), std::string::npos) << what;
    EXPECT_NE(what.find(suffuse::test::boundary_condition_pointer(
                  read_json(source_dir() / "share/scenes/upward_seepage.json"), {{"type", "bc/pore_pressure"}, {"face", "bottom"}})),
              std::string::npos)
        << what;
    EXPECT_NE(what.find("bottom face"), std::string::npos) << what;
  }
}

}  // namespace

namespace {

// A saturated foundation (water table 0.2 m below its top at 0.6 m) with a
// dry fill 0.2 m high on its left part and a saturated berm 0.1 m high on
// its right part, all with k0; no surcharge, gravity on. `width` is the
// foundation's; the fill covers [0, fill_width], the berm the rest.
nlohmann::json stacked_bodies(double width, double fill_width) {
  auto j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["outputs"] = nlohmann::json::array();
  j["gravity"] = {0.0, -9.81};
  j["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.02, 0.02}}, {"cells", {std::lround(width / 0.02), 45}}};
  auto body = [](const char* name, double x0, double y0, double x1, double y1) {
    return nlohmann::json{{"name", name}, {"material", "soil"}, {"min", {x0, y0}}, {"max", {x1, y1}}, {"k0", 0.5}};
  };
  auto saturated = [](nlohmann::json b) {
    b["liquid"] = "water";
    b["porosity"] = 0.4;
    b["water_table"] = 0.4;
    return b;
  };
  j["bodies"] = {saturated(body("foundation", 0, 0, width, 0.6)), body("fill", 0, 0.6, fill_width, 0.8)};
  if (fill_width < width) j["bodies"].push_back(saturated(body("berm", fill_width, 0.6, width, 0.7)));
  j["boundary_conditions"] = {{{"type", "bc/velocity"}, {"face", "bottom"}, {"vx", 0.0}, {"vy", 0.0}},
                              {{"type", "bc/velocity"}, {"face", "left"}, {"vx", 0.0}},
                              {{"type", "bc/velocity"}, {"face", "right"}, {"vx", 0.0}}};
  return j;
}

}  // namespace

// The geostatic stress of a body carries everything above it: its own soil
// and pore liquid, the bodies stacked on it, less its hydrostatic pore
// pressure (zero above the water table). Each point's initial vertical
// effective stress against the sum written out here, and k0 times it
// horizontally.
TEST(TwoPhase, GeostaticStressCarriesTheBodiesStackedAbove) {
  const auto j = stacked_bodies(0.4, 0.2);
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const double g = 9.81, rho_s = 2650, rho_w = 1000, n = 0.4, wt = 0.4;
  const double saturated = ((1 - n) * rho_s + n * rho_w) * g, dry = rho_s * g;
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* s = pts.data(pts.core().stress);
  const double* p = pts.data(pts.id("pore_pressure"));
  std::size_t checked = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double px = x[2 * k], y = x[2 * k + 1];
    const double pore = y < wt && p[k] != 0 ? rho_w * g * (wt - y) : 0.0;  // dry points have none
    double total;  // the weight above, per unit area
    if (y < 0.6)
      total = saturated * (0.6 - y) + (px < 0.2 ? dry * 0.2 : saturated * 0.1);
    else if (px < 0.2)
      total = dry * (0.8 - y);
    else
      total = saturated * (0.7 - y);
    EXPECT_NEAR(p[k], pore, 1e-9 * rho_w * g) << "point " << k << " at (" << px << ", " << y << ")";
    EXPECT_NEAR(s[6 * k + 1], -(total - pore), 1e-9 * total) << "point " << k << " at (" << px << ", " << y << ")";
    EXPECT_NEAR(s[6 * k], 0.5 * s[6 * k + 1], 1e-9 * total) << "point " << k;
    EXPECT_NEAR(s[6 * k + 2], 0.5 * s[6 * k + 1], 1e-9 * total) << "point " << k;
    ++checked;
  }
  EXPECT_EQ(checked, pts.size());
}

// And it is an equilibrium: a column of that foundation under the fill,
// stepped once quasi-statically over a step too short for the liquid to
// move (undrained), barely stirs. The total stress the column needs and
// the stress it starts with differ only by the points' discretisation; a
// missing load would go into the pore pressure at once (the old buoyant
// weight missed 7.16 kPa below the water table: the liquid's weight above
// it and the fill's).
TEST(TwoPhase, GeostaticStressOfAStackIsInEquilibrium) {
  auto j = stacked_bodies(0.02, 0.02);
  j.erase("damping");
  j["time"] = {{"integration", "quasi_static"}, {"dt", 1e-6}, {"end", 1e-6}};
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const auto& pts = sim.points();
  const std::vector<double> p0(pts.values(pts.id("pore_pressure")).begin(), pts.values(pts.id("pore_pressure")).end());
  sim.run({});
  ASSERT_EQ(sim.steps(), 1u);
  const double* p = pts.data(pts.id("pore_pressure"));
  const double* u = pts.data(pts.core().displacement);
  double dp = 0, uy = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    dp = std::max(dp, std::abs(p[k] - p0[k]));
    uy = std::max(uy, std::abs(u[2 * k + 1]));
  }
  const double missing = 1000 * 9.81 * 0.2 + 2650 * 9.81 * 0.2;
  EXPECT_LT(dp, 0.02 * missing) << "largest pore pressure change, Pa";
  RecordProperty("largest_pore_pressure_change", text(dp));
  RecordProperty("largest_displacement", text(uy));
  std::printf("geostatic stack: largest pore pressure change %.3g Pa (%.2g of the %.0f Pa the old buoyant weight "
              "missed), largest displacement %.3g m\n",
              dp, dp / missing, missing, uy);
}
