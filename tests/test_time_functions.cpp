// Values in time (docs/boundaries.md): a time function is exact at its rows,
// linear between them and held outside; a hydrograph given as a CSV file in
// hours is the table in seconds; the head a face condition applies follows
// the table at every time, to round-off.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <suffuse/error.hpp>
#include <suffuse/grid_face.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <suffuse/time_function.hpp>

#include "test_support.hpp"

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// A flood's head: 1 m, rising over two days to 3.5 m, three days high, two
// days falling (seconds).
const std::vector<double> flood = {0, 1.0, 172800, 3.5, 432000, 3.5, 604800, 1.0};

double by_hand(double t) {  // the same hydrograph, interpolated here
  if (t <= 0) return 1.0;
  if (t < 172800) return 1.0 + 2.5 * t / 172800;
  if (t < 432000) return 3.5;
  if (t < 604800) return 3.5 - 2.5 * (t - 432000) / 172800;
  return 1.0;
}

// A saturated column 1 m wide, 4 m high, its top face's head given by `head`.
json column_with_head(const json& head) {
  json j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/terzaghi.json");
  j["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.5, 0.5}}, {"cells", {2, 8}}};
  j["bodies"][0]["max"] = {1.0, 4.0};
  j["boundary_conditions"] = {{{"type", "bc/velocity"}, {"face", "bottom"}, {"vx", 0.0}, {"vy", 0.0}},
                              {{"type", "bc/pore_pressure"}, {"face", "top"}, {"head", head}}};
  j["outputs"] = json::array();
  return j;
}

}  // namespace

TEST(TimeFunction, ExactAtItsRowsLinearBetweenHeldOutside) {
  const suffuse::TimeFunction f(flood);
  for (std::size_t k = 0; k < flood.size(); k += 2) EXPECT_EQ(f(flood[k]), flood[k + 1]) << "row " << k / 2;
  for (double t : {-10.0, 3600.0, 86400.0, 200000.0, 500000.0, 600000.0, 1e6}) EXPECT_NEAR(f(t), by_hand(t), 1e-14 * 3.5) << t;
  EXPECT_EQ(suffuse::TimeFunction(2.5)(123.0), 2.5);
  EXPECT_TRUE(suffuse::TimeFunction(2.5).constant());
  EXPECT_FALSE(f.constant());
  EXPECT_THROW(suffuse::TimeFunction(std::vector<double>{0, 1, 10, 2, 10, 3}), suffuse::Error);
}

// The hydrograph from a CSV file in hours (days in a second file) is the
// inline table in seconds, and the head bc/pore_pressure applies on the top
// face is gamma_w (h(t) - z) at every node, at the rows and between them.
TEST(TimeFunction, AHydrographFileInHoursOrDaysDrivesAFaceHead) {
  const fs::path dir = fs::temp_directory_path() / "suffuse_time_functions";
  fs::create_directories(dir);
  std::ofstream(dir / "flood_hours.csv") << "# two days rising, three high, two falling\n"
                                            "time [h], head [m]\n0, 1\n48, 3.5\n120, 3.5\n168, 1\n";
  std::ofstream(dir / "flood_days.csv") << "time [d], head [cm]\n0, 100\n2, 350\n5, 350\n7, 100\n";
  json inline_table = json::array();
  for (std::size_t k = 0; k < flood.size(); k += 2) inline_table.push_back({flood[k], flood[k + 1]});

  suffuse::Registry registry;
  const suffuse::Scene hours = suffuse::test::scene_from(column_with_head((dir / "flood_hours.csv").string()), registry);
  const suffuse::Scene days = suffuse::test::scene_from(column_with_head((dir / "flood_days.csv").string()), registry);
  const suffuse::Scene table = suffuse::test::scene_from(column_with_head(inline_table), registry);
  const auto& h = hours.boundary_conditions[1].params.vector("head");
  EXPECT_EQ(h, table.boundary_conditions[1].params.vector("head"));
  const auto& d = days.boundary_conditions[1].params.vector("head");
  ASSERT_EQ(d.size(), flood.size());
  for (std::size_t k = 0; k < d.size(); ++k) EXPECT_NEAR(d[k], flood[k], 1e-12 * std::abs(flood[k])) << k;

  const suffuse::GridGeometry grid(2, {0, 0, 0}, {0.5, 0.5, 1}, {2, 8, 1});
  auto bc = registry.create<suffuse::BoundaryCondition>(
      "bc/pore_pressure", {hours.boundary_conditions[1].params, 2, "/boundary_conditions/1"});
  bc->setup(grid);
  const suffuse::GridFace top{1, true};
  const auto nodes = suffuse::face_nodes(grid, top);
  for (double t : {0.0, 3600.0, 172800.0, 300000.0, 432000.0, 500000.0, 604800.0, 7e5}) {
    suffuse::NodeState state;
    state.resize(grid.node_count(), 2, true);
    bc->apply_forces(grid, state, t);
    for (std::int64_t I : nodes) {
      const double z = grid.node_position(I)[1];
      const double expected = -9810.0 * (by_hand(t) - z) * suffuse::face_node_area(grid, top, I);
      EXPECT_NEAR(state.liquid_force[2 * I + 1], expected, 1e-12 * std::abs(expected) + 1e-9) << "t = " << t;
    }
  }
}
