// Third-party plugins as a user builds them: install suffuse to a prefix,
// copy the erosion-law template out of the installed share/, build it
// against the installed CMake package only, run a scene naming the law, and
// check the result, and that nothing of the installed suffuse was rebuilt.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include <suffuse/simulation.hpp>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;

using suffuse::test::slurp;

// Runs a shell command with the plugin path of the environment cleared, its
// output in `log`; returns the exit status.
int sh(const std::string& command, const fs::path& log) {
  const std::string full = "env -u SUFFUSE_PLUGIN_PATH " + command + " > " + log.string() + " 2>&1";
  const int status = std::system(full.c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

std::vector<std::string> split(const std::string& line) {
  std::vector<std::string> cells;
  std::stringstream s(line);
  for (std::string cell; std::getline(s, cell, ',');) cells.push_back(cell);
  return cells;
}

struct Installed {
  fs::path root, prefix;
  // Each test installs into a folder of its own: ctest runs them in parallel.
  explicit Installed(const std::string& name) {
    root = fs::temp_directory_path() / ("suffuse_install_test_" + name);
    fs::remove_all(root);
    fs::create_directories(root);
    prefix = root / "prefix";
    const int status = sh(std::string(CMAKE_COMMAND) + " --install " + SUFFUSE_BUILD_DIR + " --prefix " +
                              prefix.string(), root / "install.log");
    EXPECT_EQ(status, 0) << slurp(root / "install.log");
  }
  fs::path program() const { return prefix / "bin/suffuse"; }
  fs::path core() const { return fs::canonical(prefix / "lib/libsuffuse_core.so"); }
};

TEST(Install, TemplateLawBuildsAgainstTheInstalledPackageAndRuns) {
  const Installed inst("erosion_law");
  const std::string program_before = slurp(inst.program()), core_before = slurp(inst.core());
  ASSERT_FALSE(program_before.empty());
  ASSERT_FALSE(core_before.empty());

  // The template, copied from the installed share/ to a folder of its own.
  const fs::path law = inst.root / "my_law";
  fs::copy(inst.prefix / "share/suffuse/templates/erosion_law", law, fs::copy_options::recursive);
  const auto start = std::chrono::steady_clock::now();
  ASSERT_EQ(sh(std::string(CMAKE_COMMAND) + " -S " + law.string() + " -B " + (law / "build").string() +
                   " -DCMAKE_PREFIX_PATH=" + inst.prefix.string(),
               inst.root / "configure.log"),
            0)
      << slurp(inst.root / "configure.log");
  ASSERT_EQ(sh(std::string(CMAKE_COMMAND) + " --build " + (law / "build").string() + " -j2", inst.root / "build.log"),
            0)
      << slurp(inst.root / "build.log");
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  RecordProperty("out_of_tree_build_seconds", std::to_string(seconds));
  // Built from the installed package alone: no path into the source tree.
  EXPECT_EQ(slurp(law / "build/CMakeCache.txt").find(SUFFUSE_SOURCE_DIR), std::string::npos);
  EXPECT_TRUE(fs::exists(law / "build/libmy_erosion_law.so"));
  // The template's own unit test.
  EXPECT_EQ(sh("ctest --test-dir " + (law / "build").string() + " --output-on-failure", inst.root / "ctest.log"), 0)
      << slurp(inst.root / "ctest.log");

  // The scene that names the law, run by the installed program.
  ASSERT_EQ(sh(inst.program().string() + " run " + (law / "first_order_box.json").string() + " --output " +
                   (law / "out").string(),
               inst.root / "run.log"),
            0)
      << slurp(inst.root / "run.log");
  // Closed box, no flow: F = (1-n) f_c follows F_k+1 - F_inf = (1 - dt k (1 - f_inf)) (F_k - F_inf)
  // exactly, 100 steps of 0.01 s; the fines in the skeleton are rho_s F V.
  const auto scene = suffuse::test::read_json(law / "first_order_box.json");
  const double n0 = scene["bodies"][0]["porosity"], fc0 = scene["bodies"][0]["fines_content"];
  const double f_inf = scene["bodies"][0]["ultimate_fines_content"];
  const double k = scene["materials"]["sand"]["erosion"]["rate_constant"];
  const double rho_s = scene["materials"]["sand"]["density"], dt = scene["time"]["dt"];
  const double volume = 0.1 * 0.1, C = (1 - n0) * (1 - fc0), F_inf = f_inf * C / (1 - f_inf);
  const double F = F_inf + ((1 - n0) * fc0 - F_inf) * std::pow(1 - dt * k * (1 - f_inf), 100);
  std::ifstream csv(law / "out/first_order_box.ledger.csv");
  std::string header, line, last;
  std::getline(csv, header);
  while (std::getline(csv, line)) last = line;
  const auto names = split(header), values = split(last);
  ASSERT_EQ(names.size(), values.size());
  const auto column = [&](const std::string& name) {  // by the name before its unit, "time [s]"
    const auto at = std::find_if(names.begin(), names.end(),
                                 [&](const std::string& h) { return h.substr(0, h.find(" [")) == name; });
    return std::stod(values.at(static_cast<std::size_t>(at - names.begin())));
  };
  EXPECT_DOUBLE_EQ(column("time"), 1.0);
  EXPECT_NEAR(column("skeleton_fines") / (rho_s * F * volume), 1.0, 1e-12);
  EXPECT_LT(column("fines_imbalance"), 1e-12);

  // The installed program draws through its figures module (found beside
  // the installed plugins, as the core finds them).
  const fs::path png = inst.root / "fines.png";
  ASSERT_EQ(sh(inst.program().string() + " plot --png " + png.string() + " --x time --y skeleton_fines " +
                   (law / "out/first_order_box.ledger.csv").string(),
               inst.root / "plot.log"),
            0)
      << slurp(inst.root / "plot.log");
  EXPECT_GT(fs::file_size(png), 1000u);
  // Without its module, suffuse plot says what is missing (and nothing else
  // of the program needs it).
  fs::rename(inst.prefix / "lib/suffuse/libsuffuse_figures.so", inst.root / "libsuffuse_figures.so");
  EXPECT_EQ(sh(inst.program().string() + " plot --png " + png.string() + " --x time --y skeleton_fines " +
                   (law / "out/first_order_box.ledger.csv").string(),
               inst.root / "plot_without_module.log"),
            1);
  EXPECT_NE(slurp(inst.root / "plot_without_module.log").find("cannot load the figures module"), std::string::npos)
      << slurp(inst.root / "plot_without_module.log");
  EXPECT_EQ(sh(inst.program().string() + " --version", inst.root / "version.log"), 0);
  fs::rename(inst.root / "libsuffuse_figures.so", inst.prefix / "lib/suffuse/libsuffuse_figures.so");
  // The VTK writers load VTK from their module when a run opens them:
  // without it the run stops before its first step, naming the writer and
  // the module (a restart opens them too, in Writer::resume).
  fs::rename(inst.prefix / "lib/suffuse/libsuffuse_vtk_files.so", inst.root / "libsuffuse_vtk_files.so");
  EXPECT_EQ(sh(inst.program().string() + " run " + (law / "first_order_box.json").string() + " --output " +
                   (law / "out_without_module").string(),
               inst.root / "run_without_module.log"),
            1);
  const std::string without = slurp(inst.root / "run_without_module.log");
  EXPECT_NE(without.find("writer/vtk_particles: cannot load the VTK module"), std::string::npos) << without;
  EXPECT_FALSE(fs::exists(law / "out_without_module/first_order_box.pvd")) << "nothing written before the first step";
  // A restart, extending the first run to a later end: it stops before its
  // first step too (the writers resume), and leaves the first run's series
  // and checkpoint as they were.
  const std::string original_scene = slurp(law / "first_order_box.json");
  auto longer = nlohmann::json::parse(original_scene);
  longer["time"]["end"] = 2.0;
  std::ofstream(law / "first_order_box.json") << longer.dump(2);
  const auto series_size = fs::file_size(law / "out/first_order_box.pvd");
  const auto checkpoint_size = fs::file_size(law / "out/first_order_box.checkpoint");
  EXPECT_EQ(sh(inst.program().string() + " run " + (law / "first_order_box.json").string() + " --output " +
                   (law / "out").string() + " --restart " + (law / "out/first_order_box.checkpoint").string(),
               inst.root / "restart_without_module.log"),
            1);
  const std::string restart = slurp(inst.root / "restart_without_module.log");
  EXPECT_NE(restart.find("writer/vtk_particles: cannot load the VTK module"), std::string::npos) << restart;
  EXPECT_EQ(fs::file_size(law / "out/first_order_box.pvd"), series_size);
  EXPECT_EQ(fs::file_size(law / "out/first_order_box.checkpoint"), checkpoint_size);
  fs::rename(inst.root / "libsuffuse_vtk_files.so", inst.prefix / "lib/suffuse/libsuffuse_vtk_files.so");
  // With the module back the same restart runs to the later end.
  EXPECT_EQ(sh(inst.program().string() + " run " + (law / "first_order_box.json").string() + " --output " +
                   (law / "out").string() + " --restart " + (law / "out/first_order_box.checkpoint").string(),
               inst.root / "restart.log"),
            0)
      << slurp(inst.root / "restart.log");
  EXPECT_NE(slurp(law / "out/first_order_box.pvd").find("timestep=\"2"), std::string::npos)
      << slurp(law / "out/first_order_box.pvd");
  std::ofstream(law / "first_order_box.json") << original_scene;

  // suffuse plugins lists it with its library; describe prints its parameters.
  const std::string with_law = "SUFFUSE_PLUGIN_PATH=" + (law / "build").string() + " ";
  ASSERT_EQ(sh(with_law + inst.program().string() + " plugins", inst.root / "plugins.log"), 0);
  const std::string listing = slurp(inst.root / "plugins.log");
  EXPECT_NE(listing.find("erosion/first_order"), std::string::npos) << listing;
  EXPECT_NE(listing.find((law / "build/libmy_erosion_law.so").string()), std::string::npos) << listing;
  ASSERT_EQ(sh(with_law + inst.program().string() + " describe erosion/first_order", inst.root / "describe.log"), 0);
  const std::string description = slurp(inst.root / "describe.log");
  EXPECT_NE(description.find("rate_constant"), std::string::npos) << description;
  EXPECT_NE(description.find("1/s"), std::string::npos) << description;

  // Nothing of the installed suffuse was rebuilt or rewritten.
  EXPECT_TRUE(slurp(inst.program()) == program_before) << "the installed program changed";
  EXPECT_TRUE(slurp(inst.core()) == core_before) << "the installed core library changed";
}

// Mean downward displacement of the top row of a 2D body's points [m].
double top_settlement(const suffuse::PointSet& pts) {
  const double* x = pts.data(pts.core().position);
  const double* u = pts.data(pts.core().displacement);
  double top = -1e300, sum = 0;
  int count = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) top = std::max(top, x[2 * p + 1] - u[2 * p + 1]);
  for (std::size_t p = 0; p < pts.size(); ++p)
    if (x[2 * p + 1] - u[2 * p + 1] > top - 1e-9) sum -= u[2 * p + 1], ++count;
  return sum / count;
}

double settlement_after(nlohmann::json scene, double end) {
  scene["time"]["end"] = end;
  scene["outputs"] = nlohmann::json::array();
  suffuse::Registry registry;
  const suffuse::Scene s = suffuse::test::scene_from(scene, registry);
  suffuse::Simulation sim(s, registry);
  sim.run({});
  return top_settlement(sim.points());
}

// The coupled-phase template, built against the installed package: its unit
// test passes, the installed program runs its scene, and the suffusion column
// with the template's skeleton settles more than the same column with
// phase/linear_elastic once the erosion front has climbed 10 cm (10 s).
TEST(Install, CoupledPhaseTemplateBuildsAndItsColumnSettles) {
  const Installed inst("coupled_phase");
  const fs::path phase = inst.root / "my_phase";
  fs::copy(inst.prefix / "share/suffuse/templates/coupled_phase", phase, fs::copy_options::recursive);
  ASSERT_EQ(sh(std::string(CMAKE_COMMAND) + " -S " + phase.string() + " -B " + (phase / "build").string() +
                   " -DCMAKE_PREFIX_PATH=" + inst.prefix.string() + " -DCMAKE_EXPORT_COMPILE_COMMANDS=ON",
               inst.root / "configure.log"),
            0)
      << slurp(inst.root / "configure.log");
  ASSERT_EQ(sh(std::string(CMAKE_COMMAND) + " --build " + (phase / "build").string() + " -j2", inst.root / "build.log"),
            0)
      << slurp(inst.root / "build.log");
  EXPECT_EQ(slurp(phase / "build/CMakeCache.txt").find(SUFFUSE_SOURCE_DIR), std::string::npos);
  // Built without a build type, as the template says: optimised all the same
  // (the plugin's compile command; the generator's own files differ).
  const nlohmann::json commands = suffuse::test::read_json(phase / "build/compile_commands.json");
  const auto plugin = std::find_if(commands.begin(), commands.end(), [](const nlohmann::json& c) {
    return fs::path(c.at("file").get<std::string>()).filename() == "eroding_elastic.cpp";
  });
  ASSERT_NE(plugin, commands.end()) << commands.dump(1);
  EXPECT_NE(plugin->at("command").get<std::string>().find(" -O3"), std::string::npos) << plugin->dump();
  EXPECT_EQ(sh("ctest --test-dir " + (phase / "build").string() + " --output-on-failure", inst.root / "ctest.log"), 0)
      << slurp(inst.root / "ctest.log");

  // The installed program runs the template's scene (a short stretch of it).
  auto scene = suffuse::test::read_json(phase / "eroding_column.json");
  auto short_scene = scene;
  short_scene["time"]["end"] = 0.2;
  std::ofstream(phase / "short.json") << short_scene.dump(2);
  ASSERT_EQ(sh(inst.program().string() + " run " + (phase / "short.json").string() + " --quiet --output " +
                   (phase / "out").string(),
               inst.root / "run.log"),
            0)
      << slurp(inst.root / "run.log");
  EXPECT_TRUE(fs::exists(phase / "out/short.pvd"));

  // Settlement of the top, the template's skeleton against the linear one.
  scene["plugin_paths"] = {(phase / "build/libmy_coupled_phase.so").string()};
  auto linear = suffuse::test::read_json(inst.prefix / "share/suffuse/scenes/suffusion_column.json");
  // The same column but for the phase: the template has no tension cut-off.
  linear["materials"]["gap_graded_sand"]["tension_cutoff"] = false;
  const double eroding = settlement_after(scene, 10.0), elastic = settlement_after(linear, 10.0);
  char text[64];
  std::snprintf(text, sizeof text, "%.4g", eroding);
  RecordProperty("settlement_eroding_elastic_m", text);
  std::snprintf(text, sizeof text, "%.4g", elastic);
  RecordProperty("settlement_linear_elastic_m", text);
  // Softening can add at most the strain of the whole column at the residual
  // stiffness: int sigma'_v dy (1/(r M) - 1/M) = 514 Pa m (4 / 1.2e7 Pa) =
  // 1.7e-4 m (sigma'_v = (gamma' - i gamma_w) depth, M the constrained modulus).
  EXPECT_GT(eroding - elastic, 1e-5) << "eroding " << eroding << " m, linear " << elastic << " m";
  EXPECT_LT(eroding - elastic, 1.7e-4);
}

// A plugin built for another ABI major version, and a library that is not a
// suffuse plugin, named in a scene: the run stops before writing anything,
// with the library's specific message and status 1.
TEST(Install, RefusedLibrariesEndTheRunCleanly) {
  const fs::path dir = fs::temp_directory_path() / "suffuse_refused_test";
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto scene = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  const struct {
    const char* file;
    const char* message;
  } cases[] = {{"wrong_abi/libsuffuse_test_wrong_abi.so", "was built for plugin ABI"},
               {"no_entry/libsuffuse_test_no_entry.so", "is not a suffuse plugin"}};
  for (const auto& c : cases) {
    scene["plugin_paths"] = {(fs::path(SUFFUSE_TEST_PLUGIN_DIR) / c.file).string()};
    std::ofstream(dir / "scene.json") << scene.dump(2);
    const int status = sh(std::string(SUFFUSE_EXECUTABLE) + " run " + (dir / "scene.json").string() + " --output " +
                              (dir / "out").string(),
                          dir / "log.txt");
    const std::string log = slurp(dir / "log.txt");
    EXPECT_EQ(status, 1) << log;
    EXPECT_NE(log.find(c.message), std::string::npos) << log;
    EXPECT_FALSE(fs::exists(dir / "out")) << "nothing is written before the scene is valid";
  }
}

}  // namespace
