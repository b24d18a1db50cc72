// Saturated soil (two-phase single-point MPM) against analytical solutions.
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

// Terzaghi's series, z measured down from the drained top.
double terzaghi_pressure(double u0, double z, double H, double Tv) {
  double u = 0;
  for (int m = 0; m < 200; ++m) {
    const double M = (2 * m + 1) * std::numbers::pi / 2;
    u += 2 * u0 / M * std::sin(M * z / H) * std::exp(-M * M * Tv);
  }
  return u;
}

double terzaghi_degree(double Tv) {
  double s = 0;
  for (int m = 0; m < 200; ++m) {
    const double M = (2 * m + 1) * std::numbers::pi / 2;
    s += 2 / (M * M) * std::exp(-M * M * Tv);
  }
  return 1 - s;
}

std::string text(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

// share/scenes/terzaghi.json: isochrones within 0.03 u_0 everywhere along the
// column and degree of consolidation within 0.03 at T_v = 0.05, 0.2, 0.5, 1.
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
  for (const double Tv : {0.05, 0.2, 0.5, 1.0}) {
    const double t = Tv * H * H / cv;
    while (sim.time() < t - 0.5 * sim.dt()) sim.step();
    const double* x = pts.data(pts.core().position);
    const double* u = pts.data(pts.core().displacement);
    const double* p = pts.data(pressure);
    double worst = 0, mean = 0;
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double z = H - (x[2 * i + 1] - u[2 * i + 1]);  // initial depth below the drained top
      worst = std::max(worst, std::abs(p[i] - terzaghi_pressure(u0, z, H, Tv)) / u0);
      mean += p[i] / static_cast<double>(pts.size());
    }
    const double degree = 1 - mean / u0;
    EXPECT_LT(worst, 0.03) << "T_v = " << Tv << ": largest isochrone error / u_0";
    EXPECT_NEAR(degree, terzaghi_degree(Tv), 0.03) << "T_v = " << Tv;
    RecordProperty("isochrone_error_Tv_" + text(Tv), text(worst));
    RecordProperty("degree_error_Tv_" + text(Tv), text(std::abs(degree - terzaghi_degree(Tv))));
  }
}

// Invalid saturated scenes are caught before anything is built.
TEST(TwoPhase, SaturatedSceneValidation) {
  auto j = read_json(source_dir() / "share/scenes/terzaghi.json");
  j["materials"]["soil"].erase("permeability");
  j["bodies"][0].erase("porosity");
  j["bodies"].push_back({{"material", "soil"}, {"min", {0.0, 0.0}}, {"max", {0.02, 0.1}}});
  suffuse::Registry registry;
  try {
    scene_from(j, registry);
    FAIL() << "accepted";
  } catch (const suffuse::SceneError& e) {
    std::vector<std::string> pointers;
    for (const auto& d : e.diagnostics()) pointers.push_back(d.pointer);
    EXPECT_EQ(pointers, (std::vector<std::string>{"/bodies/0/porosity", "/materials/soil/permeability",
                                                  "/bodies/1/liquid"}))
        << e.what();
  }
}

}  // namespace
