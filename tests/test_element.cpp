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
  EXPECT_EQ(suffuse::run_element_test(scene, registry, out), 3200);
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
  suffuse::run_element_test(scene, registry, out);
  const auto rows = rows_of(out.str());
  const double p = std::stod(rows.back()[column(rows[0], "p [Pa]")]);
  const double q = std::stod(rows.back()[column(rows[0], "q [Pa]")]);
  // sigma_1 = 3 sigma_3 at phi = 30 deg: q = 200 kPa, p' = 166.7 kPa.
  EXPECT_NEAR(q, 200e3, 1e-6 * 200e3);
  EXPECT_NEAR(p, 500e3 / 3, 1e-6 * 500e3 / 3);
}

// Bad element scenes are refused with the JSON path; a phase that writes an
// eigenstrain is refused at the start, naming the material.
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
  j["material"]["type"] = "phase/test_swelling";
  j["material"] = {{"type", "phase/test_swelling"}, {"density", 1000.0}, {"youngs_modulus", 1e6}, {"rate", 0.1}};
  j["plugin_paths"] = {std::string(SUFFUSE_TEST_PLUGIN_DIR) + "/swelling"};
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const auto scene = suffuse::parse_element_scene(j.dump(), "swelling.json", ".", registry, loader);
  std::ostringstream out;
  try {
    suffuse::run_element_test(scene, registry, out);
    ADD_FAILURE() << "ran an eigenstrain phase";
  } catch (const suffuse::Error& e) {
    EXPECT_NE(std::string(e.what()).find("/material"), std::string::npos) << e.what();
  }
}

}  // namespace
