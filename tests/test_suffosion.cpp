// phase/suffosion: the DEM study's relations (seed 001; docs/suffosion.md)
// in element tests (share/scenes/suffosion_element.json) and in MPM.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <map>
#include <sstream>
#include <string>
#include <suffuse/element_test.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/simulation.hpp>
#include <vector>

#include "test_support.hpp"

namespace {

// The study's relations with its fitted values, written out independently
// of the plugin (docs/suffosion.md).
const double M_so = 0.71, f_so0 = 0.02, M_c = 0.86, A = 0.85, xi = 8, beta = 1.5;
double onset(double eta) { return eta < M_so ? f_so0 * std::sqrt(1 - eta * eta / (M_so * M_so)) : 0.0; }
double compaction_rate(double eta) { return A * (1 - std::pow(eta / M_c, xi)); }
double dilatancy(double eta) { return (M_c * M_c - eta * eta) / (beta * eta); }

struct Rows {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  double at(std::size_t r, const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k].substr(0, header[k].find(' ')) == name) return rows[r][k];
    throw std::logic_error("no column " + name);
  }
};

struct Case {
  Rows csv;
  suffuse::ElementResult result;
};

// Every case of the example scene, by name.
std::map<std::string, Case> run_example() {
  const auto file = suffuse::test::source_dir() / "share/scenes/suffosion_element.json";
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::ElementScene scene = suffuse::load_element_scene(file, registry, loader);
  std::map<std::string, Case> cases;
  for (std::size_t c = 0; c < scene.cases.size(); ++c) {
    std::ostringstream out;
    Case one;
    one.result = suffuse::run_element_test(scene, c, registry, out);
    std::stringstream in(out.str());
    std::string line;
    std::getline(in, line);
    for (std::stringstream h(line); std::getline(h, line, ',');) one.csv.header.push_back(line);
    while (std::getline(in, line)) {
      std::vector<double> row;
      for (std::stringstream r(line); std::getline(r, line, ',');) row.push_back(std::stod(line));
      one.csv.rows.push_back(row);
    }
    cases[scene.cases[c].name] = std::move(one);
  }
  return cases;
}

const std::map<std::string, Case>& example() {
  static const std::map<std::string, Case> cases = run_example();
  return cases;
}

// First row of the erosion stage (the last stage) and the first row where
// the erosion-induced strain is not zero.
std::size_t first_row_of_last_stage(const Rows& r) {
  const double last = r.rows.back()[1];
  std::size_t k = 0;
  while (r.rows[k][1] != last) ++k;
  return k;
}

// For eta = 0, 0.3, 0.55, 0.7 (the DEM study's range below M_so): the onset
// at f_so(eta) within 1e-6; after it, d eps_v / d f_er of the rate law and
// d eps_v / d eps_s = D within 1%; the void ratio of the identity to 1e-12.
TEST(Suffosion, ElementTestsFollowTheStudysRelations) {
  for (const double eta : {0.0, 0.3, 0.55, 0.7}) {
    std::ostringstream name;
    name << "eta_" << eta;
    const Rows& r = example().at(name.str()).csv;
    const std::size_t start = first_row_of_last_stage(r);
    EXPECT_NEAR(r.at(start, "eta"), eta, 1e-9) << "pre-sheared to eta";
    std::size_t first = start;
    while (first < r.rows.size() && r.at(first, "erosion_volumetric_strain") == 0) ++first;
    ASSERT_LT(first + 10, r.rows.size()) << name.str() << ": erosion never deformed the sample";
    const double rate = compaction_rate(eta);
    // The onset: extrapolated back from the first deformed row.
    const double f_onset = r.at(first, "eroded_fraction") - r.at(first, "erosion_volumetric_strain") / rate;
    EXPECT_NEAR(f_onset, onset(eta), 1e-6) << name.str();
    EXPECT_LE(r.at(first - 1, "eroded_fraction"), onset(eta)) << "no strain before the onset";
    // The rates, over the rest of the stage.
    const std::size_t a = first + 1, b = r.rows.size() - 1;
    const double df = r.at(b, "eroded_fraction") - r.at(a, "eroded_fraction");
    const double dv = r.at(b, "erosion_volumetric_strain") - r.at(a, "erosion_volumetric_strain");
    const double ds = r.at(b, "erosion_shear_strain") - r.at(a, "erosion_shear_strain");
    EXPECT_NEAR(dv / df, rate, 0.01 * rate) << name.str();
    if (eta > 0) EXPECT_NEAR(dv / ds, dilatancy(eta), 0.01 * dilatancy(eta)) << name.str();
    if (eta == 0) EXPECT_LT(std::abs(ds), 1e-12) << "purely volumetric at eta = 0 (q is held to round-off)";
    // The void-ratio identity at every row, with e_0 of the initial state.
    const double e0 = r.at(0, "void_ratio");
    double worst = 0;
    for (std::size_t k = 0; k < r.rows.size(); ++k) {
      const double f = r.at(k, "eroded_fraction"), ev = r.at(k, "eps_v");
      worst = std::max(worst, std::abs(r.at(k, "void_ratio") - ((1 + e0) * std::exp(-ev) / (1 - f) - 1)));
      // The study's first-order form differs by (1 + e_0) eps_v^2 / (2 (1 - f)) at most.
      const double study = (e0 + f) / (1 - f) - ev * (e0 + 1) / (1 - f);
      EXPECT_NEAR(r.at(k, "void_ratio"), study, (1 + e0) * ev * ev / (2 * (1 - f)) * 1.01 + 1e-12);
    }
    EXPECT_LT(worst, 1e-12) << name.str();
    std::printf("eta %.2f: onset %.8f (f_so %.8f), d eps_v/d f_er %.6f (law %.6f), D %.5f (law %.5f), identity %.1e\n",
                eta, f_onset, onset(eta), dv / df, rate, eta > 0 ? dv / ds : 0.0, eta > 0 ? dilatancy(eta) : 0.0,
                worst);
  }
}

// The study's trends: the onset falls as eta rises; eps_v grows with the
// eroded fraction below M_c and falls above it.
TEST(Suffosion, TrendsOfTheStudy) {
  double previous_onset = 1;
  for (const char* name : {"eta_0", "eta_0.3", "eta_0.55", "eta_0.7", "eta_0.91", "eta_0.93"}) {
    const Rows& r = example().at(name).csv;
    const double eta = r.at(r.rows.size() - 1, "eta");
    const double f_so = r.at(r.rows.size() - 1, "suffosion_onset");
    EXPECT_LT(f_so, previous_onset + (eta > M_so ? 1e-15 : 0.0)) << name;
    previous_onset = f_so;
    const double ev_end = r.at(r.rows.size() - 1, "erosion_volumetric_strain");
    if (eta < M_c)
      EXPECT_GT(ev_end, 0) << name << ": compaction below M_c";
    else
      EXPECT_LT(ev_end, 0) << name << ": dilation above M_c";
  }
}

// Runaway (the erosion-induced shear strain passes 10%): the element test
// reports the eroded fraction. The model's own closed form is
// f_so + 0.1 / (d eps_s / d f_er); the study reports 0.9% at eta = 0.93 and
// 1.38% at 0.91. At eta = 0 there is none up to 10%.
TEST(Suffosion, RunawayNearTheCriticalStressRatio) {
  EXPECT_TRUE(example().at("eta_0").result.events.empty()) << "no runaway at eta = 0";
  const std::map<double, double> study = {{0.91, 0.0138}, {0.93, 0.009}};
  for (const auto& [eta, reported] : study) {
    std::ostringstream name;
    name << "eta_" << eta;
    const auto& events = example().at(name.str()).result.events;
    ASSERT_EQ(events.size(), 1u) << name.str();
    double f = -1;
    for (const auto& [field, value] : events[0].at)
      if (field == "eroded_fraction") f = value;
    const double shear_rate = compaction_rate(eta) / dilatancy(eta);
    EXPECT_NEAR(f, onset(eta) + 0.1 / shear_rate, 2e-5) << name.str() << ": the model's closed form";
    // Within 30% of the study at 0.91; at 0.93 the relations fitted over all
    // eta give 35% more than the study's collapse (docs/suffosion.md).
    EXPECT_NEAR(f, reported, (eta < 0.92 ? 0.30 : 0.36) * reported) << name.str();
    std::printf("runaway at eta %.2f: f_er %.5f (study %.4f, %+.1f%%)\n", eta, f, reported, 100 * (f / reported - 1));
  }
}

}  // namespace
