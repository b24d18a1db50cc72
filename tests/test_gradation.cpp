// Gradations and the internal-stability criteria: closed-form cases, the DEM
// study's gap-graded soil, and the exact errors of bad PSD input.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/gradation.hpp>
#include <suffuse/internal_stability.hpp>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using suffuse::test::fresh_dir;
using suffuse::Gradation;
using suffuse::Verdict;

const suffuse::CriterionResult& criterion(const suffuse::InternalStability& s, const std::string& id) {
  for (const auto& c : s.criteria)
    if (c.id == id) return c;
  throw std::logic_error("no criterion " + id);
}

// Relative tolerance of the closed-form cases: the criteria are exact for the
// log-linear curve, so only round-off separates them from the formulas.
constexpr double rel = 1e-6;
#define EXPECT_REL(actual, expected) EXPECT_NEAR(actual, expected, rel * std::abs(expected))

// A uniform sand: F rises linearly in log D from 0 at 0.2 mm to 1 at 0.8 mm
// (r = 4), so F(D) = log(D/0.2)/log 4 and D(F) = 0.2 r^F. Then
//   D'15/d'85 = D(F_s + 0.15 (1 - F_s)) / D(0.85 F_s) = r^0.15 at every split;
//   H = F(4D) - F(D) = 1 - F, so H/F = (1 - F)/F, least at the largest F;
//   Cu = r^0.5 = 2 <= 3: F up to 0.3, (H/F)min = 0.7/0.3;
//   Li-Fannin: H/0.15 for F >= 0.15, least (1 - 0.3)/0.15 at F = 0.3;
//   h' = D90/D60 = r^0.3, h'' = D90/D15 = r^0.75.
TEST(Gradation, UniformSandIsStableWithClosedFormIndices) {
  const Gradation g({{0.2, 0}, {0.4, 50}, {0.8, 100}}, "uniform sand");
  const double r = 4;
  EXPECT_REL(g.d(60) / g.d(10), std::pow(r, 0.5));
  const auto s = suffuse::assess_internal_stability(g);
  EXPECT_REL(s.cu, 2.0);
  EXPECT_EQ(s.shape_curve_limit, 0.3);

  const auto& kezdi = criterion(s, "kezdi");
  EXPECT_REL(kezdi.value, std::pow(r, 0.15));
  EXPECT_EQ(kezdi.verdict, Verdict::stable);

  const auto& kl = criterion(s, "kenney_lau_1986");
  EXPECT_REL(kl.value, 0.7 / 0.3);
  EXPECT_REL(kl.at_passing, 0.3);
  EXPECT_REL(kl.at_size_mm, 0.2 * std::pow(r, 0.3));
  EXPECT_EQ(kl.verdict, Verdict::stable);
  EXPECT_EQ(criterion(s, "kenney_lau_1985").verdict, Verdict::stable);  // 2.33 >= 1.3

  const auto& lf = criterion(s, "li_fannin");
  EXPECT_REL(lf.value, 0.7 / 0.15);
  EXPECT_EQ(lf.verdict, Verdict::stable);

  const auto& bu = criterion(s, "burenkova");
  EXPECT_REL(bu.value, std::pow(r, 0.3));
  EXPECT_REL(bu.also.at(0).second, std::pow(r, 0.75));
  // 0.76 log10(r^0.75) + 1 = 1.343 < h' = 1.516 < 1.86 log10(r^0.75) + 1 = 1.840.
  EXPECT_EQ(bu.verdict, Verdict::stable);

  EXPECT_FALSE(s.unstable());
  EXPECT_TRUE(s.stable());
  EXPECT_EQ(s.erodible_fines, 0);
  EXPECT_FALSE(s.gap);
}

// Two sizes with a gap: 30 % fines uniform in log D over 0.1-0.2 mm, 70 %
// coarse over 1-2 mm, nothing in between. D(F) = 0.1 * 2^(F/0.3) for F <= 0.3
// and 2^((F - 0.3)/0.7) above.
//   Kezdi: for splits F_s <= 0.15/0.85 both sizes are in the fines and
//   D'15/d'85 = 2^(0.15/0.3); just above F_s = 0.15/0.85, D'15 jumps to the
//   coarse grains' 1 mm while d'85 = D(0.15) = 0.1 * 2^0.5, and the ratio
//   only falls for larger splits: sup = 1 / (0.1 * 2^0.5) = 7.071, at the
//   split F_s = 0.15/0.85.
//   Shape curve: for D in the fines, 4D lies in the gap, F(4D) = 0.3, so
//   H/F = 0.3/F - 1; Cu = D60/D10 = 2^(0.3/0.7) / (0.1 * 2^(1/3)) > 3, so F up
//   to 0.2: (H/F)min = 0.5 at F = 0.2, D = 0.1 * 2^(2/3).
//   Li-Fannin: (0.3 - F)/0.15 for F >= 0.15, least 2/3 at F = 0.2.
//   h' = D90/D60 = 2^(0.3/0.7); h'' = D90/D15 = 2^(0.6/0.7) / (0.1 * 2^0.5).
TEST(Gradation, TwoSizeGapGradedMixtureIsUnstableWithClosedFormIndices) {
  const Gradation g({{0.1, 0}, {0.2, 30}, {1.0, 30}, {2.0, 100}}, "two sizes");
  const auto s = suffuse::assess_internal_stability(g);
  EXPECT_REL(s.cu, std::pow(2, 0.3 / 0.7) / (0.1 * std::pow(2, 1.0 / 3)));
  EXPECT_EQ(s.shape_curve_limit, 0.2);

  const auto& kezdi = criterion(s, "kezdi");
  EXPECT_REL(kezdi.value, 1 / (0.1 * std::sqrt(2.0)));
  EXPECT_REL(kezdi.at_passing, 0.15 / 0.85);
  EXPECT_EQ(kezdi.verdict, Verdict::unstable);

  const auto& kl = criterion(s, "kenney_lau_1986");
  EXPECT_REL(kl.value, 0.5);
  EXPECT_REL(kl.at_passing, 0.2);
  EXPECT_REL(kl.at_size_mm, 0.1 * std::pow(2, 2.0 / 3));
  EXPECT_EQ(kl.verdict, Verdict::unstable);

  const auto& lf = criterion(s, "li_fannin");
  EXPECT_REL(lf.value, 2.0 / 3);
  EXPECT_EQ(lf.verdict, Verdict::unstable);

  const auto& bu = criterion(s, "burenkova");
  EXPECT_REL(bu.value, std::pow(2, 0.3 / 0.7));
  EXPECT_REL(bu.also.at(0).second, std::pow(2, 0.6 / 0.7) / (0.1 * std::sqrt(2.0)));
  // h' = 1.346 < 0.76 log10(12.81) + 1 = 1.842: Zone I.
  EXPECT_EQ(bu.verdict, Verdict::unstable);

  ASSERT_TRUE(s.gap);
  EXPECT_EQ(s.gap->from_mm, 0.2);
  EXPECT_EQ(s.gap->to_mm, 1.0);
  // Fines finer than 0.063 mm: none, so Chang and Zhang's gap-graded rule
  // for P < 10 % applies: Gr = 5 >= 3.
  const auto& cz = criterion(s, "chang_zhang");
  EXPECT_REL(cz.value, 5.0);
  EXPECT_EQ(cz.verdict, Verdict::unstable);
  EXPECT_EQ(criterion(s, "wan_fell_2008").verdict, Verdict::not_applicable);  // not for gap-graded soils

  EXPECT_TRUE(s.unstable());
  EXPECT_EQ(s.erodible_fines, 0.3);  // finer than the gap
}

// The DEM study's soil was chosen unstable by Kezdi, Kenney and Lau and
// Burenkova; its shipped PSD (a reconstruction, see the file) must say so.
TEST(Gradation, DemStudySoilIsUnstableByTheCriteriaItWasChosenWith) {
  const Gradation g = suffuse::read_gradation_file(suffuse::test::source_dir() / "share/gradations/dem_gap_graded.csv");
  const auto s = suffuse::assess_internal_stability(g);
  for (const char* id : {"kezdi", "kenney_lau_1985", "kenney_lau_1986", "burenkova"})
    EXPECT_EQ(criterion(s, id).verdict, Verdict::unstable) << id;
  EXPECT_EQ(s.erodible_fines, 0.35);
}

// Kezdi's split as Skempton and Brogan (1994, Geotechnique 44(3): 449-460,
// Introduction) apply it: for a split at S % passing, read d'85 on the grading
// curve at 0.85 S and D'15 at 0.85 S + 15, "then check at points a little
// above and below to ensure that a maximum value" of D'15/d'85 "has been
// found". The reported split must sit at those two points of the curve, and a
// dense scan of every split (independent of the breakpoint search) must find
// nothing larger. The curves are test curves, not published ones: a broadly
// graded one with several kinks, and the DEM soil, whose supremum lies at a
// jump of D(F) (the gap) and is only approached by the scan.
TEST(Gradation, KezdiRatioIsTheMaximumOverSplitsReadAsSkemptonAndBroganDo) {
  const Gradation broad({{0.075, 0}, {0.15, 8}, {0.6, 20}, {2, 35}, {4.75, 55}, {19, 80}, {37.5, 100}}, "broad");
  const Gradation gap =
      suffuse::read_gradation_file(suffuse::test::source_dir() / "share/gradations/dem_gap_graded.csv");
  for (const Gradation* g : {&broad, &gap}) {
    // The assessment is kept: criterion() returns a reference into it (a
    // temporary here was read after its end, found by AddressSanitizer).
    const suffuse::InternalStability assessed = suffuse::assess_internal_stability(*g);
    const auto& kezdi = criterion(assessed, "kezdi");
    const double split = kezdi.at_passing, coarse_d15 = kezdi.also.at(0).second, fine_d85 = kezdi.also.at(1).second;
    // On the curve at 0.85 S + 15 and 0.85 S: a round-off check (1e-9), the
    // points are interpolated exactly.
    EXPECT_NEAR(g->passing(coarse_d15), 0.85 * split + 0.15, 1e-9) << g->source();
    EXPECT_NEAR(g->passing(fine_d85), 0.85 * split, 1e-9) << g->source();
    EXPECT_REL(kezdi.value, coarse_d15 / fine_d85);
    double scanned = 0;
    const int n = 200000;
    for (int k = 1; k < n; ++k) {
      const double s = static_cast<double>(k) / n;
      if (0.85 * s < g->smallest_passing()) continue;
      scanned = std::max(scanned, g->d(100 * (0.85 * s + 0.15)) / g->d(100 * 0.85 * s));
    }
    // Nothing above the reported maximum but round-off; and the scan comes
    // within 0.1 % of it (a step of 5e-6 in S moves the sizes by far less).
    EXPECT_LE(scanned, kezdi.value * (1 + 1e-9)) << g->source();
    EXPECT_GE(scanned, kezdi.value * (1 - 1e-3)) << g->source();
  }
}

TEST(Gradation, InterpolatesLinearlyInLogSizeWithoutOvershoot) {
  const Gradation g({{0.1, 0}, {1.0, 40}, {10.0, 100}}, "test");
  EXPECT_REL(g.passing(std::sqrt(0.1 * 1.0)), 0.2);  // half-way in log D
  EXPECT_REL(g.d(70), std::sqrt(10.0));
  EXPECT_EQ(g.passing(0.05), 0);
  EXPECT_EQ(g.passing(20), 1);
  for (double d = 0.1; d < 10; d *= 1.1) EXPECT_LE(g.passing(d), g.passing(d * 1.1));
}

// ---------------------------------------------------------------------------
// Bad input: the exact message, naming the file and line or JSON pointer.

fs::path write_psd(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / "suffuse_gradation";
  fs::create_directories(dir);
  std::ofstream(dir / name) << text;
  return dir / name;
}

std::string error_of(const fs::path& file) {
  try {
    suffuse::read_gradation_file(file);
  } catch (const suffuse::Error& e) {
    return e.what();
  }
  return "no error";
}

TEST(GradationInput, SizesNotIncreasingNameTheLine) {
  const fs::path f = write_psd("a.csv", "size [mm], passing [%]\n0.1, 0\n0.5, 40\n0.4, 60\n1, 100\n");
  EXPECT_EQ(error_of(f), f.string() + ":4: sizes not increasing: expected a size above the previous row's 0.5 "
                                      "(smallest sieve first), found 0.4");
}

TEST(GradationInput, PercentPassingDecreasingOrOutOfRangeNameTheLine) {
  const fs::path f = write_psd("b.csv", "# sieve analysis\nsize [mm], passing [%]\n0.1, 10\n\n0.5, 5\n1, 100\n");
  EXPECT_EQ(error_of(f), f.string() + ":5: percent passing decreases: expected at least the previous row's 10 "
                                      "(a cumulative curve), found 5");
  const fs::path g = write_psd("c.csv", "size [mm], passing [%]\n0.1, 0\n0.5, 140\n1, 100\n");
  EXPECT_EQ(error_of(g), g.string() + ":3: percent passing outside 0-100: expected a percent passing in [0, 100], "
                                      "found 140");
}

TEST(GradationInput, TooFewPointsAndUnitsMissing) {
  const fs::path f = write_psd("d.csv", "size [mm], passing [%]\n0.1, 0\n1, 100\n");
  EXPECT_EQ(error_of(f), f.string() + ": too few points: expected at least 3 rows of (size, percent passing), "
                                      "found 2 row(s)");
  const fs::path g = write_psd("e.csv", "size, passing\n0.1, 0\n0.5, 40\n1, 100\n");
  EXPECT_EQ(error_of(g), g.string() + ":1: size unit missing or unknown: expected a header \"size [mm], passing "
                                      "[%]\" (size in mm, um or m, percent passing in %), found \"size\"");
  const fs::path h = write_psd("f.json", "[[0.1, 0], [0.5, 40], [1, 100]]");
  EXPECT_EQ(error_of(h), h.string() + ": /: units missing: expected {\"size_unit\": \"mm\", \"points\": [[size, "
                                      "percent passing], ...]}, found array [[0.1,0],[0.5,40],[1,100]]");
}

TEST(GradationInput, JsonProblemsNameTheJsonPointer) {
  const fs::path f = write_psd("g.json", R"({"size_unit": "um", "points": [[100, 0], [500, 40], [400, 100]]})");
  EXPECT_EQ(error_of(f), f.string() + ": /points/2/0: sizes not increasing: expected a size above the previous "
                                      "row's 0.5 (smallest sieve first), found 0.4");
  const fs::path g = write_psd("h.json", R"({"size_unit": "um", "points": [[100, 0], "x", [400, 100]]})");
  EXPECT_EQ(error_of(g), g.string() + ": /points/1: not a pair of numbers: expected [size, percent passing], "
                                      "found string \"x\"");
}

TEST(GradationInput, CurveMustReachOneHundredPercentAndCellsMustBeNumbers) {
  const fs::path f = write_psd("i.csv", "size [um], passing [%]\n100, 0\n500, 40\n1000, 90\n");
  EXPECT_EQ(error_of(f), f.string() + ":4: the curve does not reach 100 percent passing: expected 100 at the "
                                      "largest size (the whole sample passes it), found 90");
  const fs::path g = write_psd("j.csv", "size [mm], passing [%]\n0.1, 0\n0.5, forty\n1, 100\n");
  EXPECT_EQ(error_of(g), g.string() + ":3: not a number: expected a percent passing, found \"forty\"");
}

TEST(GradationInput, SizesInMicrometresAreConvertedToMillimetres) {
  const fs::path f = write_psd("k.csv", "size_um,percent_passing\n100,0\n500,40\n1000,100\n");
  const Gradation g = suffuse::read_gradation_file(f);
  EXPECT_EQ(g.sizes_mm().front(), 0.1);
  EXPECT_EQ(g.sizes_mm().back(), 1.0);
}

// Laboratory sheets list sieves from the largest down: the same curve either
// way round, and a row out of order named in the table's own order.
TEST(GradationInput, TablesListedFromTheLargestSieveDownAreReadAsTheSameCurve) {
  const fs::path up = write_psd("up.csv", "size [mm], passing [%]\n0.075, 5\n0.425, 35\n2, 35\n4.75, 60\n19, 100\n");
  const fs::path down =
      write_psd("down.csv", "sieve size [mm], percent passing [%]\n19, 100\n4.75, 60\n2, 35\n0.425, 35\n0.075, 5\n");
  const Gradation a = suffuse::read_gradation_file(up), b = suffuse::read_gradation_file(down);
  EXPECT_EQ(a.order(), suffuse::SieveOrder::smallest_first);
  EXPECT_EQ(b.order(), suffuse::SieveOrder::largest_first);
  EXPECT_EQ(a.sizes_mm(), b.sizes_mm());
  EXPECT_EQ(a.passing_points(), b.passing_points());
  const auto sa = suffuse::assess_internal_stability(a), sb = suffuse::assess_internal_stability(b);
  ASSERT_EQ(sa.criteria.size(), sb.criteria.size());
  for (std::size_t k = 0; k < sa.criteria.size(); ++k) EXPECT_EQ(sa.criteria[k].verdict, sb.criteria[k].verdict);
  EXPECT_EQ(sa.unstable(), sb.unstable());

  const fs::path bad = write_psd("down_bad.csv", "size [mm], passing [%]\n19, 100\n4.75, 60\n6, 35\n0.075, 5\n");
  EXPECT_EQ(error_of(bad), bad.string() + ":4: sizes not decreasing: expected a size below the previous row's 4.75 "
                                          "(largest sieve first), found 6");
  const fs::path rising = write_psd("down_rising.csv", "size [mm], passing [%]\n19, 100\n4.75, 60\n2, 70\n0.075, 5\n");
  EXPECT_EQ(error_of(rising), rising.string() + ":4: percent passing increases: expected at most the previous row's 60 "
                                                "(a cumulative curve), found 70");
  const fs::path short_of_all = write_psd("down_90.csv", "size [mm], passing [%]\n19, 90\n4.75, 60\n0.075, 5\n");
  EXPECT_EQ(error_of(short_of_all), short_of_all.string() + ":2: the curve does not reach 100 percent passing: "
                                                            "expected 100 at the largest size (the whole sample "
                                                            "passes it), found 90");
}

// ---------------------------------------------------------------------------
// suffuse gradation, end to end.

namespace command {

// Runs suffuse gradation ARGS in DIR; its exit status, with stdout and stderr in DIR/log.txt.
int gradation(const fs::path& dir, const std::string& args) {
  const std::string line = "cd " + dir.string() + " && " + std::string(SUFFUSE_EXECUTABLE) + " gradation " + args +
                           " > log.txt 2>&1";
  const int status = std::system(line.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}

using suffuse::test::slurp;

const std::string dem = (suffuse::test::source_dir() / "share/gradations/dem_gap_graded.csv").string();

TEST(GradationCommand, PrintsATableWithEveryCriterionAndTheErodibleFines) {
  const fs::path dir = fresh_dir("gradation_table");
  ASSERT_EQ(gradation(dir, dem), 0) << slurp(dir / "log.txt");
  const std::string out = slurp(dir / "log.txt");
  EXPECT_NE(out.find("criterion"), std::string::npos);
  for (const char* name : {"Kezdi (1979)", "Kenney and Lau (1985)", "Kenney and Lau (1986)", "Li and Fannin (2008)",
                           "Burenkova (1993)", "Modified Burenkova", "Wan and Fell (2008)", "Chang and Zhang (2013)"})
    EXPECT_NE(out.find(name), std::string::npos) << name;
  EXPECT_NE(out.find("erodible fines content: 35 %"), std::string::npos) << out;
}

TEST(GradationCommand, SaysWhichOrderItReadTheSievesIn) {
  const fs::path dir = fresh_dir("gradation_order");
  std::ofstream(dir / "down.csv") << "size [mm], passing [%]\n19, 100\n4.75, 60\n2, 35\n0.425, 35\n0.075, 5\n";
  ASSERT_EQ(gradation(dir, "down.csv"), 0) << slurp(dir / "log.txt");
  EXPECT_NE(slurp(dir / "log.txt").find("down.csv: 5 points (read largest sieve first), 0.075-19 mm"),
            std::string::npos)
      << slurp(dir / "log.txt");
  ASSERT_EQ(gradation(dir, "down.csv --json"), 0) << slurp(dir / "log.txt");
  EXPECT_EQ(nlohmann::json::parse(slurp(dir / "log.txt"))["read_order"], "largest sieve first");
  ASSERT_EQ(gradation(dir, dem), 0);
  EXPECT_NE(slurp(dir / "log.txt").find("(read smallest sieve first)"), std::string::npos);
}

TEST(GradationCommand, JsonHasTheSameVerdicts) {
  const fs::path dir = fresh_dir("gradation_json");
  ASSERT_EQ(gradation(dir, dem + " --json"), 0) << slurp(dir / "log.txt");
  const nlohmann::json j = nlohmann::json::parse(slurp(dir / "log.txt"));
  const auto g = suffuse::read_gradation_file(dem);
  const auto s = suffuse::assess_internal_stability(g);
  ASSERT_EQ(j["criteria"].size(), s.criteria.size());
  for (std::size_t k = 0; k < s.criteria.size(); ++k) {
    EXPECT_EQ(j["criteria"][k]["id"], s.criteria[k].id);
    EXPECT_EQ(j["criteria"][k]["verdict"], suffuse::to_string(s.criteria[k].verdict));
  }
  EXPECT_EQ(j["erodible_fines"], 0.35);
  EXPECT_TRUE(j["unstable"].get<bool>());
}

TEST(GradationCommand, PngIsWrittenAndBadInputIsAnErrorWithNothingWritten) {
  const fs::path dir = fresh_dir("gradation_png");
  ASSERT_EQ(gradation(dir, dem + " --png psd.png"), 0) << slurp(dir / "log.txt");
  const std::string png = slurp(dir / "psd.png");
  ASSERT_GT(png.size(), 1000u);
  EXPECT_EQ(png.substr(1, 3), "PNG");
  std::ofstream(dir / "bad.csv") << "size, passing\n0.1, 0\n1, 50\n2, 100\n";
  EXPECT_EQ(gradation(dir, "bad.csv --png bad.png"), 1);
  EXPECT_NE(slurp(dir / "log.txt").find("bad.csv:1: size unit missing or unknown"), std::string::npos);
  EXPECT_FALSE(fs::exists(dir / "bad.png"));
}

}  // namespace command


// ---------------------------------------------------------------------------
// Gradations in scenes.

namespace scenes {

nlohmann::json column() {
  nlohmann::json j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  j["bodies"][0].erase("fines_content");
  j["bodies"][0].erase("ultimate_fines_content");
  return j;
}

std::vector<suffuse::Diagnostic> diagnostics_of(const nlohmann::json& j) {
  suffuse::Registry registry;
  try {
    suffuse::test::scene_from(j, registry);
  } catch (const suffuse::SceneError& e) {
    return e.diagnostics();
  }
  return {};
}

// A file relative to the scene (scene_from reads scenes as if they were in
// the source directory).
TEST(GradationScene, FinesContentComesFromTheGradationFile) {
  nlohmann::json j = column();
  j["bodies"][0]["gradation"] = "share/gradations/dem_gap_graded.csv";
  j["bodies"][0]["fines_content_from_gradation"] = true;
  suffuse::Registry registry;
  const suffuse::Scene scene = suffuse::test::scene_from(j, registry);
  const suffuse::BodySpec& body = scene.bodies[0];
  ASSERT_TRUE(body.internal_stability);
  EXPECT_TRUE(body.internal_stability->unstable());
  EXPECT_EQ(body.fines_content, 0.35);  // finer than the gap, 35 % passing
}

TEST(GradationScene, BadInlinePointsNameTheirJsonPointer) {
  nlohmann::json j = column();
  j["bodies"][0]["gradation_points"] = {{0.2, 0}, {0.4, 50}, {0.3, 100}};
  const auto d = diagnostics_of(j);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].pointer, "/bodies/0/gradation_points/2/0");
  EXPECT_EQ(d[0].problem, "sizes not increasing");
  j["bodies"][0]["gradation_points"] = {{0.2, 0, 1}, {0.4, 50}, {0.8, 100}};
  EXPECT_EQ(diagnostics_of(j).at(0).problem, "wrong shape of a row");
}

TEST(GradationScene, ConflictingOrMissingSourcesAreErrors) {
  nlohmann::json j = column();
  j["bodies"][0]["fines_content_from_gradation"] = true;
  EXPECT_EQ(diagnostics_of(j).at(0).pointer, "/bodies/0/fines_content_from_gradation");
  j["bodies"][0]["gradation"] = "share/gradations/no_such.csv";
  const auto d = diagnostics_of(j);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].pointer, "/bodies/0/gradation");
  EXPECT_EQ(d[0].problem, "unreadable PSD file");
  j["bodies"][0]["gradation"] = "share/gradations/dem_gap_graded.csv";
  j["bodies"][0]["fines_content"] = 0.2;
  EXPECT_EQ(diagnostics_of(j).at(0).problem, "two fines contents");
}

// An erosion law on a soil every criterion finds stable: validate says so.
TEST(GradationScene, ValidateWarnsWhenAStableSoilIsEroded) {
  nlohmann::json j = column();
  j["bodies"][0]["gradation_points"] = {{0.2, 0}, {0.4, 50}, {0.8, 100}};  // the uniform sand above
  j["bodies"][0]["fines_content"] = 0.1;
  const fs::path dir = fresh_dir("gradation_validate");
  std::ofstream(dir / "stable.json") << j.dump(1);
  const std::string line = std::string(SUFFUSE_EXECUTABLE) + " validate " + (dir / "stable.json").string() + " > " +
                           (dir / "log.txt").string() + " 2>&1";
  ASSERT_EQ(std::system(line.c_str()), 0) << suffuse::test::slurp(dir / "log.txt");
  const std::string out = suffuse::test::slurp(dir / "log.txt");
  EXPECT_NE(out.find("Kezdi (1979)"), std::string::npos) << out;
  EXPECT_NE(out.find("warning: body 'column': every applicable criterion finds its gradation stable, yet material "
                     "'gap_graded_sand' erodes it (erosion/vardoulakis_ccr)"),
            std::string::npos)
      << out;
}

}  // namespace scenes

}  // namespace
