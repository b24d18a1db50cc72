// Phases coupled to the other parts of the core: the coupling fields a phase
// reads, the eigenstrain it writes, and the validation of what it needs.
// Uses the coupled-phase template (share/templates/coupled_phase, built here
// as tests/plugins/eroding_elastic).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <suffuse/error.hpp>
#include <suffuse/simulation.hpp>
#include <vector>

#include "test_support.hpp"

namespace {

using suffuse::test::scene_from;

std::string sci(double v) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", v);
  return text;
}

// A rigid column (every skeleton node held) with a uniform Darcy flux q from
// base to top, no gravity, erosion/fines_limited: the eroded fraction grows
// uniformly, by the closed form of physics.md section 2 (see test_erosion).
nlohmann::json rigid_eroding_column(const nlohmann::json& phase) {
  nlohmann::json j;
  const double h = 0.02, L = 0.2;
  j["dimension"] = 2;
  j["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {h, h}}, {"cells", {1, 10}}};
  j["shape_function"] = {{"type", "shape/gimp"}};
  j["materials"]["sand"] = phase;
  j["materials"]["sand"]["permeability"] = {{"type", "permeability/constant"}, {"hydraulic_conductivity", 0.1}};
  j["materials"]["sand"]["erosion"] = {{"type", "erosion/fines_limited"}, {"lambda", 1.0}};
  j["liquids"]["water"] = {{"type", "phase/pore_liquid"}, {"density", 1000.0}, {"bulk_modulus", 1e6}};
  j["bodies"] = {{{"material", "sand"}, {"liquid", "water"}, {"porosity", 0.3}, {"fines_content", 0.25},
                  {"ultimate_fines_content", 0.05}, {"min", {0.0, 0.0}}, {"max", {h, L}},
                  {"stress", {-1000.0, -2000.0, -500.0, 0.0, 0.0, 100.0}}}};
  j["boundary_conditions"] = {
      {{"type", "bc/velocity"}, {"box_min", {0.0, 0.0}}, {"box_max", {h, L}}, {"vx", 0.0}, {"vy", 0.0}, {"phase", "solid"}},
      {{"type", "bc/velocity"}, {"face", "left"}, {"vx", 0.0}},
      {{"type", "bc/velocity"}, {"face", "right"}, {"vx", 0.0}},
      {{"type", "bc/inflow_flux"}, {"face", "bottom"}, {"flux", 0.5}, {"ramp_time", 0.1}},
      {{"type", "bc/pore_pressure"}, {"face", "top"}, {"pressure", 0.0}}};
  j["time"] = {{"end", 1.5}};
  j["outputs"] = nlohmann::json::array();
  j["plugin_paths"] = {std::string(SUFFUSE_TEST_PLUGIN_DIR) + "/eroding_elastic"};
  return j;
}

const nlohmann::json eroding_elastic = {{"type", "phase/eroding_elastic"}, {"density", 2650.0},
                                        {"youngs_modulus", 1e7},          {"poisson_ratio", 0.25},
                                        {"softening", 10.0},              {"residual_stiffness", 0.2}};

// A phase that reads the eroded fraction is refused, naming the field and the
// material, where the scene provides none: a dry scene, and a saturated one
// without fines.
TEST(CoupledPhase, RefusedWhereTheFieldIsMissing) {
  nlohmann::json saturated = rigid_eroding_column(eroding_elastic);
  saturated["materials"]["sand"].erase("erosion");
  saturated["bodies"][0]["fines_content"] = 0.0;
  saturated["bodies"][0]["ultimate_fines_content"] = 0.0;
  nlohmann::json dry = saturated;
  dry["materials"]["sand"].erase("permeability");
  for (const char* key : {"liquid", "porosity", "fines_content", "ultimate_fines_content"}) dry["bodies"][0].erase(key);
  dry["boundary_conditions"] = nlohmann::json::array();
  for (const auto& j : {saturated, dry}) {
    suffuse::Registry registry;
    try {
      scene_from(j, registry);
      ADD_FAILURE() << "accepted a phase whose field the scene lacks";
    } catch (const suffuse::SceneError& e) {
      const std::string what = e.what();
      EXPECT_NE(what.find("/materials/sand/type"), std::string::npos) << what;
      EXPECT_NE(what.find("reads point field 'eroded_fraction'"), std::string::npos) << what;
      EXPECT_NE(what.find("fines are tracked"), std::string::npos) << what;
    }
  }
  // With erosion the same scene is valid.
  suffuse::Registry registry;
  EXPECT_NO_THROW(scene_from(rigid_eroding_column(eroding_elastic), registry));
}

// On a held skeleton the strain increment is zero, so the eigenstrain alone
// moves the stress: the secant-elastic phase keeps sigma = C(E) eps_e at a
// constant elastic strain, sigma = sigma_0 E(f_er) / E_0 at every point and
// every step, to round-off. The eroded fraction follows the closed form; the
// core's accumulated "eigenstrain" is S(E_0) sigma_0 times the sum of the
// step ratios E_k / E_k+1 - 1, which is ln(E_0 / E) to first order.
TEST(CoupledPhase, StressFollowsTheStiffnessOnAHeldSkeleton) {
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(rigid_eroding_column(eroding_elastic), registry);
  suffuse::Simulation sim(scene, registry);
  const auto& pts = sim.points();
  const double E0 = 1e7, nu = 0.25, a = 10.0, r = 0.2, end = 1.5;
  const double s0[6] = {-1000.0, -2000.0, -500.0, 0.0, 0.0, 100.0};
  // Closed form of the uniform erosion (fines_limited, lambda = 1, q ramped over 0.1 s).
  const double n0 = 0.3, fc0 = 0.25, fc_inf = 0.05, q = 0.5, ramp = 0.1;
  const double C = (1 - n0) * (1 - fc0), F0 = (1 - n0) * fc0, F_inf = fc_inf * C / (1 - fc_inf);
  auto eroded_fraction = [&](double t) {
    const double Q = t < ramp ? q * t * t / (2 * ramp) : q * (t - ramp / 2);
    return (F0 - (F_inf + (F0 - F_inf) * std::exp(-(1 - fc_inf) * Q))) / (C + F0);
  };
  double worst_stress = 0, worst_fraction = 0, reached = 0, worst_increment = 0;
  std::vector<double> n_before(pts.size()), f_before(pts.size()), fc_before(pts.size());
  while (sim.time() < end - 1e-9) {
    const double* n = pts.data(pts.id("porosity"));
    const double* fc = pts.data(pts.id("fines_content"));
    for (std::size_t p = 0; p < pts.size(); ++p)
      n_before[p] = n[p], f_before[p] = pts.data(pts.id("eroded_fraction"))[p], fc_before[p] = fc[p];
    sim.step();
    const double* s = pts.data(pts.core().stress);
    const double* fer = pts.data(pts.id("eroded_fraction"));
    // The step's increments, as the phase saw them, are this step's changes.
    const double* dn = pts.data(pts.id("porosity_increment"));
    const double* dfer = pts.data(pts.id("eroded_fraction_increment"));
    const double* dfc = pts.data(pts.id("fines_content_increment"));
    for (std::size_t p = 0; p < pts.size(); ++p)
      worst_increment = std::max({worst_increment, std::abs(dn[p] - (n[p] - n_before[p])),
                                  std::abs(dfer[p] - (fer[p] - f_before[p])), std::abs(dfc[p] - (fc[p] - fc_before[p]))});
    for (std::size_t p = 0; p < pts.size(); ++p) {
      const double ratio = std::max(r, 1 - a * fer[p]);
      for (int c = 0; c < 6; ++c)
        worst_stress = std::max(worst_stress, std::abs(s[p * 6 + c] - s0[c] * ratio) / 2000.0);
      worst_fraction = std::max(worst_fraction, std::abs(fer[p] - eroded_fraction(sim.time())));
      reached = std::max(reached, fer[p]);
    }
  }
  RecordProperty("worst_stress_error", sci(worst_stress));
  RecordProperty("worst_eroded_fraction_error", sci(worst_fraction));
  EXPECT_LT(worst_stress, 1e-12);
  EXPECT_LT(worst_increment, 1e-15) << "porosity, eroded fraction and fines content increments of the step";
  EXPECT_LT(worst_fraction, 0.01 * eroded_fraction(end));
  EXPECT_GT(reached, (1 - r) / a) << "the residual stiffness was reached";
  const double* e = pts.data(pts.id("eigenstrain"));
  const double* fer = pts.data(pts.id("eroded_fraction"));
  const double elastic_yy = ((1 + nu) * s0[1] - nu * (s0[0] + s0[1] + s0[2])) / E0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const double expected = elastic_yy * std::log(1 / std::max(r, 1 - a * fer[p]));
    EXPECT_NEAR(e[p * 6 + 1], expected, 1e-3 * std::abs(expected));
  }
}

// A block of phase/test_swelling (eps* = rate t in x and y, rate 0.01 1/s,
// E = 1 MPa, nu = 0) from min to max, without gravity, to t = 2 s: the
// eigenstrain is then 0.02.
constexpr double swelling_strain = 0.01 * 2.0;
nlohmann::json swelling_block(const std::vector<double>& min, const std::vector<double>& max) {
  nlohmann::json j;
  j["dimension"] = 2;
  j["plugin_paths"] = {std::string(SUFFUSE_TEST_PLUGIN_DIR) + "/swelling"};
  j["gravity"] = {0.0, 0.0};
  j["materials"]["clay"] = {{"type", "phase/test_swelling"}, {"density", 1000.0}, {"youngs_modulus", 1e6}, {"rate", 0.01}};
  j["bodies"] = {{{"material", "clay"}, {"min", min}, {"max", max}}};
  j["time"] = {{"end", 2.0}};
  return j;
}

// The fields the swelling tests read.
struct SwollenPoints {
  const double *x, *u, *s, *e;
  explicit SwollenPoints(const suffuse::PointSet& pts)
      : x(pts.data(pts.core().position)),
        u(pts.data(pts.core().displacement)),
        s(pts.data(pts.core().stress)),
        e(pts.data(pts.id("eigenstrain"))) {}
};

// The core applies an eigenstrain consistently: a free body (no supports, no
// gravity, damped) given a slowly growing in-plane eigenstrain eps* = rate t
// expands with it and stays free of stress.
TEST(Eigenstrain, FreeBodyFollowsItWithoutStress) {
  nlohmann::json j = swelling_block({-0.5, -0.5}, {0.5, 0.5});
  j["damping"] = 0.1;
  j["grid"] = {{"origin", {-1.0, -1.0}}, {"cell_size", {0.1, 0.1}}, {"cells", {20, 20}}};
  j["shape_function"] = {{"type", "shape/gimp"}};
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});
  const auto& pts = sim.points();
  const SwollenPoints f(pts);
  const double strain = swelling_strain;
  double worst_u = 0, worst_s = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    for (int i = 0; i < 2; ++i) {
      const double x0 = f.x[2 * p + i] - f.u[2 * p + i];  // the body is centred on the origin
      worst_u = std::max(worst_u, std::abs(f.u[2 * p + i] - strain * x0));
    }
    for (int c = 0; c < 6; ++c) worst_s = std::max(worst_s, std::abs(f.s[p * 6 + c]));
    EXPECT_NEAR(f.e[p * 6 + 0], strain, 1e-12);
    EXPECT_NEAR(f.e[p * 6 + 1], strain, 1e-12);
    EXPECT_EQ(f.e[p * 6 + 2], 0.0);
  }
  RecordProperty("worst_displacement_error", sci(worst_u / (0.5 * strain)));
  RecordProperty("worst_stress", sci(worst_s / (1e6 * strain)));
  EXPECT_LT(worst_u, 0.02 * 0.5 * strain) << "2% of the edge displacement";
  EXPECT_LT(worst_s, 0.02 * 1e6 * strain) << "2% of the stress the eigenstrain would cause if held";
}

// The same eigenstrain in quasi-static steps: imposed once per step, before
// the Newton iterations (not once per iteration), so the body, held only
// against rigid motion (rollers on its left and bottom faces), ends at
// eps* = rate t exactly, stress free, displaced by eps* x (within 2%).
TEST(Eigenstrain, QuasiStaticStepsImposeItOncePerStep) {
  nlohmann::json j = swelling_block({0.0, 0.0}, {1.0, 1.0});
  j["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.1, 0.1}}, {"cells", {12, 12}}};
  j["shape_function"] = {{"type", "shape/linear"}};
  j["boundary_conditions"] = {{{"type", "bc/velocity"}, {"face", "left"}, {"vx", 0.0}},
                              {{"type", "bc/velocity"}, {"face", "bottom"}, {"vy", 0.0}}};
  j["time"].update({{"integration", "quasi_static"}, {"dt", 0.25}, {"max_dt", 0.25}});
  suffuse::Registry registry;
  const suffuse::Scene scene = scene_from(j, registry);
  suffuse::Simulation sim(scene, registry);
  sim.run({});
  ASSERT_NEAR(sim.time(), 2.0, 1e-12);
  const auto& pts = sim.points();
  const SwollenPoints f(pts);
  const double strain = swelling_strain;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    EXPECT_NEAR(f.e[p * 6 + 0], strain, 1e-12) << "point " << p;
    EXPECT_NEAR(f.e[p * 6 + 1], strain, 1e-12);
    // 2%, as above: the steps' strains are taken on the moving body (0.9% here)
    for (int i = 0; i < 2; ++i) {
      const double x0 = f.x[2 * p + i] - f.u[2 * p + i];
      EXPECT_NEAR(f.u[2 * p + i], strain * x0, 0.02 * strain * x0 + 1e-12);
    }
    for (int c = 0; c < 6; ++c) EXPECT_NEAR(f.s[p * 6 + c], 0.0, 1e-6 * 1e6 * strain);
  }
}

}  // namespace
