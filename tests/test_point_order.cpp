// Points sorted again into the grid's order when they mixed
// (/sort_points_at_spread, framework/src/mpm/point_order.hpp): a sort changes the
// points' numbers and the order of the sums, not the physics beyond
// round-off; what keeps point numbers (a loaded surface, a followed point, a
// restarted run) follows. Many processes: tests/test_parallel.cpp.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <suffuse/boundary_condition.hpp>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <suffuse/simulation.hpp>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The Mohr-Coulomb column collapse of share/scenes/column_collapse_mc.json
// at cells of 2.5 cm, 9 points per cell: 4,608 points in 3 scatter chunks
// of 2,048. Its points mix as the column spreads (sorted once, between 0.42
// and 0.48 s, at the default threshold).
json collapse(double end) {
  json j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/column_collapse_mc.json");
  j["grid"]["cell_size"] = {0.025, 0.025};
  j["grid"]["cells"] = {100, 36};
  j["bodies"][0]["points_per_cell"] = 3;
  j["time"]["end"] = end;
  j["outputs"] = json::array();
  return j;
}

struct Run {
  suffuse::Registry registry;
  std::unique_ptr<suffuse::Simulation> sim;
  fs::path dir;
};

std::unique_ptr<Run> run(const json& j, const std::string& name, const fs::path& restart = {}) {
  auto r = std::make_unique<Run>();
  r->dir = fs::temp_directory_path() / ("suffuse_point_order_" + name);
  if (restart.empty()) fs::remove_all(r->dir);
  suffuse::Scene scene = suffuse::test::scene_from(j, r->registry);
  scene.name = name;
  r->sim = std::make_unique<suffuse::Simulation>(scene, r->registry, 1);
  suffuse::RunOptions options;
  options.output_dir = r->dir;
  options.restart = restart;
  r->sim->run(options);
  return r;
}

using suffuse::test::slurp;

// Runs `j` to its end with a checkpoint at `checkpoint_at` seconds, copies
// the output directory once that checkpoint is written, restarts from the
// copy, and expects both runs to end with the same checkpoint, byte for
// byte. Returns the sorts of the whole run by the checkpoint and at its
// end, and those of the restarted run.
struct RestartSorts {
  std::size_t at_checkpoint = 99, whole = 0, restarted = 0;
};
RestartSorts expect_restart_ends_alike(const json& j, const std::string& name, double checkpoint_at) {
  const fs::path whole_dir = fs::temp_directory_path() / ("suffuse_point_order_" + name + "_whole"),
                 copy_dir = fs::temp_directory_path() / ("suffuse_point_order_" + name + "_restarted");
  fs::remove_all(whole_dir);
  fs::remove_all(copy_dir);
  suffuse::Registry registry;
  suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  scene.name = name;
  const fs::path checkpoint = name + ".checkpoint";
  suffuse::Simulation whole(scene, registry, 1);
  suffuse::RunOptions options;
  options.output_dir = whole_dir;
  options.checkpoint_interval = checkpoint_at;
  RestartSorts sorts;
  options.on_step = [&](const suffuse::Progress&) {
    if (sorts.at_checkpoint != 99 || !fs::exists(whole_dir / checkpoint)) return;
    fs::copy(whole_dir, copy_dir, fs::copy_options::recursive);
    sorts.at_checkpoint = whole.point_sorts();
  };
  whole.run(options);
  sorts.whole = whole.point_sorts();
  suffuse::Simulation rest(scene, registry, 1);
  suffuse::RunOptions resume;
  resume.output_dir = copy_dir;
  resume.restart = copy_dir / checkpoint;
  rest.run(resume);
  sorts.restarted = rest.point_sorts();
  EXPECT_EQ(rest.steps(), whole.steps());
  const std::string a = slurp(whole_dir / checkpoint), b = slurp(copy_dir / checkpoint);
  EXPECT_GT(a.size(), 10000u);
  EXPECT_TRUE(a == b) << name << ": the restarted run ends elsewhere";
  return sorts;
}

// Each point's number at the start (field "id"), checked to be a
// permutation of 0 .. n-1.
std::vector<std::size_t> start_numbers(const suffuse::PointSet& pts) {
  const double* id = pts.data(pts.id("id"));
  std::vector<std::size_t> number(pts.size()), seen(pts.size(), 0);
  for (std::size_t p = 0; p < pts.size(); ++p) {
    number[p] = static_cast<std::size_t>(id[p]);
    EXPECT_EQ(static_cast<double>(number[p]), id[p]);
    EXPECT_LT(number[p], pts.size());
    if (number[p] < pts.size()) ++seen[number[p]];
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), static_cast<std::ptrdiff_t>(pts.size())) << "ids lost or doubled";
  return number;
}

// The largest difference over every field of `a`'s points and those of `b`
// they are matched to (`b_of_a[p]`: the point of `b` that point p of `a`
// is), each over its field's largest magnitude in `b`; `b`'s fields only.
double largest_difference(const suffuse::PointSet& a, const suffuse::PointSet& b, const std::vector<std::size_t>& b_of_a,
                          std::string* field = nullptr) {
  EXPECT_EQ(a.size(), b.size());
  double worst = 0;
  for (suffuse::FieldId f = 0; f < b.field_count(); ++f) {
    const std::string& name = b.info(f).name;
    const auto m = static_cast<std::size_t>(b.components(f));
    const double* x = a.data(a.id(name));
    const double* y = b.data(f);
    double largest = 0, difference = 0;
    for (std::size_t p = 0; p < b.size(); ++p)
      for (std::size_t c = 0; c < m; ++c) {
        largest = std::max(largest, std::abs(y[b_of_a[p] * m + c]));
        difference = std::max(difference, std::abs(x[p * m + c] - y[b_of_a[p] * m + c]));
      }
    if (largest > 0 && difference / largest > worst) {
      worst = difference / largest;
      if (field) *field = name;
    }
  }
  return worst;
}

std::vector<std::size_t> same_numbers(std::size_t n) {
  std::vector<std::size_t> v(n);
  for (std::size_t p = 0; p < n; ++p) v[p] = p;
  return v;
}

}  // namespace

// Sorted at every step (a threshold below 1), the collapsing column's points
// are renumbered 123 times (to 0.025 s; to 0.05 s the test took 18 s
// sanitized); matched by id, every field ends as close to that of a run
// whose points keep their order as a run with gravity one ulp weaker
// (within 10 times: round-off of the sums' order, amplified by the plastic
// flow; measured 2.6e-5 and 3.2e-5 of the field's largest value).
TEST(PointOrder, SortingAtEveryStepChangesOnlyTheNumbers) {
  json fixed_scene = collapse(0.025);
  fixed_scene["sort_points_at_spread"] = 0;
  const auto fixed = run(fixed_scene, "fixed");
  EXPECT_EQ(fixed->sim->point_sorts(), 0u);
  EXPECT_FALSE(fixed->sim->points().find("id")) << "no sorting, no id";

  json sorted_scene = collapse(0.025);
  sorted_scene["sort_points_at_spread"] = 0.5;
  const auto sorted = run(sorted_scene, "every_step");
  EXPECT_EQ(sorted->sim->steps(), fixed->sim->steps());
  EXPECT_EQ(sorted->sim->point_sorts(), sorted->sim->steps());
  const std::vector<std::size_t> start = start_numbers(sorted->sim->points());
  std::size_t moved = 0;
  for (std::size_t p = 0; p < start.size(); ++p) moved += start[p] != p;
  EXPECT_GT(moved, start.size() / 2) << "the sort by cell reorders the bodies' rows of points";
  // The yardstick of round-off: gravity one ulp weaker, points unsorted.
  json nudged_scene = fixed_scene;
  nudged_scene["gravity"][1] = std::nextafter(-9.81, 0.0);
  const auto nudged = run(nudged_scene, "nudged");
  const double round_off = largest_difference(nudged->sim->points(), fixed->sim->points(), same_numbers(start.size()));
  std::string field;
  const double sorting = largest_difference(sorted->sim->points(), fixed->sim->points(), start, &field);
  EXPECT_GT(round_off, 0);
  EXPECT_LE(sorting, 10 * round_off) << field;
  EXPECT_LE(sorting, 1e-3) << field;
  EXPECT_NEAR(sorted->sim->total_mass(), fixed->sim->total_mass(), 1e-14 * fixed->sim->total_mass());
}

// The collapse sorts its points once they have mixed. At a threshold of
// 1.15 (the default 1.5 is reached between 0.42 and 0.48 s, which
// Parallel.SortedPointsMoveBetweenProcessesAndEqualSerial runs through) it
// does not by 0.15 s and sorts once by 0.25 s. A run restarted from a
// checkpoint at 0.15 s, before the sort, sorts where the whole run does:
// both end with the same checkpoint, byte for byte.
TEST(PointOrder, CollapseSortsOnceItsPointsMixAndARestartSortsAlike) {
  json j = collapse(0.25);
  j["sort_points_at_spread"] = 1.15;
  const RestartSorts sorts = expect_restart_ends_alike(j, "collapse", 0.15);
  EXPECT_EQ(sorts.at_checkpoint, 0u) << "the checkpoint at 0.15 s comes before the sort";
  EXPECT_EQ(sorts.whole, 1u);
  EXPECT_EQ(sorts.restarted, 1u);
}

// A surcharge on a column's top points (bc/traction keeps their numbers)
// and a followed point (writer/csv_probe "at") through a sort at every
// step: the column ends as the one whose points keep their numbers, and the
// probe follows the same point (1e-9: round-off of the sums' order).
TEST(PointOrder, LoadedAndFollowedPointsFollowTheSort) {
  json j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/bench_column.json");
  j["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.05, 0.05}}, {"cells", {24, 44}}};
  j["bodies"][0]["min"] = {0.0, 0.0};
  j["bodies"][0]["max"] = {1.0, 2.0};  // 3,200 points, 2 chunks
  j["time"]["end"] = 0.02;
  j["boundary_conditions"].push_back(
      {{"type", "bc/traction"}, {"box_min", {0.0, 2.0}}, {"box_max", {0.5, 2.0}}, {"traction", {0.0, -20000.0}}});
  j["outputs"] = {{{"type", "writer/csv_probe"}, {"name", "corner"}, {"fields", {"displacement", "stress"}},
                   {"at", {0.24, 1.96}}, {"interval", 0.002}}};
  j["sort_points_at_spread"] = 0;
  const auto fixed = run(j, "loaded_fixed");
  j["sort_points_at_spread"] = 0.5;
  const auto sorted = run(j, "loaded_sorted");
  EXPECT_EQ(sorted->sim->point_sorts(), sorted->sim->steps());
  j["sort_points_at_spread"] = 0;
  j["gravity"][1] = std::nextafter(-9.81, 0.0);
  const auto nudged = run(j, "loaded_nudged");
  const std::size_t n = fixed->sim->points().size();
  const double round_off = largest_difference(nudged->sim->points(), fixed->sim->points(), same_numbers(n));
  std::string field;
  const double sorting =
      largest_difference(sorted->sim->points(), fixed->sim->points(), start_numbers(sorted->sim->points()), &field);
  EXPECT_GT(round_off, 0);
  EXPECT_LE(sorting, 10 * round_off) << field;
  EXPECT_LE(sorting, 1e-3) << field;

  // The followed point's rows, each column over its largest magnitude.
  auto probe_difference = [](const suffuse::test::CsvTable& a, const suffuse::test::CsvTable& b) {
    EXPECT_EQ(a.rows.size(), b.rows.size());
    EXPECT_EQ(a.header, b.header);
    double worst = 0;
    for (std::size_t c = 0; c < a.header.size(); ++c) {
      double largest = 0, difference = 0;
      for (std::size_t r = 0; r < std::min(a.rows.size(), b.rows.size()); ++r) {
        largest = std::max(largest, std::abs(b.rows[r][c]));
        difference = std::max(difference, std::abs(a.rows[r][c] - b.rows[r][c]));
      }
      if (largest > 0) worst = std::max(worst, difference / largest);
    }
    return worst;
  };
  const auto probe = suffuse::test::read_csv(fixed->dir / "loaded_fixed.corner.csv");
  ASSERT_GT(probe.rows.size(), 10u);
  const double probe_round_off = probe_difference(suffuse::test::read_csv(nudged->dir / "loaded_nudged.corner.csv"), probe);
  const double probe_sorting = probe_difference(suffuse::test::read_csv(sorted->dir / "loaded_sorted.corner.csv"), probe);
  EXPECT_LE(probe_sorting, 10 * std::max(probe_round_off, 1e-15));
  EXPECT_LE(probe_sorting, 1e-3);
  EXPECT_LT(probe.at(probe.rows.size() - 1, "displacement_y"), -1e-5) << "the followed point settles";
}

namespace {

// A third-party condition that loads points and does not say it follows a
// renumbering (BoundaryCondition::follows_renumbering).
class PointLoadThatKeepsNumbers final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() { return {}; }
  explicit PointLoadThatKeepsNumbers(const suffuse::PluginArgs&) {}
  void setup(const suffuse::GridGeometry&) override {}
  bool loads_points() const override { return true; }
  std::vector<std::size_t> loaded_points() const override { return {0, 1}; }
};

}  // namespace

// Scenes that sort refuse such a condition before the first step, naming it
// and the setting that turns sorting off; with that setting it runs.
TEST(PointOrder, AConditionThatDoesNotFollowIsRefusedBeforeTheRun) {
  json j = collapse(0.001);
  j["boundary_conditions"].push_back({{"type", "bc/test_keeps_numbers"}});
  suffuse::Registry registry;
  registry.add<suffuse::BoundaryCondition, PointLoadThatKeepsNumbers>("bc/test_keeps_numbers", "a test condition");
  const suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  try {
    suffuse::Simulation sim(scene, registry, 1);
    FAIL() << "the condition should be refused";
  } catch (const suffuse::Error& e) {
    const std::string what = e.what();
    EXPECT_NE(what.find("/boundary_conditions/"), std::string::npos) << what;
    EXPECT_NE(what.find("bc/test_keeps_numbers"), std::string::npos) << what;
    EXPECT_NE(what.find("set /sort_points_at_spread to 0"), std::string::npos) << what;
  }
  j["sort_points_at_spread"] = 0;
  const suffuse::Scene fixed = suffuse::test::scene_from(j, registry);
  suffuse::Simulation sim(fixed, registry, 1);
  sim.step();
  EXPECT_EQ(sim.steps(), 1u);
}

// A run restarted from a checkpoint written after a sort: the surcharge of
// bc/traction (which named its points on the fresh lattice) acts on the
// same points as in the uninterrupted run. The collapse under a surcharge
// on the top of the column, at a threshold of 1.15, sorts once between
// 0.25 and 0.3 s and again by 0.35 s; restarted from the checkpoint at
// 0.3 s it ends with the whole run's checkpoint, byte for byte.
TEST(PointOrder, ARestartAfterASortLoadsTheSamePoints) {
  json j = collapse(0.35);
  j["sort_points_at_spread"] = 1.15;
  j["boundary_conditions"].push_back(
      {{"type", "bc/traction"}, {"box_min", {0.0, 0.8}}, {"box_max", {0.2, 0.8}}, {"traction", {0.0, -2000.0}}});
  const RestartSorts sorts = expect_restart_ends_alike(j, "loaded", 0.3);
  EXPECT_EQ(sorts.at_checkpoint, 1u) << "the checkpoint at 0.3 s comes after the first sort";
  EXPECT_EQ(sorts.whole, 2u);
  EXPECT_EQ(sorts.restarted, 1u);
}
