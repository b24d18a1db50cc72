// Quasi-static integration (docs/time-integration.md) against the closed
// forms of consolidation and steady seepage, and against explicit runs.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <sstream>
#include <vector>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace {

using suffuse::test::read_json;
using suffuse::test::scene_from;
using suffuse::test::source_dir;

using suffuse::test::text;

using suffuse::test::terzaghi_pressure;

// The explicit scene made quasi-static: no damping, a first step.
nlohmann::json quasi_static(nlohmann::json j, double dt, double max_dt = 0) {
  j.erase("damping");
  j["time"].erase("cfl");
  j["time"].erase("mass_scaling");
  j["time"]["integration"] = "quasi_static";
  j["time"]["dt"] = dt;
  if (max_dt > 0) j["time"]["max_dt"] = max_dt;
  j["outputs"] = nlohmann::json::array();
  return j;
}

// The Terzaghi column of share/scenes/terzaghi.json made 3D: one cell deep,
// the front and back faces held like the left and right ones.
nlohmann::json terzaghi_3d(nlohmann::json j) {
  j["dimension"] = 3;
  j["grid"] = {{"origin", {0.0, 0.0, 0.0}}, {"cell_size", {0.02, 0.02, 0.02}}, {"cells", {1, 55, 1}}};
  j["bodies"][0]["min"] = {0.0, 0.0, 0.0};
  j["bodies"][0]["max"] = {0.02, 1.0, 0.02};
  j["boundary_conditions"] = {
      {{"type", "bc/velocity"}, {"face", "bottom"}, {"vx", 0.0}, {"vy", 0.0}, {"vz", 0.0}},
      {{"type", "bc/velocity"}, {"face", "left"}, {"vx", 0.0}},
      {{"type", "bc/velocity"}, {"face", "right"}, {"vx", 0.0}},
      {{"type", "bc/velocity"}, {"face", "front"}, {"vz", 0.0}},
      {{"type", "bc/velocity"}, {"face", "back"}, {"vz", 0.0}},
      {{"type", "bc/traction"}, {"box_min", {0.0, 1.0, 0.0}}, {"box_max", {0.02, 1.0, 0.02}},
       {"traction", {0.0, -10000.0, 0.0}}}};
  return j;
}

// The Terzaghi column with steps 174 times the explicit one (whose stable
// step the liquid's bulk modulus sets): isochrones within 0.02 u_0 of the
// series at T_v = 0.05, 0.2, 0.5 and 1 (measured in 2D 0.018, 0.015, 0.012,
// 0.008: the spatial error, the same with steps 8 times shorter; the 3D
// column gives the same figures to the digits printed); the total stress
// carries the load.
void check_terzaghi_isochrones(const nlohmann::json& explicit_scene) {
  const int dim = explicit_scene["dimension"];
  const double H = 1.0, s = 1e4;
  const double E = explicit_scene["materials"]["soil"]["youngs_modulus"];
  const double K = explicit_scene["materials"]["soil"]["permeability"]["hydraulic_conductivity"];
  const double n = explicit_scene["bodies"][0]["porosity"];
  const double KL = explicit_scene["liquids"]["water"]["bulk_modulus"];
  const double u0 = s * (KL / n) / (KL / n + E);
  const double cv = K * E / (1000 * 9.81);
  suffuse::Registry registry;
  double explicit_dt = 0;
  {
    const suffuse::Scene scene = scene_from(explicit_scene, registry);
    explicit_dt = suffuse::Simulation(scene, registry).dt();
  }
  const double dt = 0.0049;  // T_v = 0.005 per step
  ASSERT_GE(dt, 100 * explicit_dt);
  const suffuse::Scene scene = scene_from(quasi_static(explicit_scene, dt), registry);
  suffuse::Simulation sim(scene, registry);
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  const double* sig = pts.data(pts.core().stress);
  const double* p = pts.data(pts.id("pore_pressure"));
  for (const double Tv : {0.05, 0.2, 0.5, 1.0}) {
    while (sim.time() < Tv * H * H / cv - 0.5 * dt) sim.step();
    const double tv = sim.time() * cv / (H * H);
    double isochrone = 0, total = 0;
    std::vector<double> cell_total(50, 0.0), cell_points(50, 0.0);
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double y = x[dim * i + 1] - u[dim * i + 1];
      isochrone = std::max(isochrone, std::abs(p[i] - terzaghi_pressure(u0, H - y, H, tv)) / u0);
      const auto c = std::min<std::size_t>(49, static_cast<std::size_t>(y / 0.02));
      cell_total[c] += sig[6 * i + 1] - p[i];
      cell_points[c] += 1;
    }
    for (std::size_t c = 0; c < 50; ++c) total = std::max(total, std::abs(cell_total[c] / cell_points[c] / -s - 1));
    EXPECT_LT(isochrone, 0.02) << "T_v = " << Tv;
    // Per cell: the points of a cell share its strain while the pressure
    // varies linearly, so each differs from the load by up to 2.6%; the
    // cells' means by 0.4% to 1.0% (T_v = 0.05 to 1) as the column settles
    // 1 cm and the points' cells change.
    EXPECT_LT(total, 0.015) << "T_v = " << Tv << ": total vertical stress / load - 1, cell means";
    testing::Test::RecordProperty("isochrone_error_Tv_" + text(Tv), text(isochrone));
    testing::Test::RecordProperty("total_stress_error_Tv_" + text(Tv), text(total));
  }
  testing::Test::RecordProperty("steps", text(static_cast<double>(sim.steps())));
  testing::Test::RecordProperty("step_over_explicit", text(dt / explicit_dt));
  EXPECT_LT(sim.mass_ledger().liquid_imbalance(), 1e-12);
}

TEST(QuasiStatic, TerzaghiIsochrones) {
  check_terzaghi_isochrones(read_json(source_dir() / "share/scenes/terzaghi.json"));
}

TEST(QuasiStatic, TerzaghiIsochrones3D) {
  check_terzaghi_isochrones(terzaghi_3d(read_json(source_dir() / "share/scenes/terzaghi.json")));
}

// share/scenes/upward_seepage.json, quasi-static: the head at the base rises
// by 0.5 m over 0.05 s, then the flow is steady. Averaged over each cell's
// points (within a cell the strain is constant and the pressure linear, so
// the two rows of points differ by +-0.5% of the base effective stress and
// their mean is the cell's): Darcy flux K i within 0.1% and effective stress
// (gamma' - i gamma_w) z within 0.5% of its base value; pore pressure linear
// at every point within 0.1% of the base pressure; the liquid's ledger
// closes. The drained top cell too: the free surface's pressure is zero
// where the surface is, not at the node next to it (measured: flux 0.076%,
// effective stress 0.070%, pressure 0.006%). With p = 0 at the node the
// top cell's flux was 0.58% off: the column swells 0.25 mm above its top
// node. A column 0.99 m tall ends half a cell below a node (measured 0.076%,
// 0.052%, 0.006%; with p = 0 at the node the top cell's flux was 48% off,
// the effective stress 4.8% and the pressure 1.6%), in 2D and in 3D. And
// with a saturated layer one cell thick held one empty cell above that
// column: the same figures (its bottom node, drained, followed the
// column's pressure across the gap while extrapolation could walk past a
// surface node: the column's flux was then 27% off).
void check_steady_upward_seepage(double L, int dim = 2, bool lid = false) {
  auto j = quasi_static(read_json(source_dir() / "share/scenes/upward_seepage.json"), 0.05);
  j["bodies"][0]["max"][1] = L;
  j["bodies"][0]["water_table"] = L;
  auto& head = j["boundary_conditions"][4];
  ASSERT_EQ(head["type"], "bc/pore_pressure");
  head["initial_head"] = L;
  head["head"] = L + 0.5;
  if (dim == 3) {  // the same column, one cell deep, standing along z (the vertical is the last axis)
    j["dimension"] = 3;
    j["gravity"] = {0.0, 0.0, -9.81};
    j["grid"] = {{"origin", {0.0, 0.0, 0.0}}, {"cell_size", {0.02, 0.02, 0.02}}, {"cells", {1, 1, 55}}};
    j["bodies"][0]["min"] = {0.0, 0.0, 0.0};
    j["bodies"][0]["max"] = {0.02, 0.02, L};
    head["face"] = "front";
    j["boundary_conditions"][0] = {{"type", "bc/velocity"}, {"face", "front"}, {"vx", 0.0}, {"vy", 0.0},
                                   {"vz", 0.0}, {"phase", "solid"}};
    j["boundary_conditions"][1] = {{"type", "bc/velocity"}, {"face", "front"}, {"vx", 0.0}, {"vy", 0.0},
                                   {"phase", "liquid"}};
    j["boundary_conditions"].push_back({{"type", "bc/velocity"}, {"face", "bottom"}, {"vy", 0.0}});
    j["boundary_conditions"].push_back({{"type", "bc/velocity"}, {"face", "top"}, {"vy", 0.0}});
  }
  if (lid) {  // a saturated layer one cell thick, held one empty cell above the column
    auto layer = j["bodies"][0];
    layer["name"] = "lid";
    layer["min"] = {0.0, 1.02};
    layer["max"] = {0.02, 1.04};
    layer["water_table"] = 1.04;
    j["bodies"].push_back(layer);
    j["boundary_conditions"].push_back({{"type", "bc/velocity"}, {"box_min", {0.0, 1.02}}, {"box_max", {0.02, 1.04}},
                                        {"vx", 0.0}, {"vy", 0.0}, {"phase", "solid"}});
  }
  suffuse::test::UpwardSeepage seepage;
  seepage.L = L;
  const double q_exact = seepage.flux(), h = 0.02;
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
  const auto cells = static_cast<std::size_t>(std::ceil(L / h - 1e-9));
  std::vector<double> cell_q(cells, 0.0), cell_error(cells, 0.0), cell_points(cells, 0.0);
  double p_worst = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double y = x[dim * k + dim - 1] - u[dim * k + dim - 1], z = L - y;  // height
    if (y > L) continue;  // the lid
    const auto c = std::min(cells - 1, static_cast<std::size_t>(y / h));
    p_worst = std::max(p_worst, std::abs(p[k] - seepage.pressure(y)) / seepage.pressure(0));
    cell_q[c] += q[dim * k + dim - 1];
    cell_error[c] += s[6 * k + dim - 1] + seepage.effective_stress(z);  // sigma'_yy, sigma'_zz in 3D
    cell_points[c] += 1;
  }
  double q_worst = 0, s_worst = 0;
  const double s_base = seepage.effective_stress(L);
  for (std::size_t c = 0; c < cells; ++c) {
    q_worst = std::max(q_worst, std::abs(cell_q[c] / cell_points[c] / q_exact - 1));
    s_worst = std::max(s_worst, std::abs(cell_error[c] / cell_points[c]) / s_base);
  }
  EXPECT_LT(q_worst, 1e-3) << "Darcy flux, cell means";
  EXPECT_LT(s_worst, 5e-3) << "effective stress, cell means / its base value";
  EXPECT_LT(p_worst, 1e-3) << "pore pressure / base pressure";
  EXPECT_LT(sim.mass_ledger().liquid_imbalance(), 1e-12);
  ::testing::Test::RecordProperty("darcy_flux_error", text(q_worst));
  ::testing::Test::RecordProperty("effective_stress_error", text(s_worst));
  ::testing::Test::RecordProperty("pressure_linearity_error", text(p_worst));
  ::testing::Test::RecordProperty("steps", text(static_cast<double>(sim.steps())));
}

TEST(QuasiStatic, SteadyUpwardSeepage) { check_steady_upward_seepage(1.0); }

TEST(QuasiStatic, SteadyUpwardSeepageBelowASurfaceBetweenNodes) { check_steady_upward_seepage(0.99); }

TEST(QuasiStatic, SteadyUpwardSeepageBelowASurfaceBetweenNodes3D) { check_steady_upward_seepage(0.99, 3); }

TEST(QuasiStatic, SteadyUpwardSeepageBelowALayerAcrossAGap) { check_steady_upward_seepage(0.99, 2, true); }

// A dry body: share/scenes/self_weight_column.json (10 m, E = 10 MPa, no
// liquid) in one quasi-static step: sigma_yy = -rho g (H - y) at the points,
// within half a point spacing's weight (the stress of a point is its
// cell's, the load grows linearly; measured 0.625%); the surface settles
// rho g H^2 / (2 E) within 0.1% (measured 0.016%).
TEST(QuasiStatic, DrySelfWeightColumn) {
  auto j = quasi_static(read_json(source_dir() / "share/scenes/self_weight_column.json"), 1.0);
  j["time"]["end"] = 1.0;
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const suffuse::RunSummary run = sim.run({});
  ASSERT_EQ(sim.steps(), 1u);
  EXPECT_EQ(run.creep_held_most, 0u) << "every point of an elastic column under its weight has its stiffness";
  EXPECT_TRUE(std::isnan(run.creep_held_from));
  const double rho = j["materials"]["soil"]["density"], E = j["materials"]["soil"]["youngs_modulus"], g = 9.81;
  const double H = j["bodies"][0]["max"][1];
  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  const double* s = pts.data(pts.core().stress);
  double worst = 0, settlement = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    const double y = x[2 * k + 1] - u[2 * k + 1];
    worst = std::max(worst, std::abs(s[6 * k + 1] + rho * g * (H - y)) / (rho * g * H));
    settlement = std::min(settlement, u[2 * k + 1]);
  }
  const double exact = -rho * g * H * H / (2 * E);
  EXPECT_LT(worst, 0.007) << "sigma_yy / base stress (half a point spacing's weight: 0.625%)";
  EXPECT_NEAR(settlement / exact, 1.0, 1e-3) << "surface settlement";
  RecordProperty("stress_error", text(worst));
  RecordProperty("settlement_ratio", text(settlement / exact));
}

// With /time/inertia a step balances the mixture's inertia too (backward
// Euler): M (du - dt v0) / dt^2 = f. A column falling freely (no support,
// no stress) then moves exactly as the scheme's own recurrence says, every
// point alike: after n steps v = g n dt and u = g dt^2 n (n + 1) / 2.
TEST(QuasiStatic, InertiaMakesAFreeFallTheSchemesOwn) {
  auto j = quasi_static(read_json(source_dir() / "share/scenes/self_weight_column.json"), 0.02, 0.02);
  j["time"]["inertia"] = true;
  j["time"]["end"] = 0.2;
  j["grid"]["origin"] = {0.0, -1.0};
  j["grid"]["cells"] = {1, 45};
  j["boundary_conditions"] = {{{"type", "bc/velocity"}, {"face", "left"}, {"vx", 0.0}},
                              {{"type", "bc/velocity"}, {"face", "right"}, {"vx", 0.0}}};
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});
  ASSERT_EQ(sim.steps(), 10u);
  const double g = 9.81, dt = 0.02, n = 10;
  const double u_exact = -g * dt * dt * n * (n + 1) / 2, v_exact = -g * n * dt;
  const auto& pts = sim.points();
  const double* u = pts.data(pts.core().displacement);
  const double* v = pts.data(pts.core().velocity);
  const double* stress = pts.data(pts.core().stress);
  double u_error = 0, v_error = 0, largest_stress = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    u_error = std::max(u_error, std::abs(u[2 * p + 1] / u_exact - 1));
    v_error = std::max(v_error, std::abs(v[2 * p + 1] / v_exact - 1));
    for (int c = 0; c < 6; ++c) largest_stress = std::max(largest_stress, std::abs(stress[6 * p + c]));
  }
  EXPECT_LT(u_error, 1e-12);
  EXPECT_LT(v_error, 1e-12);
  const double base_stress = 2000.0 * g * 10.0;  // rho g H, what the column would carry standing
  EXPECT_LT(largest_stress, 1e-9 * base_stress) << "Pa: a free fall strains nothing";
  RecordProperty("displacement_error", text(u_error));
}

// The elastic bar of share/scenes/elastic_bar.json (fixed at x = 0, free at
// x = L, every point starting at v0), stepped with /time/inertia at twice
// the explicit stability limit h / c. The reference is independent of MPM:
// the bar's modes (omega_k = (2k - 1) pi c / 2L), each stepped by the same
// backward Euler recurrence (q' = (q + dt v) / (1 + omega^2 dt^2), v' =
// (q' - q) / dt), summed at the last point. Backward Euler shortens the
// swing of each mode by 1 / sqrt(1 + omega^2 dt^2) per step, the higher
// modes most: the first peak is 25% below the exact v0 L / c. Measured: the
// bar within 0.32% of that peak of the reference over two periods (the
// MPM's own error in space).
TEST(QuasiStatic, InertiaSwingsAnElasticBarAsBackwardEulerSwingsItsModes) {
  auto j = quasi_static(read_json(source_dir() / "share/scenes/elastic_bar.json"), 1e-3, 1e-3);
  j["time"]["inertia"] = true;
  j["time"]["end"] = 0.08;  // two periods
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const double L = 1.0, v0 = 0.01, c = std::sqrt(1e7 / 1000.0), dt = 1e-3;
  ASSERT_GE(dt, 2 * 0.05 / c) << "twice the explicit limit";
  const auto& pts = sim.points();
  std::size_t tip = 0;
  for (std::size_t p = 0; p < pts.size(); ++p)
    if (pts.data(pts.core().position)[2 * p] > pts.data(pts.core().position)[2 * tip]) tip = p;
  const double x_tip = pts.data(pts.core().position)[2 * tip];
  constexpr int modes = 400;
  std::vector<double> q(modes, 0.0), qv(modes, 0.0), omega(modes), shape(modes);
  for (int k = 0; k < modes; ++k) {
    const double beta = (2 * k + 1) * std::numbers::pi / (2 * L);
    omega[k] = c * beta;
    shape[k] = std::sin(beta * x_tip);
    qv[k] = 4 * v0 / ((2 * k + 1) * std::numbers::pi);  // v0 = sum of qv_k sin(beta_k x)
  }
  double worst = 0, peak = 0;
  suffuse::RunOptions options;
  options.on_step = [&](const suffuse::Progress&) {
    double reference = 0;
    for (int k = 0; k < modes; ++k) {
      const double next = (q[k] + dt * qv[k]) / (1 + omega[k] * omega[k] * dt * dt);
      qv[k] = (next - q[k]) / dt;
      q[k] = next;
      reference += q[k] * shape[k];
    }
    const double u = pts.data(pts.core().displacement)[2 * tip];
    worst = std::max(worst, std::abs(u - reference));
    peak = std::max(peak, u);
  };
  sim.run(options);
  ASSERT_EQ(sim.steps(), 80u);
  const double u_max = v0 * L / c;  // the exact peak: the sum of the modes' swings
  EXPECT_LT(worst / u_max, 0.01) << "of the exact peak";
  EXPECT_LT(peak / u_max, 0.8) << "backward Euler damps";
  EXPECT_GT(peak / u_max, 0.7);
  RecordProperty("tip_error_over_peak", text(worst / u_max));
  RecordProperty("first_peak_over_exact", text(peak / u_max));
}

// The Mohr-Coulomb column that has no equilibrium (NoEquilibriumSaysWhere)
// collapses with /time/inertia, as in an explicit run: the mean displacement
// of its points after 0.1 s within 3% of the explicit run's (no damping in
// either). Measured: -1.3% across, -1.4% down, in 33 steps of 0.005 s or
// less (14 halved; the explicit run takes 245).
TEST(QuasiStatic, InertiaCollapsesAColumnThatHasNoEquilibrium) {
  const auto collapse = read_json(source_dir() / "share/scenes/column_collapse_mc.json");
  const auto mean_displacement = [](const suffuse::PointSet& pts) {
    std::array<double, 2> sum{0, 0};
    const double* u = pts.data(pts.core().displacement);
    for (std::size_t p = 0; p < pts.size(); ++p)
      for (int i = 0; i < 2; ++i) sum[i] += u[2 * p + i] / static_cast<double>(pts.size());
    return sum;
  };
  auto e = collapse;
  e["damping"] = 0.0;
  e["time"]["end"] = 0.1;
  e["outputs"] = nlohmann::json::array();
  suffuse::Registry registry;
  suffuse::Simulation explicit_run(scene_from(e, registry), registry);
  explicit_run.run({});
  auto j = quasi_static(collapse, 0.005, 0.005);
  j["time"]["end"] = 0.1;
  j["time"]["inertia"] = true;
  suffuse::Simulation sim(scene_from(j, registry), registry);
  sim.run({});
  const auto reference = mean_displacement(explicit_run.points()), u = mean_displacement(sim.points());
  EXPECT_GT(reference[0], 0.005) << "m: the column spreads";
  for (int i = 0; i < 2; ++i) EXPECT_NEAR(u[i] / reference[i], 1.0, 0.03) << "axis " << i;
  RecordProperty("across_over_explicit", text(u[0] / reference[0]));
  RecordProperty("down_over_explicit", text(u[1] / reference[1]));
  RecordProperty("explicit_steps", text(static_cast<double>(explicit_run.steps())));
}

// A cohesionless column free on one side has no static equilibrium: the run
// stops with an error that says where the forces did not balance (a node on
// the column) and which points had no stiffness (the sand at the apex of
// its cone: c = 0, so wherever it is unconfined).
TEST(QuasiStatic, NoEquilibriumSaysWhere) {
  auto j = quasi_static(read_json(source_dir() / "share/scenes/column_collapse_mc.json"), 0.1);
  j["time"]["end"] = 0.5;
  j["time"]["max_iterations"] = 8;  // each of the 21 attempts gives up sooner: a third of the test's time
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  std::string message;
  try {
    sim.run({});
  } catch (const suffuse::Error& e) {
    message = e.what();
  }
  ASSERT_NE(message.find("no equilibrium"), std::string::npos) << message;
  const std::string at = "is at the node (";
  const auto k = message.find(at);
  ASSERT_NE(k, std::string::npos) << message;
  double x = -1, y = -1;
  ASSERT_EQ(std::sscanf(message.c_str() + k + at.size(), "%lf, %lf", &x, &y), 2) << message;
  const double h = 0.05, width = j["bodies"][0]["max"][0], height = j["bodies"][0]["max"][1];
  EXPECT_GE(x, 0.0);
  EXPECT_LE(x, width + h) << "the node is on the column";
  EXPECT_GE(y, 0.0);
  EXPECT_LE(y, height + h) << "the node is on the column";
  EXPECT_NE(message.find("had no stiffness at the last iteration"), std::string::npos) << message;
  EXPECT_EQ(sim.steps(), 0u) << "no step converged";
}

// The default suffusion column, quasi-static (share/scenes/suffusion_column_1h.json
// to 50 s): at least 1,000 times fewer steps than the explicit run, every
// species' ledger closing to 1e-12, the erodible fines washed out by 50 s
// as in the explicit run, within 1% (docs/time-integration.md gives F(t)
// against explicit runs: too long for a test).
TEST(QuasiStatic, SuffusionColumn) {
  suffuse::Registry registry;
  double explicit_dt = 0;
  {
    auto j = read_json(source_dir() / "share/scenes/suffusion_column.json");
    j["outputs"] = nlohmann::json::array();
    const suffuse::Scene scene = scene_from(j, registry);
    explicit_dt = suffuse::Simulation(scene, registry).dt();
  }
  auto j = read_json(source_dir() / "share/scenes/suffusion_column_1h.json");
  j["time"]["end"] = 50.0;
  j["outputs"] = nlohmann::json::array();
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const suffuse::RunSummary run = sim.run({});
  const double explicit_steps = 50.0 / explicit_dt;
  EXPECT_LE(static_cast<double>(run.steps) * 1000, explicit_steps);
  const suffuse::MassLedger& ledger = *run.ledger;
  EXPECT_LT(ledger.fines_imbalance(), 1e-12);
  EXPECT_LT(ledger.liquid_imbalance(), 1e-12);
  EXPECT_LT(ledger.solid_imbalance(), 1e-12);
  // The erodible fines washed out by 50 s, as in the explicit run: F is
  // (f_c0 - f_c_inf) / (1 - f_c_inf) of the solid, 0.15789 (measured
  // 0.157895; the heaving top kept 0.2% before the consistent face flux).
  const double F = ledger.eroded / ledger.initial_solid, F_all = (0.2 - 0.05) / (1 - 0.05);
  EXPECT_GT(F, 0.999 * F_all);
  EXPECT_LE(F, F_all * (1 + 1e-12));
  // The summary says when points had no stiffness (held by the creep
  // term): a few at the surface from about 16 s, and the heaving top, a
  // seventh of the column (96 points at 39.1 s), after its onset at 38 s.
  EXPECT_GE(run.creep_held_most, sim.points().size() / 8) << "the heaving top";
  EXPECT_GE(run.creep_held_most_at, 38.0);
  EXPECT_LE(run.creep_held_most_at, 45.0);
  RecordProperty("creep_held_most", text(static_cast<double>(run.creep_held_most)));
  RecordProperty("creep_held_most_at", text(run.creep_held_most_at));
  RecordProperty("eroded_fraction_50s", text(F));
  RecordProperty("steps", text(static_cast<double>(run.steps)));
  RecordProperty("explicit_steps", text(explicit_steps));
  RecordProperty("fines_imbalance", text(ledger.fines_imbalance()));
}

// The default column's eroded fraction F(t), quasi-static with steps of at
// most 0.05 s (share/scenes/suffusion_column_1h.json to 50 s), against the
// explicit run of share/scenes/suffusion_column.json without mass scaling
// (/time/mass_scaling 1: 1.45 million steps, 28 minutes; its ledger gave the
// values below): within 1% at each time, using at least 1,000 times fewer
// steps (measured: 1,007 steps; within 0.99% at 3 s, 0.73% at 5 s, under
// 0.5% from 8 s on; 0.98% and 0.67% when a step eroded with its end's flux
// alone, not the mean of its start's and end's). The bound is issue 13's: tight on purpose, a change
// that crosses it no longer meets the issue. The points' Darcy flux is the nodal flux interpolated:
// with -K grad p at each point, F was 1.58% high at 5 s and 1.04% low at 45 s.
TEST(QuasiStatic, SuffusionColumnErodesAsTheExplicitRunDoes) {
  const std::array<std::array<double, 2>, 10> explicit_run{{{3, 0.007231},
                                                            {5, 0.012312},
                                                            {8, 0.019401},
                                                            {10, 0.024367},
                                                            {12, 0.029458},
                                                            {20, 0.051941},
                                                            {30, 0.086235},
                                                            {40, 0.136374},
                                                            {45, 0.157895},
                                                            {50, 0.157895}}};
  suffuse::Registry registry;
  double explicit_dt = 0;
  {
    auto j = read_json(source_dir() / "share/scenes/suffusion_column.json");
    j["outputs"] = nlohmann::json::array();
    j["time"]["mass_scaling"] = 1.0;
    const suffuse::Scene scene = scene_from(j, registry);
    explicit_dt = suffuse::Simulation(scene, registry).dt();
  }
  auto j = read_json(source_dir() / "share/scenes/suffusion_column_1h.json");
  j["time"]["end"] = 50.0;
  j["time"]["max_dt"] = 0.05;
  j["outputs"] = nlohmann::json::array();
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  std::vector<std::array<double, 2>> F{{0.0, 0.0}};  // (t, F) after each step
  suffuse::RunOptions options;
  options.on_step = [&](const suffuse::Progress&) {
    const suffuse::MassLedger ledger = sim.mass_ledger();
    F.push_back({sim.time(), ledger.eroded / ledger.initial_solid});
  };
  const suffuse::RunSummary run = sim.run(options);
  EXPECT_LE(static_cast<double>(run.steps) * 1000, 50.0 / explicit_dt);
  double worst = 0;
  for (const auto& [t, F_explicit] : explicit_run) {
    const auto after = std::lower_bound(F.begin(), F.end(), t, [](const auto& a, double v) { return a[0] < v; });
    ASSERT_NE(after, F.end()) << t;
    ASSERT_NE(after, F.begin()) << t;
    const auto& [t1, F1] = *after;
    const auto& [t0, F0] = *(after - 1);
    const double at_t = F0 + (F1 - F0) * (t - t0) / (t1 - t0);
    EXPECT_NEAR(at_t / F_explicit, 1.0, 0.01) << "F at " << t << " s";
    worst = std::max(worst, std::abs(at_t / F_explicit - 1));
  }
  RecordProperty("eroded_fraction_worst_relative_difference", text(worst));
  RecordProperty("steps", text(static_cast<double>(run.steps)));
  RecordProperty("explicit_steps", text(50.0 / explicit_dt));
}

// The default column in a grid one cell taller, so that its top is a free
// surface: the last uneroded layer heaves at about 38 s. With the tension
// cut-off's "point" separation a point's whole stress drops when it turns
// tensile, a jump Newton's iterations cannot settle below 2e-7 to 3e-6 of
// the forces: the run crawled at the heave (36.7 s, steps of 1e-6 s).
// Rankine's continuous cut-off ("planes", and the creep term on the nodes of
// points separated across a plane) passes it: to 50 s in 93 steps
// (measured), every ledger closing.
TEST(QuasiStatic, HeavePassesWithSeparationAcrossPlanes) {
  auto j = read_json(source_dir() / "share/scenes/suffusion_column_1h.json");
  j["time"]["end"] = 50.0;
  j["time"]["inertia"] = true;
  j["grid"]["cells"] = {4, 41};
  j["materials"]["gap_graded_sand"]["separation"] = "planes";
  j["outputs"] = nlohmann::json::array();
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  const suffuse::RunSummary run = sim.run({});
  EXPECT_NEAR(sim.time(), 50.0, 1e-9);
  EXPECT_LE(run.steps, 150u) << "it crawled";
  const suffuse::MassLedger& ledger = *run.ledger;
  EXPECT_LT(ledger.fines_imbalance(), 1e-12);
  EXPECT_LT(ledger.liquid_imbalance(), 1e-12);
  EXPECT_LT(ledger.solid_imbalance(), 1e-12);
  // The top heaved: its points carry no stress across horizontal planes.
  const auto& pts = sim.points();
  const double* u = pts.data(pts.core().displacement);
  double heave = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) heave = std::max(heave, u[p * 2 + 1]);
  EXPECT_GT(heave, 1e-4);
  RecordProperty("steps", text(static_cast<double>(run.steps)));
  RecordProperty("heave", text(heave));
}

// The default column made 3D, one cell deep: z is the vertical in 3D (heads,
// water tables, geostatic stress), so the column stands along z, its base
// and top the front and back faces; the y faces held like the x ones. The
// same eroded fraction, displacement and steps as the 2D column, and every
// ledger closing, at 10 s, while the erosion front is under way.
nlohmann::json column_3d(const nlohmann::json& flat) {
  nlohmann::json j = flat;
  j["dimension"] = 3;
  j["gravity"] = {0.0, 0.0, -9.81};
  j["grid"] = {{"origin", {0.0, 0.0, 0.0}}, {"cell_size", {0.01, 0.01, 0.01}}, {"cells", {4, 1, 40}}};
  j["bodies"][0]["min"] = {0.0, 0.0, 0.0};
  j["bodies"][0]["max"] = {0.04, 0.01, 0.4};
  j["boundary_conditions"] = nlohmann::json::array();
  for (nlohmann::json bc : flat["boundary_conditions"]) {
    const std::string face = bc["face"];
    bc["face"] = face == "bottom" ? "front" : face == "top" ? "back" : face;
    if (bc["type"] == "bc/velocity" && face == "bottom") {
      if (bc.contains("vy")) bc["vz"] = bc["vy"];
      bc["vy"] = 0.0;
    }
    j["boundary_conditions"].push_back(bc);
  }
  for (const char* face : {"bottom", "top"}) j["boundary_conditions"].push_back({{"type", "bc/velocity"}, {"face", face}, {"vy", 0.0}});
  return j;
}

TEST(QuasiStatic, SuffusionColumn3D) {
  auto j = read_json(source_dir() / "share/scenes/suffusion_column_1h.json");
  j["time"]["end"] = 10.0;
  j["outputs"] = nlohmann::json::array();
  struct Result {
    double F, heave;
    std::size_t steps;
  };
  auto run = [](const nlohmann::json& scene_json) {
    suffuse::Registry registry;
    const suffuse::Scene scene = scene_from(scene_json, registry);
    suffuse::Simulation sim(scene, registry);
    const suffuse::RunSummary summary = sim.run({});
    const suffuse::MassLedger& ledger = *summary.ledger;
    EXPECT_LT(ledger.fines_imbalance(), 1e-12);
    EXPECT_LT(ledger.liquid_imbalance(), 1e-12);
    EXPECT_LT(ledger.solid_imbalance(), 1e-12);
    const auto& pts = sim.points();
    const int dim = scene.dim;
    const double* u = pts.data(pts.core().displacement);
    double heave = 0;  // the largest vertical displacement (the seepage lifts the column)
    for (std::size_t p = 0; p < pts.size(); ++p) heave = std::max(heave, std::abs(u[p * dim + dim - 1]));
    return Result{ledger.eroded / ledger.initial_solid, heave, summary.steps};
  };
  const Result flat = run(j), deep = run(column_3d(j));
  std::printf("column at 10 s: F %.9f (2D) %.9f (3D), largest vertical displacement %.9e %.9e m, steps %zu %zu\n",
              flat.F, deep.F, flat.heave, deep.heave, flat.steps, deep.steps);
  EXPECT_GT(flat.F, 0.01) << "the front is under way";
  EXPECT_LT(flat.F, 0.9 * (0.2 - 0.05) / (1 - 0.05)) << "and not through";
  EXPECT_NEAR(deep.F, flat.F, 1e-6 * flat.F);
  EXPECT_GT(flat.heave, 0.0);
  EXPECT_NEAR(deep.heave, flat.heave, 1e-6 * flat.heave);
  EXPECT_EQ(deep.steps, flat.steps);
}

// The default column without erosion, its pores full of clean water, fed
// with a suspension (c = 0.01) from below: the front crosses it in about
// 6 s, then the flow carries the suspension through unchanged. Once a
// substep erodes nothing and the composition is steady, the rest of a step
// is one backward-Euler step instead of hundreds of substeps.
struct SuspensionRun {
  suffuse::MassLedger at_100s, at_end;
  std::size_t substeps = 0, steady_steps = 0;
  double largest_concentration = 0;
};
SuspensionRun feed_suspension(double steady_tolerance) {
  suffuse::Registry registry;
  auto j = read_json(source_dir() / "share/scenes/suffusion_column_1h.json");
  j["materials"]["gap_graded_sand"].erase("erosion");
  j["bodies"][0]["fines_content"] = 0.0;
  j["bodies"][0]["ultimate_fines_content"] = 0.0;
  j["time"]["end"] = 200.0;
  j["time"]["max_dt"] = 20.0;
  j["time"]["steady_transport_tolerance"] = steady_tolerance;
  j["outputs"] = nlohmann::json::array();
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  SuspensionRun r;
  while (sim.time() < 100) sim.step();
  r.at_100s = sim.mass_ledger();
  const suffuse::RunSummary run = sim.run({});
  r.at_end = *run.ledger;
  r.substeps = sim.transport_substeps();
  r.steady_steps = sim.steady_transport_steps();
  for (const double c : sim.points().values(*sim.points().find("concentration")))
    r.largest_concentration = std::max(r.largest_concentration, c);
  return r;
}

// Fines and liquid leaving the top between 100 s and the end.
std::pair<double, double> top_outflow(const SuspensionRun& r) {
  auto out = [](const suffuse::MassLedger& l, bool fines) {
    for (const auto& b : l.boundaries)
      if (b.face == "top") return fines ? b.fines_out - b.fines_in : b.liquid_out - b.liquid_in;
    return 0.0;
  };
  return {out(r.at_end, true) - out(r.at_100s, true), out(r.at_end, false) - out(r.at_100s, false)};
}

TEST(QuasiStatic, SteadyTransportEndsStepsWithOneImplicitStep) {
  const SuspensionRun steady = feed_suspension(1e-3), substepped = feed_suspension(0);
  for (const SuspensionRun* r : {&steady, &substepped}) {
    EXPECT_LT(r->at_end.fines_imbalance(), 1e-12);
    EXPECT_LT(r->at_end.liquid_imbalance(), 1e-12);
  }
  // Every step after the front ended implicitly, with few substeps.
  EXPECT_EQ(substepped.steady_steps, 0u);
  EXPECT_GE(steady.steady_steps, 8u);
  EXPECT_LT(steady.substeps * 5, substepped.substeps);
  // Steady: what leaves has the composition of what enters, the mass
  // fraction of fines c rho_s / (c rho_s + (1 - c) rho_w).
  const double c = 0.01, fraction = c * 2650 / (c * 2650 + (1 - c) * 1000);
  const auto [fines, liquid] = top_outflow(steady);
  const auto [fines_substepped, liquid_substepped] = top_outflow(substepped);
  EXPECT_NEAR(fines / liquid, fraction, 1e-6 * fraction);
  EXPECT_NEAR(fines_substepped / liquid_substepped, fraction, 1e-6 * fraction);
  // The implicit steps carry what the substeps do (measured: 4.1e-6).
  EXPECT_NEAR(fines, fines_substepped, 1e-4 * fines_substepped);
  EXPECT_NEAR(liquid, liquid_substepped, 1e-4 * liquid_substepped);
  // No point holds a suspension much above what was fed in (the points'
  // share of their nodes' changes leaves 5e-4 of it).
  EXPECT_LT(steady.largest_concentration, 1.001 * c);
  RecordProperty("substeps", text(static_cast<double>(steady.substeps)));
  RecordProperty("substeps_without", text(static_cast<double>(substepped.substeps)));
  RecordProperty("fines_out_relative_difference", text(fines / fines_substepped - 1));
  RecordProperty("outflow_fines_fraction_error", text(fines / liquid / fraction - 1));
  RecordProperty("outflow_fines_fraction_error_substepped",
                 text(fines_substepped / liquid_substepped / fraction - 1));
  RecordProperty("liquid_out_relative_difference", text(liquid / liquid_substepped - 1));
  RecordProperty("largest_concentration", text(steady.largest_concentration));
}

}  // namespace

// A block off the grid's lines carried sideways by its base, quasi-statically,
// without gravity: a translation, which strains nothing. As its edges move,
// the supports of its outer points reach new nodes by slivers; such nodes
// have no unknowns of their own and follow the points (their stiffness is
// nearly nil: solved for, they swung by metres in the levee, and here the
// Newton iterations do not settle on any step). Following the points, they
// carry the translation exactly; held in place, they would strain the
// points they touch (1.6 kPa after 30 steps).
TEST(QuasiStatic, NodesABodyBarelyReachesFollowIt) {
  auto j = quasi_static(read_json(source_dir() / "share/scenes/self_weight_column.json"), 0.1);
  j["gravity"] = {0.0, 0.0};
  j["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.1, 0.1}}, {"cells", {10, 6}}};
  j["bodies"][0]["min"] = {0.2013, 0.0};
  j["bodies"][0]["max"] = {0.6013, 0.3001};
  j["boundary_conditions"] = {{{"type", "bc/velocity"}, {"face", "bottom"}, {"vx", 0.01}, {"vy", 0.0}}};
  j["time"]["end"] = 3.0;
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});
  ASSERT_EQ(sim.steps(), 30u);
  const auto& pts = sim.points();
  const double* u = pts.data(pts.core().displacement);
  const double* s = pts.data(pts.core().stress);
  const double E = j["materials"]["soil"]["youngs_modulus"];
  double stress = 0, ux = 0;
  for (std::size_t k = 0; k < pts.size(); ++k) {
    for (int c = 0; c < 6; ++c) stress = std::max(stress, std::abs(s[6 * k + c]));
    ux = std::max(ux, std::abs(u[2 * k] - 0.03));
    EXPECT_NEAR(u[2 * k + 1], 0.0, 1e-12) << "point " << k;
  }
  EXPECT_LT(ux, 1e-12) << "every point moved with the base, 3 cm";
  // A strain of 1e-12 in a step of 1 mm over 10 cm cells is round-off.
  EXPECT_LT(stress, 1e-12 * E) << "largest stress component, Pa";
  RecordProperty("largest_stress", text(stress));
}

namespace {

// The levee of share/scenes/levee_suffusion.json at 20 cm cells, quasi-static,
// for its first 4 s: Mohr-Coulomb's levee and the suffosion foundation
// yield at the landside toe, so the tangent changes from one Newton
// iteration to the next. With /time/reuse_factors (the default) the
// iterations after a step's first solve by GMRES, preconditioned by the
// factors of an earlier iterate; they reach the equilibria of runs that
// factorise every iteration within the Newton tolerance: the same steps,
// and every point's displacement, stress and pore pressure within 1e-9 of
// the field's largest (measured: 3.5e-13), with fewer than half as many
// factorisations.
TEST(QuasiStatic, ReusedFactorsReachTheEquilibriaOfFactorisedOnes) {
  const auto j = suffuse::test::coarse_quasi_static_levee(4.0);
  suffuse::Registry registry;
  auto factorised = j;
  factorised["time"]["reuse_factors"] = false;
  const suffuse::Scene reusing_scene = scene_from(j, registry), factorised_scene = scene_from(factorised, registry);
  suffuse::Simulation reusing(reusing_scene, registry), every(factorised_scene, registry);
  const suffuse::RunSummary a = reusing.run({}), b = every.run({});
  ASSERT_EQ(a.steps, b.steps);
  EXPECT_GE(b.factorisations, b.newton_iterations) << "one factorisation per iteration (failed attempts' too)";
  EXPECT_EQ(b.gmres_iterations, 0u);
  EXPECT_GT(a.gmres_iterations, 0u);
  EXPECT_LT(2 * a.factorisations, a.newton_iterations);
  const auto& pa = reusing.points();
  const auto& pb = every.points();
  ASSERT_EQ(pa.size(), pb.size());
  double worst = 0;
  for (const char* field : {"displacement", "stress", "pore_pressure"}) {
    const double d = suffuse::test::max_relative_difference(pa.values(pa.id(field)), pb.values(pb.id(field)));
    EXPECT_LT(d, 1e-9) << field;
    worst = std::max(worst, d);
  }
  std::printf("levee to 4 s: %zu steps; reusing factors %zu factorisations and %zu GMRES iterations in %zu Newton "
              "iterations, factorising %zu in %zu; fields within %.1e\n",
              a.steps, a.factorisations, a.gmres_iterations, a.newton_iterations, b.factorisations,
              b.newton_iterations, worst);
  RecordProperty("largest_relative_difference", text(worst));
}

// A step starts Newton from the last equilibrium's nodal pressures, not from
// the points' projection of them (the storage of the old pressures is the
// points' either way). Steps so short that nothing moves between them then
// start in equilibrium: the third of three steps of 1 ns, on the Terzaghi
// column just loaded and on the coarse levee (Mohr-Coulomb, GIMP), starts
// within 1e-6 of the forces (measured 4.1e-7 and 2.7e-7: what the second
// step moved). From the projection they started 3.5e-2 and 3.2e-2 off,
// however short the step: that difference is carried undrained,
// and on a flood levee's wetting front it pushed points to the apex until
// the step lost its equilibrium.
TEST(QuasiStatic, AShortStepStartsInTheLastEquilibrium) {
  const auto terzaghi = quasi_static(read_json(source_dir() / "share/scenes/terzaghi.json"), 1e-9);
  auto levee = suffuse::test::coarse_quasi_static_levee(1.0);
  levee["time"]["dt"] = 1e-9;
  for (const auto& [name, j] : {std::pair{"terzaghi", terzaghi}, std::pair{"levee", levee}}) {
    suffuse::Registry registry;
    const suffuse::Scene scene = scene_from(j, registry);
    suffuse::Simulation sim(scene, registry);
    std::vector<double> first;
    for (int step = 0; step < 3; ++step) {
      sim.step();
      ASSERT_FALSE(sim.newton_residuals().empty());
      first.push_back(sim.newton_residuals().front());
    }
    std::printf("%s: steps of 1 ns start %.1e, %.1e, %.1e off balance\n", name, first[0], first[1], first[2]);
    RecordProperty(std::string(name) + "_third_start", text(first[2]));
    EXPECT_LT(first[2], 1e-6) << name;
  }
}


// A step the run rejects and halves leaves nothing behind: the attempt at
// half the step is the step taken at that size from the start, bit for bit.
// The Terzaghi column on a soil five times softer settles 5 cm (2.5 cells);
// under /failure a first step that moves a node a cell or more is a
// mechanism's and halved. Until 0.21.4 the retry started Newton from the
// rejected attempt's pressures (the equilibrium it had found at the longer
// step), so that the run depended on the attempts it had thrown away.
TEST(QuasiStatic, AHalvedStepIsTheStepTakenAtItsSize) {
  auto j = quasi_static(read_json(source_dir() / "share/scenes/terzaghi.json"), 2.0);
  j["materials"]["soil"]["youngs_modulus"] = 2e5;
  j["time"]["reuse_factors"] = false;  // (reused factors would carry the attempt's matrix)
  j["failure"] = nlohmann::json::object();
  suffuse::Registry registry;
  const suffuse::Scene halving_scene = scene_from(j, registry);
  suffuse::Simulation halving(halving_scene, registry);
  halving.step();
  ASSERT_GT(halving.halved_steps(), 0u) << "the first attempt was not rejected";
  const double dt = halving.time();
  j["time"]["dt"] = dt;
  const suffuse::Scene direct_scene = scene_from(j, registry);
  suffuse::Simulation direct(direct_scene, registry);
  direct.step();
  ASSERT_EQ(direct.halved_steps(), 0u);
  ASSERT_EQ(direct.time(), dt);
  const auto& a = halving.points();
  const auto& b = direct.points();
  for (const char* field : {"displacement", "stress", "pore_pressure"}) {
    const auto x = a.values(a.id(field)), y = b.values(b.id(field));
    EXPECT_TRUE(std::ranges::equal(x, y)) << field << " differs by up to " << suffuse::test::max_relative_difference(x, y);
  }
  std::printf("Terzaghi, soft: the step of 2 s halved %zu times to %g s, as the step taken at %g s\n",
              halving.halved_steps(), dt, dt);
}

}  // namespace
