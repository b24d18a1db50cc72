// Quasi-static integration (docs/time-integration.md) against the closed
// forms of consolidation and steady seepage, and against explicit runs.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <sstream>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace {

using suffuse::test::read_json;
using suffuse::test::scene_from;
using suffuse::test::source_dir;

std::string text(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

// Terzaghi's series, z measured down from the drained top.
double terzaghi_pressure(double u0, double z, double H, double Tv) {
  double u = 0;
  for (int m = 0; m < 200; ++m) {
    const double M = (2 * m + 1) * std::numbers::pi / 2;
    if (M * M * Tv > 50) break;
    u += 2 * u0 / M * std::sin(M * z / H) * std::exp(-M * M * Tv);
  }
  return u;
}

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

// share/scenes/terzaghi.json with steps 175 times the explicit one (whose
// stable step the liquid's bulk modulus sets): isochrones within 0.02 u_0 of
// the series at T_v = 0.05, 0.2, 0.5 and 1; the total stress equals the load.
TEST(QuasiStatic, TerzaghiIsochrones) {
  const auto explicit_scene = read_json(source_dir() / "share/scenes/terzaghi.json");
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
    for (std::size_t i = 0; i < pts.size(); ++i) {
      const double z = H - (x[2 * i + 1] - u[2 * i + 1]);
      isochrone = std::max(isochrone, std::abs(p[i] - terzaghi_pressure(u0, z, H, tv)) / u0);
      total = std::max(total, std::abs((sig[6 * i + 1] - p[i]) / -s - 1));
    }
    EXPECT_LT(isochrone, 0.02) << "T_v = " << Tv;
    EXPECT_LT(total, 1e-6) << "T_v = " << Tv << ": total vertical stress / load - 1";
    RecordProperty("isochrone_error_Tv_" + text(Tv), text(isochrone));
    RecordProperty("total_stress_error_Tv_" + text(Tv), text(total));
  }
  RecordProperty("steps", text(static_cast<double>(sim.steps())));
  RecordProperty("step_over_explicit", text(dt / explicit_dt));
  EXPECT_LT(sim.mass_ledger().liquid_imbalance(), 1e-12);
}

}  // namespace
