// writer/csv_probe: each kind of probe against the run's own state, computed
// independently here, and the face probes against the mass ledger and the
// closed form of steady upward seepage.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace fs = std::filesystem;
using suffuse::test::read_csv;

namespace {

fs::path run_scene(const nlohmann::json& j, const std::string& name, std::unique_ptr<suffuse::Simulation>& sim,
                   suffuse::Registry& registry) {
  const fs::path dir = fs::temp_directory_path() / ("suffuse_probes_" + name);
  fs::remove_all(dir);
  suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  scene.name = name;
  sim = std::make_unique<suffuse::Simulation>(scene, registry, 1);
  suffuse::RunOptions options;
  options.output_dir = dir;
  sim->run(options);
  return dir;
}

}  // namespace

// The suffusion column after 0.5 s: a followed point, box reductions and the
// fines that left through the top.
TEST(Probes, PointBoxAndLedgerFaceOnTheSuffusionColumn) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  j["time"]["end"] = 0.5;
  j["outputs"] = {
      {{"type", "writer/csv_probe"}, {"name", "surface"}, {"fields", {"displacement", "pore_pressure"}},
       {"at", {0.021, 0.4}}},
      {{"type", "writer/csv_probe"}, {"name", "base_mean"}, {"fields", {"porosity", "fines_content"}},
       {"box_min", {0.0, 0.0}}, {"box_max", {0.04, 0.1}}},
      {{"type", "writer/csv_probe"}, {"name", "base_fines"}, {"fields", {"suspended_fines"}},
       {"box_min", {0.0, 0.0}}, {"box_max", {0.04, 0.1}}, {"reduce", "sum"}},
      {{"type", "writer/csv_probe"}, {"name", "base_max"}, {"fields", {"concentration"}},
       {"box_min", {0.0, 0.0}}, {"box_max", {0.04, 0.1}}, {"reduce", "max"}},
      {{"type", "writer/csv_probe"}, {"name", "out"}, {"fields", {"fines_discharged", "liquid_discharged"}},
       {"face", "top"}, {"interval", 0.01}}};
  suffuse::Registry registry;
  std::unique_ptr<suffuse::Simulation> sim;
  const fs::path dir = run_scene(j, "column", sim, registry);
  const suffuse::PointSet& pts = sim->points();
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  const double* V = pts.data(pts.core().volume);

  // The followed point: the one starting nearest (0.021, 0.4), i.e. a top point at x = 0.025.
  const auto surface = read_csv(dir / "column.surface.csv");
  ASSERT_EQ(surface.header.size(), 4u);
  EXPECT_EQ(surface.header[0], "time [s]");
  EXPECT_EQ(surface.header[1], "displacement_x [m]");
  EXPECT_EQ(surface.header[3], "pore_pressure [Pa]");
  ASSERT_EQ(surface.rows.size(), 201u) << "200 frames by default, and the initial state";
  std::size_t nearest = 0;
  double best = 1e300;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    const double d = std::hypot(x[2 * p] - u[2 * p] - 0.021, x[2 * p + 1] - u[2 * p + 1] - 0.4);
    if (d < best) best = d, nearest = p;
  }
  EXPECT_EQ(surface.rows.back()[2], u[2 * nearest + 1]);
  EXPECT_EQ(surface.rows.back()[3], pts.data(pts.id("pore_pressure"))[nearest]);
  EXPECT_EQ(surface.rows.front()[2], 0.0);

  // Box: points whose centre is in the lowest quarter now.
  double volume = 0, n_sum = 0, fc_sum = 0, suspended = 0, c_max = -1;
  const double* n = pts.data(pts.id("porosity"));
  const double* fc = pts.data(pts.id("fines_content"));
  const double* sf = pts.data(pts.id("suspended_fines"));
  const double* c = pts.data(pts.id("concentration"));
  for (std::size_t p = 0; p < pts.size(); ++p) {
    if (x[2 * p + 1] > 0.1) continue;
    volume += V[p];
    n_sum += n[p] * V[p];
    fc_sum += fc[p] * V[p];
    suspended += sf[p];
    c_max = std::max(c_max, c[p]);
  }
  const auto mean = read_csv(dir / "column.base_mean.csv");
  EXPECT_NEAR(mean.rows.back()[1], n_sum / volume, 1e-15);
  EXPECT_NEAR(mean.rows.back()[2], fc_sum / volume, 1e-15);
  EXPECT_NEAR(read_csv(dir / "column.base_fines.csv").rows.back()[1], suspended, 1e-15 * suspended);
  EXPECT_GT(suspended, 0) << "fines were eroded in the base";
  EXPECT_EQ(read_csv(dir / "column.base_max.csv").rows.back()[1], c_max);

  // Face: what left through the top, net, as the ledger books it.
  const suffuse::MassLedger ledger = sim->mass_ledger();
  const auto top = std::find_if(ledger.boundaries.begin(), ledger.boundaries.end(),
                                [](const suffuse::BoundaryDischarge& d) { return d.face == "top"; });
  ASSERT_NE(top, ledger.boundaries.end());
  const auto out = read_csv(dir / "column.out.csv");
  EXPECT_EQ(out.header[1], "fines_discharged [kg/m]") << "per metre of thickness in 2D";
  ASSERT_EQ(out.rows.size(), 51u);
  EXPECT_EQ(out.rows.back()[1], top->fines_out - top->fines_in);
  EXPECT_EQ(out.rows.back()[2], top->liquid_out - top->liquid_in);
  EXPECT_GT(out.rows.back()[2], 0);
  // Liquid leaves steadily: non-decreasing, to round-off (-6e-20 kg at the first step).
  for (std::size_t r = 1; r < out.rows.size(); ++r)
    EXPECT_GE(out.rows[r][2], out.rows[r - 1][2] - 1e-15 * out.rows.back()[2]) << "row " << r;
}

// Steady upward seepage (share/scenes/upward_seepage.json): the flow rate
// out through the base is -K i times its width, within 1% (the tolerance of
// the points' flux in TwoPhase.SteadyUpwardSeepage).
TEST(Probes, FlowRateThroughTheBase) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/upward_seepage.json");
  j["outputs"] = {{{"type", "writer/csv_probe"}, {"name", "base"}, {"fields", {"darcy_flux"}}, {"face", "bottom"}}};
  suffuse::Registry registry;
  std::unique_ptr<suffuse::Simulation> sim;
  const fs::path dir = run_scene(j, "seep", sim, registry);
  const auto base = read_csv(dir / "seep.base.csv");
  EXPECT_EQ(base.header[1], "flow_rate [m^2/s]");
  const double width = 0.02, q = 0.01 * 0.5;
  EXPECT_NEAR(base.rows.back()[1] / (-q * width), 1.0, 0.01);
}

// Quasi-static steady seepage up a column whose last cell (the top 2 cm)
// conducts five times better, drained at the top face (p = 0): both faces
// carry the series flow q = dh / (L1 / K1 + L2 / K2) times the width within
// 0.5%. The flux through a face whose pressure is prescribed is its nodes'
// pressure-equation residual; the mean of the points near the face, one
// cell deep and with the conductivity jumping there, was 6.1% off (40% at
// the top of the washed-out suffusion column).
TEST(Probes, QuasiStaticFlowRateThroughDrainedFaces) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/upward_seepage.json");
  j.erase("damping");
  j["time"] = {{"end", 1.0}, {"integration", "quasi_static"}, {"dt", 0.05}, {"max_dt", 0.2}};
  j["grid"]["cells"] = {1, 50};
  j["materials"]["top_sand"] = j["materials"]["sand"];
  j["materials"]["top_sand"]["permeability"]["hydraulic_conductivity"] = 0.05;
  j["bodies"][0]["max"] = {0.02, 0.98};
  nlohmann::json top = j["bodies"][0];
  top["name"] = "top_layer";
  top["material"] = "top_sand";
  top["min"] = {0.0, 0.98};
  top["max"] = {0.02, 1.0};
  j["bodies"].push_back(top);
  j["boundary_conditions"].push_back({{"type", "bc/pore_pressure"}, {"face", "top"}, {"pressure", 0.0}});
  j["outputs"] = {{{"type", "writer/csv_probe"}, {"name", "base"}, {"fields", {"darcy_flux"}}, {"face", "bottom"}},
                  {{"type", "writer/csv_probe"}, {"name", "top"}, {"fields", {"darcy_flux"}}, {"face", "top"}}};
  suffuse::Registry registry;
  std::unique_ptr<suffuse::Simulation> sim;
  const fs::path dir = run_scene(j, "drained", sim, registry);
  const double width = 0.02, q = 0.5 / (0.98 / 0.01 + 0.02 / 0.05);
  const double base = read_csv(dir / "drained.base.csv").rows.back()[1];
  const double top_rate = read_csv(dir / "drained.top.csv").rows.back()[1];
  EXPECT_NEAR(-base / (q * width), 1.0, 5e-3);
  EXPECT_NEAR(top_rate / (q * width), 1.0, 5e-3);
  RecordProperty("base_error", std::to_string(-base / (q * width) - 1));
  RecordProperty("top_error", std::to_string(top_rate / (q * width) - 1));
}

// Bad probes are refused at validation, naming the key.
TEST(Probes, BadProbesAreRefused) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  auto message = [&](const nlohmann::json& probe) {
    // An array of one node: `= {probe}` is the node itself with clang.
    j["outputs"] = nlohmann::json::array({probe});
    suffuse::Registry registry;
    try {
      suffuse::test::scene_from(j, registry);
    } catch (const std::exception& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  const nlohmann::json base = {{"type", "writer/csv_probe"}, {"name", "p"}, {"fields", {"porosity"}}};
  EXPECT_NE(message(base).find("no unique probe"), std::string::npos);
  auto both = base;
  both["at"] = {0.0, 0.0};
  both["face"] = "top";
  EXPECT_NE(message(both).find("no unique probe"), std::string::npos);
  auto corner = base;
  corner["box_min"] = {0.0, 0.0};
  EXPECT_NE(message(corner).find("/outputs/0/box_max"), std::string::npos);
  auto face = base;
  face["face"] = "top";
  EXPECT_NE(message(face).find("not a quantity of a face"), std::string::npos);
  auto missing = base;
  missing["at"] = {0.0, 0.0};
  missing["fields"] = {"plastic_strain"};
  EXPECT_NE(message(missing).find("reads point field 'plastic_strain'"), std::string::npos);
  auto name = base;
  name["at"] = {0.0, 0.0};
  name["name"] = "../x";
  EXPECT_NE(message(name).find("/outputs/0/name: not a file-name part"), std::string::npos) << message(name);
  j["outputs"] = {missing, missing};
  j["outputs"][0]["fields"] = {"porosity"};
  j["outputs"][1]["fields"] = {"porosity"};
  suffuse::Registry registry;
  try {
    suffuse::test::scene_from(j, registry);
    ADD_FAILURE() << "two outputs of one name";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("/outputs/1/name: duplicate output name"), std::string::npos) << e.what();
  }
}
