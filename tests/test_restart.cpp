// Checkpoint and restart: a run restarted from a checkpoint ends bit for bit
// where the uninterrupted run ends, and its outputs continue instead of
// starting over; checkpoints of another scene, damaged ones and ones at or
// past the end time are refused with a message.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace fs = std::filesystem;
using suffuse::test::fresh_dir;

namespace {

using suffuse::test::slurp;

struct Case {
  const char* scene;
  double end;
  nlohmann::json extra_bc;  // merged into the first boundary condition (e.g. a reaction)
};

// Every point field, bit for bit.
void expect_same_points(const suffuse::PointSet& a, const suffuse::PointSet& b) {
  ASSERT_EQ(a.field_count(), b.field_count());
  ASSERT_EQ(a.size(), b.size());
  for (suffuse::FieldId f = 0; f < a.field_count(); ++f) {
    const auto va = a.values(f), vb = b.values(f);
    ASSERT_EQ(va.size(), vb.size());
    EXPECT_EQ(std::memcmp(va.data(), vb.data(), va.size() * sizeof(double)), 0) << "field " << a.info(f).name;
  }
}

class Restart : public ::testing::TestWithParam<Case> {
 protected:
  nlohmann::json scene_json() const {
    auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes" / (std::string(GetParam().scene) + ".json"));
    j["time"]["end"] = GetParam().end;
    j["outputs"] = {{{"type", "writer/vtk_particles"}, {"interval", GetParam().end / 10}},
                    {{"type", "writer/csv_probe"}, {"name", "all"}, {"fields", {"displacement"}},
                     {"box_min", {-1e3, -1e3}}, {"box_max", {1e3, 1e3}}}};
    if (!GetParam().extra_bc.is_null()) j["boundary_conditions"][0].update(GetParam().extra_bc);
    return j;
  }
};

// Run A goes to the end, with a checkpoint half-way; a copy of its output
// directory is taken right after that checkpoint. Run B restarts from the
// copy.
struct HalfwayRestart {
  std::unique_ptr<suffuse::Simulation> a, b;
  fs::path a_dir, b_dir;
  suffuse::RunSummary b_summary;
};

HalfwayRestart restart_halfway(const suffuse::Scene& scene, suffuse::Registry& registry, double end) {
  HalfwayRestart r{std::make_unique<suffuse::Simulation>(scene, registry, 1), nullptr,
                   fresh_dir("restart_" + scene.name + "_a"), fresh_dir("restart_" + scene.name + "_b"), {}};
  suffuse::RunOptions options;
  options.output_dir = r.a_dir;
  options.checkpoint_interval = end / 2;
  bool copied = false;
  double copied_at = 0, copied_dt = 0;
  options.on_step = [&](const suffuse::Progress& p) {
    if (copied || !fs::exists(r.a_dir / (scene.name + ".checkpoint"))) return;
    fs::copy(r.a_dir, r.b_dir, fs::copy_options::recursive);
    copied = true;
    copied_at = p.time;
    copied_dt = p.dt;
  };
  r.a->run(options);
  EXPECT_TRUE(copied);
  EXPECT_NEAR(copied_at, end / 2, copied_dt) << "the first checkpoint is half-way (by the step that passed it)";

  r.b = std::make_unique<suffuse::Simulation>(scene, registry, 1);
  suffuse::RunOptions resume;
  resume.output_dir = r.b_dir;
  resume.restart = r.b_dir / (scene.name + ".checkpoint");
  r.b_summary = r.b->run(resume);
  return r;
}

// B's points, its .pvd series, its ledger, reactions and probe must equal A's.
TEST_P(Restart, ContinuesBitForBitAndItsOutputsContinue) {
  const std::string name = GetParam().scene;
  suffuse::Registry registry;
  suffuse::Scene scene = suffuse::test::scene_from(scene_json(), registry);
  scene.name = name;
  const HalfwayRestart r = restart_halfway(scene, registry, GetParam().end);
  const suffuse::Simulation &a = *r.a, &b = *r.b;
  const fs::path &a_dir = r.a_dir, &b_dir = r.b_dir;
  const suffuse::RunSummary& summary = r.b_summary;
  EXPECT_LT(summary.steps, a.steps()) << "B stepped only the second half";
  EXPECT_EQ(b.steps(), a.steps());
  EXPECT_EQ(b.time(), a.time());
  expect_same_points(a.points(), b.points());
  for (const char* suffix : {".pvd", ".ledger.csv", ".reactions.csv", ".all.csv"}) {
    if (!fs::exists(a_dir / (name + suffix))) continue;
    EXPECT_EQ(slurp(b_dir / (name + suffix)), slurp(a_dir / (name + suffix))) << suffix;
  }
  EXPECT_EQ(slurp(b_dir / (name + "_000010.vtp")), slurp(a_dir / (name + "_000010.vtp"))) << "the last frame";
  EXPECT_FALSE(fs::exists(b_dir / (name + "_000011.vtp")));
  // 200 rows by default (a quasi-static run may have fewer steps than rows:
  // its file is then compared with run A's above only).
  if (a.steps() > 1000) {
    EXPECT_EQ(suffuse::test::read_csv(b_dir / (name + ".all.csv")).rows.size(), 201u) << "the probe's rows";
  }
  // The final checkpoint of both runs holds the same state.
  EXPECT_EQ(slurp(b_dir / (name + ".checkpoint")), slurp(a_dir / (name + ".checkpoint")));
}

INSTANTIATE_TEST_SUITE_P(Scenes, Restart,
                         ::testing::Values(
                             // erosion, transport, the ledger's open faces, pore-pressure boundaries
                             Case{"suffusion_column", 0.2, nullptr},
                             // a traction on the points, a recorded reaction, a saturated column
                             Case{"terzaghi", 0.05, {{"reaction", "base"}}},
                             // Mohr-Coulomb's plastic state, a velocity-driven footing
                             Case{"footing_mc", 0.1, nullptr},
                             // quasi-static steps: adaptive sizes, erosion and transport substeps
                             Case{"suffusion_column_1h", 30.0, nullptr}),
                         [](const auto& info) { return std::string(info.param.scene); });

// A finished run extended to a later end time is the run given that end
// from the start, bit for bit: its end's checkpoint holds the state before
// its last step, which was shortened to land on the old end.
class Extension : public ::testing::TestWithParam<Case> {};

double checkpoint_time(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::string magic, header;
  std::getline(in, magic);
  std::getline(in, header);
  return nlohmann::json::parse(header).at("time").get<double>();
}

TEST_P(Extension, IsBitForBitTheRunGivenTheLaterEndFromTheStart) {
  const std::string name = GetParam().scene;
  const double first_end = GetParam().end, later_end = 2 * GetParam().end;
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes" / (name + ".json"));
  j["outputs"] = {{{"type", "writer/vtk_particles"}, {"interval", first_end / 4}}};
  auto run = [&](double end, const fs::path& dir, const fs::path& restart) {
    j["time"]["end"] = end;
    suffuse::Registry registry;
    suffuse::Scene scene = suffuse::test::scene_from(j, registry);
    scene.name = name;
    auto sim = std::make_unique<suffuse::Simulation>(scene, registry, 1);
    suffuse::RunOptions options;
    options.output_dir = dir;
    options.restart = restart;
    sim->run(options);
    return sim;
  };
  const fs::path extended = fresh_dir("restart_" + name + "_extended"), whole = fresh_dir("restart_" + name + "_whole");
  run(first_end, extended, {});
  const fs::path checkpoint = extended / (name + ".checkpoint");
  ASSERT_LT(checkpoint_time(checkpoint), first_end) << "the premise: the first run's last step was shortened";
  EXPECT_FALSE(fs::exists(extended / (name + ".checkpoint.end")));
  const auto b = run(later_end, extended, checkpoint);
  const auto c = run(later_end, whole, {});
  EXPECT_EQ(b->steps(), c->steps());
  EXPECT_EQ(b->time(), c->time());
  expect_same_points(b->points(), c->points());
  EXPECT_EQ(slurp(extended / (name + ".checkpoint")), slurp(whole / (name + ".checkpoint")));
}

INSTANTIATE_TEST_SUITE_P(Scenes, Extension,
                         ::testing::Values(Case{"suffusion_column", 0.1, nullptr},     // eroding, explicit
                                           Case{"suffusion_column_1h", 13.7, nullptr}),  // quasi-static
                         [](const auto& info) { return std::string(info.param.scene); });

class RestartRefused : public ::testing::Test {
 protected:
  void SetUp() override {
    // One directory per test: ctest runs the tests of this fixture in parallel.
    dir_ = fresh_dir(std::string("restart_refused_") + ::testing::UnitTest::GetInstance()->current_test_info()->name());
    j_ = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
    j_["time"]["end"] = 0.05;
    j_["outputs"] = nlohmann::json::array();
    run_column(j_);
    checkpoint_ = dir_ / "column.checkpoint";
    ASSERT_TRUE(fs::exists(checkpoint_)) << "a checkpoint at the end by default";
  }
  // Runs scene `j` (named "column") into the test's directory, from `restart` if given.
  suffuse::RunSummary run_column(const nlohmann::json& j, const fs::path& restart = {}) {
    suffuse::Registry registry;
    suffuse::Scene scene = suffuse::test::scene_from(j, registry);
    scene.name = "column";
    suffuse::Simulation sim(scene, registry, 1);
    suffuse::RunOptions options;
    options.output_dir = dir_;
    options.restart = restart;
    return sim.run(options);
  }
  // The message of restarting scene `j` from `file`.
  std::string restart_error(const nlohmann::json& j, const fs::path& file) {
    try {
      run_column(j, file);
    } catch (const suffuse::Error& e) {
      return e.what();
    }
    return "";
  }
  fs::path dir_, checkpoint_;
  nlohmann::json j_;
};

TEST_F(RestartRefused, AnotherScene) {
  auto j = j_;
  j["time"]["end"] = 0.1;
  j["bodies"][0]["porosity"] = 0.35;
  EXPECT_NE(restart_error(j, checkpoint_).find("written by a run of another scene"), std::string::npos);
}

// The same scene written by another tool: keys in another order, whole
// numbers without a decimal point (as jq writes them). Not another scene.
nlohmann::ordered_json rewritten(const nlohmann::json& j) {
  if (j.is_object()) {
    nlohmann::ordered_json object = nlohmann::ordered_json::object();
    std::vector<std::string> keys;
    for (const auto& [key, value] : j.items()) keys.push_back(key);
    for (auto k = keys.rbegin(); k != keys.rend(); ++k) object[*k] = rewritten(j[*k]);
    return object;
  }
  if (j.is_array()) {
    nlohmann::ordered_json array = nlohmann::ordered_json::array();
    for (const auto& value : j) array.push_back(rewritten(value));
    return array;
  }
  if (j.is_number_float() && j.get<double>() == std::trunc(j.get<double>()) && std::abs(j.get<double>()) < 1e15)
    return static_cast<std::int64_t>(j.get<double>());
  return j;
}

TEST_F(RestartRefused, NotForTheSameSceneRewrittenByAnotherTool) {
  auto j = j_;
  j["time"]["end"] = 0.1;
  const nlohmann::ordered_json text = rewritten(j);
  ASSERT_NE(text.dump().find("\"density\":1000,"), std::string::npos) << "whole numbers written as integers";
  ASSERT_NE(text.dump().substr(0, 12), nlohmann::json(j).dump().substr(0, 12)) << "keys in another order";
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  suffuse::Scene scene = suffuse::parse_scene(text.dump(2), "test.json", suffuse::test::source_dir(), registry, loader);
  scene.name = "column";
  suffuse::Simulation sim(scene, registry, 1);
  suffuse::RunOptions options;
  options.output_dir = dir_;
  options.restart = checkpoint_;
  sim.run(options);
  EXPECT_NEAR(sim.time(), 0.1, 1e-12) << "continued to the later end";
}

TEST_F(RestartRefused, AtOrPastTheEndTime) {
  EXPECT_NE(restart_error(j_, checkpoint_).find("raise /time/end to extend the run"), std::string::npos);
}

TEST_F(RestartRefused, DamagedOrTruncatedOrNotACheckpoint) {
  auto j = j_;
  j["time"]["end"] = 0.1;
  std::string bytes = slurp(checkpoint_);
  const fs::path damaged = dir_ / "damaged.checkpoint", truncated = dir_ / "truncated.checkpoint",
                 other = dir_ / "other.checkpoint";
  bytes[bytes.size() / 2] ^= 0x10;
  std::ofstream(damaged, std::ios::binary) << bytes;
  std::ofstream(truncated, std::ios::binary) << bytes.substr(0, bytes.size() / 3);
  std::ofstream(other) << "{\"not\": \"a checkpoint\"}\n";
  EXPECT_NE(restart_error(j, damaged).find("checksum does not match"), std::string::npos);
  EXPECT_NE(restart_error(j, truncated).find("checksum does not match"), std::string::npos);
  EXPECT_NE(restart_error(j, other).find("not a suffuse checkpoint"), std::string::npos);
  EXPECT_NE(restart_error(j, dir_ / "missing.checkpoint").find("no such file"), std::string::npos);
}

// A dry scene with no outputs writes nothing else, so nothing has made its
// output directory when the checkpoint at the end is due (the run failed
// there, after its last step).
TEST(Checkpoint, WrittenWhereNothingElseIs) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  j["outputs"] = nlohmann::json::array();
  j["time"]["end"] = 1e-4;
  suffuse::Registry registry;
  suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  scene.name = "bar";
  suffuse::Simulation sim(scene, registry, 1);
  suffuse::RunOptions options;
  options.output_dir = fresh_dir("restart_no_outputs") / "nested";
  ASSERT_NO_THROW(sim.run(options));
  EXPECT_TRUE(fs::exists(options.output_dir / "bar.checkpoint"));
}

// A probe's followed point is the one it followed before the checkpoint,
// not picked again: points equally near the probe (here above and below it,
// at dyadic positions) may change places in the restarted run's pick by the
// round-off of position - displacement. Fifteen such ties in a consolidating
// column: before 0.15 at least one restarted probe followed the other point.
TEST(Checkpoint, KeepsEachProbesFollowedPoint) {
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/terzaghi.json");
  j["grid"]["cell_size"] = {0.125, 0.125};
  j["grid"]["cells"] = {1, 9};
  j["bodies"][0]["max"] = {0.125, 1.0};
  j["boundary_conditions"][3]["box_max"] = {0.125, 1.0};
  j["time"]["end"] = 0.02;
  j["outputs"] = nlohmann::json::array();
  for (int k = 1; k < 16; ++k)  // points at y = 0.03125 + 0.0625 i: a tie at each 0.0625 k
    j["outputs"].push_back({{"type", "writer/csv_probe"}, {"name", "tie" + std::to_string(k)},
                            {"fields", {"displacement"}}, {"at", {0.03125, 0.0625 * k}}});
  suffuse::Registry registry;
  suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  scene.name = "ties";
  const HalfwayRestart r = restart_halfway(scene, registry, 0.02);
  for (int k = 1; k < 16; ++k) {
    const std::string probe = "ties.tie" + std::to_string(k) + ".csv";
    EXPECT_EQ(slurp(r.b_dir / probe), slurp(r.a_dir / probe)) << probe;
  }
}

// Extending a finished run: a later end time alone is allowed, the ledger
// continues and still closes.
TEST_F(RestartRefused, ALaterEndTimeExtendsTheRun) {
  auto j = j_;
  j["time"]["end"] = 0.1;
  const suffuse::RunSummary s = run_column(j, checkpoint_);
  EXPECT_DOUBLE_EQ(s.simulated_time, 0.1);
  ASSERT_TRUE(s.ledger);
  EXPECT_LT(s.ledger->fines_imbalance(), 1e-12);
  EXPECT_LT(s.ledger->liquid_imbalance(), 1e-12);
  const auto ledger = suffuse::test::read_csv(dir_ / "column.ledger.csv");
  EXPECT_NEAR(ledger.rows.back()[ledger.column("time")], 0.1, 1e-12);
}

}  // namespace
