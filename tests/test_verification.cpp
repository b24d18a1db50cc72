// Verification of the single-phase explicit MPM against analytical solutions.
// Each test states its tolerance and why it is what it is.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace {

using suffuse::test::read_json;
using suffuse::test::scene_from;
using suffuse::test::source_dir;

// Axial vibration of a bar fixed at x = 0, free at x = L: the first mode
// v(x, t) = v0 sin(pi x / 2L) cos(omega t) has the period T = 4 L / sqrt(E / rho).
TEST(Verification, ElasticBarPeriod) {
  auto j = read_json(source_dir() / "share/scenes/elastic_bar.json");
  j["outputs"] = nlohmann::json::array();
  const double L = 1.0, E = j["materials"]["steel_like"]["youngs_modulus"];
  const double rho = j["materials"]["steel_like"]["density"];
  const double T = 4 * L / std::sqrt(E / rho);

  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  double* v = pts.data(pts.core().velocity);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    v[p * 2] = 0.01 * std::sin(std::numbers::pi * x[p * 2] / (2 * L));
    v[p * 2 + 1] = 0;
  }

  // Zero crossings of the total momentum, which follows cos(omega t).
  std::vector<double> crossings;
  double previous = sim.total_momentum()[0];
  while (sim.time() < 3.2 * T) {
    const double t0 = sim.time();
    sim.step();
    const double now = sim.total_momentum()[0];
    if ((previous > 0) != (now > 0)) crossings.push_back(t0 + sim.dt() * previous / (previous - now));
    previous = now;
  }
  ASSERT_GE(crossings.size(), 5u);
  const double measured = 2 * (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
  // 1%: the requirement; linear MPM with 20 cells along the bar is
  // expected to be within a few tenths of a percent.
  EXPECT_NEAR(measured / T, 1.0, 0.01) << "measured period " << measured << " s, analytical " << T << " s";
  RecordProperty("bar_period_relative_error", std::to_string(measured / T - 1));
}

// Column under self-weight, settled with local damping: sigma_yy = -rho g (H - y0)
// where y0 is the initial height (the mass above a point does not change).
TEST(Verification, SelfWeightColumnStress) {
  auto j = read_json(source_dir() / "share/scenes/self_weight_column.json");
  j["outputs"] = nlohmann::json::array();
  const double rho = j["materials"]["soil"]["density"];
  const double g = 9.81, H = 10.0;

  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});

  const auto& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  const double* s = pts.data(pts.core().stress);
  const double* v = pts.data(pts.core().velocity);
  double worst = 0, vmax = 0;
  std::size_t checked = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    vmax = std::max(vmax, std::hypot(v[2 * p], v[2 * p + 1]));
    const double y0 = x[2 * p + 1] - u[2 * p + 1];
    if (y0 < 1.0 || y0 > H - 1.0) continue;  // one metre away from the base and the free top
    const double exact = -rho * g * (H - y0);
    worst = std::max(worst, std::abs(s[6 * p + 1] - exact) / std::abs(exact));
    ++checked;
  }
  EXPECT_GT(checked, pts.size() / 2);
  // 2%: the requirement for the stress away from the boundaries.
  EXPECT_LT(worst, 0.02) << "largest relative error of sigma_yy";
  // At rest: below 1% of the particle velocity of the loading wave, rho g H / (rho c) = 1.4 m/s.
  const double c = std::sqrt(double(j["materials"]["soil"]["youngs_modulus"]) / rho);
  EXPECT_LT(vmax, 0.01 * g * H / c);
  // Settlement: u_y(y0) = -(rho g / E) (H y0 - y0^2 / 2), at most rho g H^2 / (2 E) at the top.
  const double E = j["materials"]["soil"]["youngs_modulus"];
  const double u_top = rho * g * H * H / (2 * E);
  double worst_u = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const double y0 = x[2 * p + 1] - u[2 * p + 1];
    const double exact = -(rho * g / E) * (H * y0 - y0 * y0 / 2);
    worst_u = std::max(worst_u, std::abs(u[2 * p + 1] - exact) / u_top);
  }
  EXPECT_LT(worst_u, 0.02) << "largest settlement error, relative to the top settlement";
  RecordProperty("column_settlement_worst_error", std::to_string(worst_u));
  RecordProperty("column_stress_worst_relative_error", std::to_string(worst));
}

// A damped start (/damping_until): the column of SelfWeightColumnStress
// settles under its weight with local damping 0.2 until 10 s, to rho g H^2
// / (2 E) at its top; then it is free, and a surcharge q applied at once at
// 10 s drives it undamped: an elastic system under a suddenly applied load
// swings to twice its static displacement, the top to 2 q H / E below
// where it rested (a dynamic load factor of 2, the wave reflecting at the
// fixed base). Asserted: the settlement at 10 s within 1% of the closed
// form (measured -0.57%), the swing's peak within 5% of twice the static
// increment (1.936: the discrete column's highest modes, out of phase,
// round the wave's front, as its 40 cells of GIMP can); damped to the end,
// the same load's peak stays below the static increment (0.935; asserted
// below 1.5), so the damping did stop at 10 s.
TEST(Verification, ADampedStartLeavesTheColumnFreeUnderASuddenLoad) {
  const double rho = 2000, g = 9.81, H = 10.0, E = 1e7, q = 20e3, start = 10.0;
  auto peak_over_static = [&](bool damping_ends, double& settled) {
    auto j = read_json(source_dir() / "share/scenes/self_weight_column.json");
    j["outputs"] = nlohmann::json::array();
    if (damping_ends) j["damping_until"] = start;
    j["boundary_conditions"].push_back(
        {{"type", "bc/traction"}, {"box_min", {0.0, H}}, {"box_max", {0.25, H}}, {"traction", {0.0, -q}},
         {"factor", {{0.0, 0.0}, {start, 0.0}, {start + 1e-6, 1.0}, {100.0, 1.0}}}});
    j["time"]["end"] = start + 0.6;  // a period of the column, 4 H / c = 0.57 s, after the load
    suffuse::Registry registry;
    suffuse::Simulation sim(scene_from(j, registry), registry);
    const auto& pts = sim.points();
    const double* x = pts.data(pts.core().position);
    const double* u = pts.data(pts.core().displacement);
    std::size_t top = 0;
    for (std::size_t p = 0; p < pts.size(); ++p)
      if (x[2 * p + 1] > x[2 * top + 1]) top = p;
    while (sim.time() < start - 0.5 * sim.dt()) sim.step();
    settled = -u[2 * top + 1];
    double lowest = settled;
    while (sim.time() < j["time"]["end"].get<double>() - 0.5 * sim.dt()) {
      sim.step();
      lowest = std::max(lowest, -u[2 * top + 1]);
    }
    return (lowest - settled) / (q * H / E);
  };
  double settled = 0, settled_damped = 0;
  const double undamped = peak_over_static(true, settled);
  const double damped = peak_over_static(false, settled_damped);
  const double exact = rho * g * H * H / (2 * E);
  EXPECT_NEAR(settled, exact, 0.01 * exact) << "top settlement at rest [m]";
  EXPECT_NEAR(undamped, 2.0, 0.1) << "peak over the static increment, free after the damped start";
  EXPECT_LT(damped, 1.5) << "peak over the static increment, damped throughout";
  RecordProperty("settled", std::to_string(settled / exact - 1));
  RecordProperty("undamped", std::to_string(undamped));
  RecordProperty("damped", std::to_string(damped));
}

nlohmann::json free_body_scene(int dim) {
  nlohmann::json j;
  j["dimension"] = dim;
  const std::vector<double> h(dim, 0.1), v(dim == 2 ? std::vector<double>{1.0, -0.5}
                                                    : std::vector<double>{1.0, -0.5, 0.25});
  std::vector<int> cells(dim, 20);
  j["grid"] = {{"origin", std::vector<double>(dim, 0.0)}, {"cell_size", h}, {"cells", cells}};
  j["shape_function"] = {{"type", "shape/linear"}};
  j["materials"]["block"] = {{"type", "phase/linear_elastic"}, {"density", 1500.0}, {"youngs_modulus", 1e6},
                             {"poisson_ratio", 0.25}};
  j["bodies"] = {{{"material", "block"}, {"min", std::vector<double>(dim, 0.55)},
                  {"max", std::vector<double>(dim, 1.05)}, {"velocity", v}}};
  j["time"] = {{"end", 0.3}};
  return j;
}

// A free body in uniform motion: mass and momentum conserved to round-off, no
// stress created, and it moves by v t.
class FreeBody : public ::testing::TestWithParam<int> {};

TEST_P(FreeBody, ConservesMassAndMomentum) {
  const int dim = GetParam();
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(free_body_scene(dim), registry);
  suffuse::Simulation sim(scene, registry);
  const double m0 = sim.total_mass();
  const auto p0 = sim.total_momentum();
  const auto& pts = sim.points();
  const std::vector<double> x0(pts.values(pts.core().position).begin(), pts.values(pts.core().position).end());
  sim.run({});
  EXPECT_GT(sim.steps(), 50u);
  EXPECT_EQ(sim.total_mass(), m0);
  const auto p1 = sim.total_momentum();
  double drift = 0;
  for (int a = 0; a < dim; ++a) {
    EXPECT_NEAR(p1[a], p0[a], 1e-12 * std::abs(p0[0])) << "axis " << a;
    drift = std::max(drift, std::abs(p1[a] - p0[a]) / std::abs(p0[0]));
  }
  RecordProperty("momentum_relative_drift", [&] { std::ostringstream o; o << drift; return o.str(); }());
  const double* x = pts.data(pts.core().position);
  const double* s = pts.data(pts.core().stress);
  const double v[3] = {1.0, -0.5, 0.25};
  for (std::size_t p = 0; p < pts.size(); ++p) {
    for (int a = 0; a < dim; ++a) EXPECT_NEAR(x[p * dim + a] - x0[p * dim + a], v[a] * sim.time(), 1e-10);
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(s[p * 6 + c], 0.0, 1e-6);  // Pa, against E = 1e6 Pa
  }
}

INSTANTIATE_TEST_SUITE_P(Dimensions, FreeBody, ::testing::Values(2, 3));

// The same scene gives the same numbers, run after run.
TEST(Verification, Deterministic) {
  suffuse::Registry registry;
  auto j = read_json(source_dir() / "share/scenes/elastic_bar.json");
  j["outputs"] = nlohmann::json::array();
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation a(scene, registry), b(scene, registry);
  a.run({});
  b.run({});
  const auto& pa = a.points();
  const auto& pb = b.points();
  for (suffuse::FieldId f = 0; f < pa.field_count(); ++f) {
    const auto va = pa.values(f), vb = pb.values(f);
    ASSERT_TRUE(std::equal(va.begin(), va.end(), vb.begin())) << pa.info(f).name;
  }
}

// Two threads give the numbers of one thread, bit for bit. A column this
// small runs its loops on one thread whatever the thread count
// (Executor::min_items_per_thread); test_threads.cpp has scenes whose loops
// split, of several scatter chunks.
TEST(Verification, ThreadsAgreeWithSerial) {
  suffuse::Registry registry;
  auto j = read_json(source_dir() / "share/scenes/self_weight_column.json");
  j["outputs"] = nlohmann::json::array();
  j["time"]["end"] = 1.0;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation serial(scene, registry, 1), parallel(scene, registry, 2);
  serial.run({});
  parallel.run({});
  EXPECT_EQ(parallel.total_mass(), serial.total_mass());
  const auto& a = serial.points();
  const auto& b = parallel.points();
  const auto sa = a.values(a.core().stress), sb = b.values(b.core().stress);
  EXPECT_GT(std::abs(*std::min_element(sa.begin(), sa.end())), 1e5);  // Pa: the column is loaded
  EXPECT_EQ(suffuse::test::max_relative_difference(sa, sb), 0.0);
}

// A point leaving the grid stops the run with a message naming it.
TEST(Verification, PointLeavingTheGridIsAnError) {
  auto j = free_body_scene(2);
  j["bodies"][0]["velocity"] = {10.0, 0.0};
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  try {
    sim.run({});
    FAIL() << "no error";
  } catch (const suffuse::Error& e) {
    const std::string m = e.what();
    EXPECT_NE(m.find("of body 'body 0' left the grid at step"), std::string::npos) << m;
  }
}

}  // namespace

namespace {

// Mass scaling: the self-weight column settles to the same stress with a
// four times larger automatic step (scaling 16); the weight is not scaled.
TEST(Verification, MassScalingKeepsTheQuasiStaticAnswer) {
  auto j = read_json(source_dir() / "share/scenes/self_weight_column.json");
  j["outputs"] = nlohmann::json::array();
  j["time"]["end"] = 40.0;  // the slowed-down column needs four times longer to settle
  suffuse::Registry registry;
  auto scaled_json = j;
  scaled_json["time"]["mass_scaling"] = 16.0;
  const suffuse::Scene plain_scene = scene_from(j, registry), scaled_scene = scene_from(scaled_json, registry);
  suffuse::Simulation plain(plain_scene, registry), scaled(scaled_scene, registry);
  EXPECT_NEAR(scaled.dt() / plain.dt(), 4.0, 1e-12);
  scaled.run({});
  const auto& pts = scaled.points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  const double* s = pts.data(pts.core().stress);
  const double rho = 2000, g = 9.81, H = 10;
  double worst = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const double y0 = x[2 * p + 1] - u[2 * p + 1];
    if (y0 < 1.0 || y0 > H - 1.0) continue;
    worst = std::max(worst, std::abs(s[6 * p + 1] + rho * g * (H - y0)) / (rho * g * (H - y0)));
  }
  EXPECT_LT(worst, 0.02);
  EXPECT_EQ(scaled.total_mass(), plain.total_mass());  // the points' mass is not scaled
  RecordProperty("mass_scaled_column_stress_error", std::to_string(worst));
}

}  // namespace
