// Element tests (suffuse element): one point of a phase driven along a path.
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>
#include <suffuse/element_test.hpp>
#include <suffuse/error.hpp>
#include <vector>

#include "test_support.hpp"

namespace {

std::vector<std::vector<std::string>> rows_of(const std::string& csv) {
  std::vector<std::vector<std::string>> rows;
  std::stringstream in(csv);
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

std::size_t column(const std::vector<std::string>& header, const std::string& name) {
  for (std::size_t k = 0; k < header.size(); ++k)
    if (header[k] == name) return k;
  ADD_FAILURE() << "no column " << name;
  return 0;
}

// The example scene: isotropic compression of normally consolidated clay,
// then undrained triaxial compression to the critical state.
TEST(ElementTest, ExampleScenesFollowTheClosedForms) {
  const auto file = suffuse::test::source_dir() / "share/scenes/triaxial_mcc.json";
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::ElementScene scene = suffuse::load_element_scene(file, registry, loader);
  std::ostringstream out;
  EXPECT_EQ(suffuse::run_element_test(scene, 0, registry, out).increments, 3200);
  const auto rows = rows_of(out.str());
  ASSERT_EQ(rows.size(), 3202u) << "a header, the initial state and a row per increment";
  const auto& h = rows[0];
  const std::size_t p = column(h, "p [Pa]"), q = column(h, "q [Pa]"), e = column(h, "void_ratio [-]");
  const std::size_t ev = column(h, "eps_v [-]");
  // Isotropic stage: on the NCL, e = N - 1 - lambda ln(p'/1 kPa).
  const auto& iso = rows[201];
  EXPECT_NEAR(std::stod(iso[e]), 3.0 - 1 - 0.2 * std::log(std::stod(iso[p]) / 1e3), 1e-3);
  EXPECT_NEAR(std::stod(iso[ev]), 0.0693, 1e-12);
  // Undrained stage: the volume stays, the path ends at the critical state.
  const double p0 = std::stod(iso[p]), Lambda = 0.75;
  const auto& end = rows.back();
  EXPECT_EQ(end[e], iso[e]);
  EXPECT_NEAR(std::stod(end[p]) / (p0 * std::pow(2.0, -Lambda)), 1.0, 1e-4);
  EXPECT_NEAR(std::stod(end[q]) / std::stod(end[p]), 1.0, 1e-4);
  EXPECT_EQ(h[column(h, "preconsolidation_pressure [Pa]")], "preconsolidation_pressure [Pa]") << "units in the header";
}

// A drained triaxial compression of Mohr-Coulomb sand reaches its closed-form
// failure stress through the driver's lateral-stress control.
TEST(ElementTest, DrainedTriaxialHoldsTheCellPressure) {
  const nlohmann::json j = {
      {"description", "Mohr-Coulomb drained triaxial compression"},
      {"material",
       {{"type", "phase/mohr_coulomb"}, {"density", 2000.0}, {"youngs_modulus", 2e7}, {"friction_angle", 30.0},
        {"cohesion", 0.0}}},
      {"initial_pressure", 100e3},
      {"path", {{{"type", "drained_triaxial"}, {"strain", 0.02}, {"increments", 200}}}}};
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const auto scene = suffuse::parse_element_scene(j.dump(), "mc.json", ".", registry, loader);
  std::ostringstream out;
  suffuse::run_element_test(scene, 0, registry, out);
  const auto rows = rows_of(out.str());
  const double p = std::stod(rows.back()[column(rows[0], "p [Pa]")]);
  const double q = std::stod(rows.back()[column(rows[0], "q [Pa]")]);
  // sigma_1 = 3 sigma_3 at phi = 30 deg: q = 200 kPa, p' = 166.7 kPa.
  EXPECT_NEAR(q, 200e3, 1e-6 * 200e3);
  EXPECT_NEAR(p, 500e3 / 3, 1e-6 * 500e3 / 3);
}

// Runs an element scene given as JSON; the CSV rows (header first).
std::vector<std::vector<std::string>> run_scene(const nlohmann::json& j) {
  return rows_of(suffuse::test::element_csv(j));
}

double value(const std::vector<std::vector<std::string>>& rows, std::size_t row, const std::string& name) {
  return std::stod(rows[row][column(rows[0], name)]);
}

// A hold at constant p' and q while the eroded fraction grows: the
// softening skeleton of the coupled-phase template (E = E_0 (1 - a f_er))
// strains by its eigenstrain to carry the same stress, so its strains are the
// secant compliance's: eps_v = p'/K(f) - p'/K_0, eps_s = q/(3G(f)) - q/(3G_0).
TEST(ElementTest, HoldAtConstantStressWhileTheInputsChange) {
  const double E0 = 1e7, nu = 0.25, a = 5, p = 100e3, q = 60e3;
  const nlohmann::json j = {
      {"plugin_paths", {std::string(SUFFUSE_TEST_PLUGIN_DIR) + "/eroding_elastic"}},
      {"material",
       {{"type", "phase/eroding_elastic"}, {"density", 2000.0}, {"youngs_modulus", E0}, {"poisson_ratio", nu},
        {"softening", a}}},
      {"initial_pressure", p},
      {"path",
       {{{"type", "stress_controlled"}, {"q", q}, {"increments", 20}},
        {{"type", "stress_controlled"}, {"inputs", {{"eroded_fraction", 0.1}}}, {"increments", 50}}}}};
  const auto rows = run_scene(j);
  ASSERT_EQ(rows.size(), 72u);
  auto K = [&](double f) { return E0 * (1 - a * f) / (3 * (1 - 2 * nu)); };
  auto G = [&](double f) { return E0 * (1 - a * f) / (2 * (1 + nu)); };
  // Loading to q at constant p': elastic, eps_s = q / 3G.
  EXPECT_NEAR(value(rows, 21, "eps_s [-]"), q / (3 * G(0)), 1e-12);
  EXPECT_NEAR(value(rows, 21, "eps_v [-]"), 0.0, 1e-12);
  for (std::size_t r = 22; r < rows.size(); ++r) {
    const double f = value(rows, r, "eroded_fraction [-]");
    EXPECT_NEAR(f, 0.1 * static_cast<double>(r - 21) / 50, 1e-15) << "the input ramps linearly";
    EXPECT_NEAR(value(rows, r, "p [Pa]"), p, 1e-9 * p) << "held, row " << r;
    EXPECT_NEAR(value(rows, r, "q [Pa]"), q, 1e-9 * p) << "held, row " << r;
    EXPECT_NEAR(value(rows, r, "eps_v [-]"), p / K(f) - p / K(0), 1e-9 * p / K(f)) << "row " << r;
    EXPECT_NEAR(value(rows, r, "eps_s [-]"), q / (3 * G(f)), 1e-9 * q / G(f)) << "row " << r;
  }
}

// A phase that swells in x and y (an eigenstrain rate, nu = 0) held at its
// initial stress strains by exactly its eigenstrain, z not at all: the three
// normal strains are solved for independently.
TEST(ElementTest, HoldFollowsAnEigenstrain) {
  const double rate = 1e-4;
  const nlohmann::json j = {
      {"plugin_paths", {std::string(SUFFUSE_TEST_PLUGIN_DIR) + "/swelling"}},
      {"material", {{"type", "phase/test_swelling"}, {"density", 1000.0}, {"youngs_modulus", 1e6}, {"rate", rate}}},
      {"initial_pressure", 10e3},
      {"path", {{{"type", "stress_controlled"}, {"increments", 30}}}}};
  const auto rows = run_scene(j);
  ASSERT_EQ(rows.size(), 32u);
  // Increments of 1 s: eps_xx = eps_yy = 30 rate, eps_zz = 0 (tension positive).
  EXPECT_NEAR(value(rows, 31, "eps_v [-]"), -60 * rate, 1e-12);
  EXPECT_NEAR(value(rows, 31, "p [Pa]"), 10e3, 1e-6);
  EXPECT_NEAR(value(rows, 31, "q [Pa]"), 0.0, 1e-6);
  // eps_s = sqrt(2/3 e:e) of the deviator of (a, a, 0): 2a/3.
  EXPECT_NEAR(value(rows, 31, "eps_s [-]"), 2 * 30 * rate / 3, 1e-12);
}

// A stress-controlled drained path of normally consolidated Modified
// Cam-Clay (dp' = dq/3) against the closed form of its void ratio,
// e = e_0 - lambda ln(p'/p'_0) - (lambda - kappa) ln(1 + eta^2/M^2), and the
// strain the driver sums against the logarithmic one, ln(v_0 / v).
TEST(ElementTest, StressControlledPathOfCamClayFollowsTheClosedForm) {
  const double p0 = 100e3, lambda = 0.2, kappa = 0.05, M = 1.0, N = 3.0;
  const nlohmann::json j = {
      {"material",
       {{"type", "phase/modified_cam_clay"}, {"density", 2700.0}, {"lambda", lambda}, {"kappa", kappa},
        {"critical_state_ratio", M}, {"N", N}, {"poisson_ratio", 0.3}}},
      {"initial_pressure", p0},
      {"path", {{{"type", "stress_controlled"}, {"p", p0 + 60e3 / 3}, {"q", 60e3}, {"increments", 400}}}}};
  const auto rows = run_scene(j);
  ASSERT_EQ(rows.size(), 402u);
  const double e0 = N - 1 - lambda * std::log(p0 / 1e3);
  EXPECT_NEAR(value(rows, 1, "void_ratio [-]"), e0, 1e-12);
  for (std::size_t r = 41; r < rows.size(); r += 40) {
    const double p = value(rows, r, "p [Pa]"), q = value(rows, r, "q [Pa]"), eta = q / p;
    EXPECT_NEAR(q, 60e3 * static_cast<double>(r - 1) / 400, 1e-9 * p0);
    EXPECT_NEAR(p, p0 + q / 3, 1e-9 * p0);
    const double e = value(rows, r, "void_ratio [-]");
    EXPECT_NEAR(e, e0 - lambda * std::log(p / p0) - (lambda - kappa) * std::log(1 + eta * eta / (M * M)), 1e-5)
        << "row " << r;
    EXPECT_NEAR(value(rows, r, "eps_v [-]"), std::log((1 + e0) / (1 + e)), 1e-9) << "row " << r;
  }
}

// A stress beyond the Mohr-Coulomb envelope cannot be held: the driver says
// "failure" with the stage and the increment, and the rows so far are kept.
TEST(ElementTest, StressBeyondFailureIsReportedAsFailure) {
  const nlohmann::json j = {
      {"material",
       {{"type", "phase/mohr_coulomb"}, {"density", 2000.0}, {"youngs_modulus", 2e7}, {"friction_angle", 30.0},
        {"cohesion", 0.0}}},
      {"initial_pressure", 100e3},
      // Failure at constant p' = 100 kPa: q_f = 6 sin(phi) / (3 - sin(phi)) p' = 120 kPa.
      {"path", {{{"type", "stress_controlled"}, {"q", 200e3}, {"increments", 10}}}}};
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const auto scene = suffuse::parse_element_scene(j.dump(), "mc.json", ".", registry, loader);
  std::ostringstream out;
  try {
    suffuse::run_element_test(scene, 0, registry, out);
    ADD_FAILURE() << "held a stress beyond failure";
  } catch (const suffuse::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("path stage 0 (stress_controlled), increment 7 of 10: failure"), std::string::npos) << what;
  }
  const auto rows = rows_of(out.str());
  ASSERT_EQ(rows.size(), 8u) << "header, initial state, six increments up to q = 120 kPa";
  EXPECT_NEAR(value(rows, 7, "q [Pa]"), 120e3, 1e-6);
}

// Bad element scenes are refused with the JSON path.
TEST(ElementTest, BadScenesAreRefusedWithTheirPath) {
  const nlohmann::json good = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/triaxial_mcc.json");
  auto expect_error = [](const nlohmann::json& j, const std::string& pointer) {
    suffuse::Registry registry;
    suffuse::PluginLoader loader(registry);
    try {
      suffuse::parse_element_scene(j.dump(), "bad.json", ".", registry, loader);
      ADD_FAILURE() << "accepted " << j.dump();
    } catch (const suffuse::SceneError& e) {
      EXPECT_NE(std::string(e.what()).find(pointer), std::string::npos) << e.what();
    }
  };
  auto j = good;
  j["path"][1]["type"] = "consolidated_drained";
  expect_error(j, "/path/1/type");
  j = good;
  j.erase("material");
  expect_error(j, "/material");
  j = good;
  j["path"] = nlohmann::json::array();
  expect_error(j, "/path");
  j = good;
  j["initial_pressure"] = -1.0;
  expect_error(j, "/initial_pressure");
  j = good;
  j["path"][1]["inputs"] = {{"eroded_fraction", 0.1}};
  expect_error(j, "/path/1/inputs/eroded_fraction");  // Modified Cam-Clay reads no eroded fraction
  j = good;
  j["path"][1] = {{"type", "stress_controlled"}, {"strain", 0.1}};
  expect_error(j, "/path/1/strain");
  j = good;
  j["path"][1]["q"] = 1e3;
  expect_error(j, "/path/1/q");
  j = good;
  j["path"][1].erase("strain");
  expect_error(j, "/path/1/strain");
  j = good;
  j["path"][1]["increments"] = 0;
  expect_error(j, "/path/1/increments");
  j = good;
  j["path"][1]["until"] = {{"eta", -0.3}};
  expect_error(j, "/path/1/until/eta");  // the CSV's eta is a magnitude
  j = good;
  j["path"][1]["until"] = {{"stress_ratio_of_the_moon", 1.0}};
  expect_error(j, "/path/1/until/stress_ratio_of_the_moon");
  // A wrapping phase: its base is required and cannot wrap in turn.
  const nlohmann::json suffosion = {{"type", "phase/suffosion"}};
  j = good;
  j["material"] = suffosion;
  expect_error(j, "/material/base");
  j["material"]["base"] = suffosion;
  expect_error(j, "/material/base/type");
  j["material"]["base"] = good["material"];
  j["path"][1]["inputs"] = {{"eroded_fraction", 1.0}};
  expect_error(j, "/path/1/inputs/eroded_fraction");
  // Cases: named, uniquely.
  j = good;
  j["cases"] = {{{"name", "a"}, {"path", good["path"]}}, {{"name", "a"}, {"path", good["path"]}}};
  expect_error(j, "/cases/1/name");
}

}  // namespace
