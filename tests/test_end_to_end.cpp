// End to end: the suffuse program runs an example scene and VTK's own XML
// readers read back what it wrote.
#include <gtest/gtest.h>
#include <vtkDataArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPolyData.h>
#include <vtkCellData.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkXMLImageDataReader.h>
#include <vtkXMLPolyDataReader.h>

#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cctype>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <fstream>
#include <iterator>
#include <regex>
#include <sstream>

#include <suffuse/simulation.hpp>

#include <suffuse/element_test.hpp>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using suffuse::test::fresh_dir;

struct Frame {
  double time;
  std::string file;
  int part;  // the writer's index in /outputs
};

// The entries of a .pvd collection; `part`: only that writer's (-1: all).
std::vector<Frame> read_pvd(const fs::path& pvd, int part = -1) {
  std::ifstream in(pvd);
  std::stringstream s;
  s << in.rdbuf();
  const std::string text = s.str();
  std::vector<Frame> frames;
  const std::regex dataset(R"re(<DataSet timestep="([^"]+)"[^>]*part="([0-9]+)" file="([^"]+)")re");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), dataset); it != std::sregex_iterator(); ++it)
    if (part < 0 || std::stoi((*it)[2]) == part) frames.push_back({std::stod((*it)[1]), (*it)[3], std::stoi((*it)[2])});
  return frames;
}

int run(const std::string& args, const fs::path& log, const std::string& environment = "") {
  const std::string command =
      "env " + environment + std::string(SUFFUSE_EXECUTABLE) + " " + args + " > " + log.string() + " 2>&1";
  return WEXITSTATUS(std::system(command.c_str()));
}

using suffuse::test::slurp;

TEST(EndToEnd, BarSceneWritesAReadableSeries) {
  const fs::path out = fresh_dir("e2e_bar");
  const fs::path scene = suffuse::test::source_dir() / "share/scenes/elastic_bar.json";
  ASSERT_EQ(run("run " + scene.string() + " --output " + out.string(), out / "log.txt"), 0) << slurp(out / "log.txt");
  const std::string log = slurp(out / "log.txt");
  EXPECT_NE(log.find("million point updates per second"), std::string::npos);
  // Not a terminal: a progress line at every tenth of the simulated time,
  // before the summary.
  for (const char* tenth : {"   10%  t = 0.012 of 0.12 s, step ", "   50%  t = 0.06 of 0.12 s, step ",
                            "  100%  t = 0.12 of 0.12 s, step "})
    EXPECT_NE(log.find(tenth), std::string::npos) << tenth << " in\n" << log;
  EXPECT_LT(log.find("  100%"), log.find("done:"));
  EXPECT_NE(log.find("steps/s, wall "), std::string::npos);

  const auto frames = read_pvd(out / "elastic_bar.pvd");
  // Initial state plus one frame every 0.002 s up to 0.12 s.
  ASSERT_EQ(frames.size(), 61u);
  EXPECT_EQ(frames.front().time, 0.0);
  EXPECT_NEAR(frames.back().time, 0.12, 1e-12);
  for (std::size_t i = 1; i < frames.size(); ++i) EXPECT_NEAR(frames[i].time - frames[i - 1].time, 0.002, 1e-9);

  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((out / frames.back().file).c_str());
  reader->Update();
  vtkPolyData* poly = reader->GetOutput();
  ASSERT_EQ(poly->GetNumberOfPoints(), 80);  // 40 x 2 points
  EXPECT_EQ(poly->GetNumberOfVerts(), 80);
  struct Expected {
    const char* name;
    int components;
  };
  for (const Expected& e : {Expected{"displacement", 3}, Expected{"velocity", 3}, Expected{"stress", 6},
                            Expected{"strain", 6}, Expected{"mass", 1}, Expected{"volume", 1},
                            Expected{"material_id", 1}}) {
    vtkDataArray* array = poly->GetPointData()->GetArray(e.name);
    ASSERT_NE(array, nullptr) << e.name;
    EXPECT_EQ(array->GetNumberOfComponents(), e.components) << e.name;
    EXPECT_EQ(array->GetNumberOfTuples(), 80) << e.name;
  }
  // Total mass read back equals rho * L * h = 1000 * 1 * 0.05.
  double mass = 0;
  vtkDataArray* m = poly->GetPointData()->GetArray("mass");
  for (vtkIdType p = 0; p < m->GetNumberOfTuples(); ++p) mass += m->GetTuple1(p);
  EXPECT_NEAR(mass, 50.0, 1e-9);
  // The bar has moved: some displacement is not zero.
  double umax = 0;
  vtkDataArray* u = poly->GetPointData()->GetArray("displacement");
  for (vtkIdType p = 0; p < u->GetNumberOfTuples(); ++p) umax = std::max(umax, std::abs(u->GetComponent(p, 0)));
  EXPECT_GT(umax, 1e-6);
}

TEST(EndToEnd, FailingRunLeavesReadableOutput) {
  const fs::path out = fresh_dir("e2e_fail");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  j["bodies"][0]["velocity"] = {2.0, 0.0};  // the free end flies out of the grid
  j["boundary_conditions"].erase(  // nothing holds the bar back
      suffuse::test::boundary_condition_index(j, {{"type", "bc/velocity"}, {"face", "left"}}));
  j["time"]["end"] = 1.0;
  j["outputs"][0]["interval"] = 0.01;
  std::ofstream(out / "flyaway.json") << j.dump(2);
  ASSERT_NE(run("run " + (out / "flyaway.json").string() + " --output " + out.string() + " --quiet", out / "log.txt"),
            0);
  const std::string log = slurp(out / "log.txt");
  EXPECT_NE(log.find("suffuse: error: material point"), std::string::npos) << log;
  const auto frames = read_pvd(out / "flyaway.pvd");
  ASSERT_GE(frames.size(), 2u);
  for (const Frame& f : frames) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((out / f.file).c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 80) << f.file;
  }
}

// Frames land on multiples of the interval even after thousands of steps, and
// two writers do not overwrite each other: each is one part of the series.
TEST(EndToEnd, OutputScheduleAndSeveralWriters) {
  const fs::path out = fresh_dir("e2e_schedule");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  j["time"] = {{"end", 1.0}, {"dt", 1e-4}};
  j["outputs"] = {{{"type", "writer/vtk_particles"}, {"interval", 0.01}},
                  {{"type", "writer/vtk_particles"}, {"interval", 0.25}, {"compress", false}}};
  std::ofstream(out / "schedule.json") << j.dump(2);
  ASSERT_EQ(run("run " + (out / "schedule.json").string() + " --output " + out.string() + " --quiet", out / "log.txt"),
            0)
      << slurp(out / "log.txt");
  const auto fine = read_pvd(out / "schedule.pvd", 0);
  const auto coarse = read_pvd(out / "schedule.pvd", 1);
  ASSERT_EQ(fine.size(), 101u);
  ASSERT_EQ(coarse.size(), 5u);
  for (std::size_t i = 0; i < fine.size(); ++i) EXPECT_NEAR(fine[i].time, 0.01 * i, 1e-12) << "frame " << i;
  for (std::size_t i = 0; i < coarse.size(); ++i) EXPECT_NEAR(coarse[i].time, 0.25 * i, 1e-12) << "frame " << i;
  EXPECT_TRUE(fs::exists(out / fine.back().file));
  EXPECT_TRUE(fs::exists(out / coarse.back().file));
  EXPECT_NE(fine.back().file, coarse.back().file);
}

TEST(EndToEnd, InvalidSceneFailsBeforeWritingAnything) {
  const fs::path out = fresh_dir("e2e_invalid");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  j["materials"]["steel_like"]["youngs_modulus"] = -1.0;
  j["time"]["cfl"] = 2.0;
  std::ofstream(out / "bad.json") << j.dump(2);
  EXPECT_EQ(run("validate " + (out / "bad.json").string(), out / "validate.txt"), 1);
  EXPECT_EQ(run("run " + (out / "bad.json").string() + " --output " + (out / "results").string(), out / "log.txt"), 1);
  const std::string log = slurp(out / "log.txt");
  EXPECT_NE(log.find("(2 errors)"), std::string::npos) << log;
  EXPECT_NE(log.find("/materials/steel_like/youngs_modulus: value out of range; expected number > 0 [Pa], found -1.0 "
                     "(declared by phase/linear_elastic)"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("/time/cfl: value out of range"), std::string::npos) << log;
  EXPECT_FALSE(fs::exists(out / "results"));
}

TEST(EndToEnd, CommandsForPluginsAndHelp) {
  const fs::path out = fresh_dir("e2e_cmds");
  ASSERT_EQ(run("plugins", out / "plugins.txt"), 0);
  const std::string plugins = slurp(out / "plugins.txt");
  for (const char* name : {"shape/linear", "phase/linear_elastic", "bc/velocity", "writer/vtk_particles"})
    EXPECT_NE(plugins.find(name), std::string::npos) << name;
  EXPECT_NE(plugins.find("libsuffuse_phase_linear_elastic.so"), std::string::npos);

  ASSERT_EQ(run("describe phase/linear_elastic", out / "describe.txt"), 0);
  const std::string describe = slurp(out / "describe.txt");
  EXPECT_NE(describe.find("youngs_modulus"), std::string::npos);
  EXPECT_NE(describe.find("number > 0 [Pa]"), std::string::npos);

  EXPECT_EQ(run("describe phase/nonexistent", out / "bad.txt"), 1);
  EXPECT_NE(slurp(out / "bad.txt").find("no plugin or core section named 'phase/nonexistent'"), std::string::npos);
  EXPECT_EQ(run("--version", out / "version.txt"), 0);
  EXPECT_NE(slurp(out / "version.txt").find(std::string("suffuse ") + suffuse::framework_version), std::string::npos);
  EXPECT_EQ(run("--help", out / "help.txt"), 0);
  EXPECT_NE(slurp(out / "help.txt").find("suffuse run SCENE.json"), std::string::npos);
  EXPECT_EQ(run("frobnicate", out / "unknown.txt"), 2);
}

// PETSc (about 90 libraries with MUMPS, HYPRE, Trilinos, HDF5), VTK's
// rendering and OpenGL, and VTK's XML output are loaded only by what needs
// them (the modules of distributed_system.hpp, figures_module.hpp and
// plugins/writer/vtk_common/vtk_files.hpp): linked into the core, the
// program or the plugins, they cost every command 60 MB and a tenth of a
// second.
TEST(EndToEnd, ARunLoadsOnlyTheLibrariesItsOutputsNeed) {
  const fs::path out = fresh_dir("e2e_libraries");
  // glibc's loader lists each library it opens ("file=libname ...").
  ASSERT_EQ(run("run " + std::string(SUFFUSE_SOURCE_DIR) + "/share/scenes/elastic_bar.json --quiet --output " +
                    (out / "run").string(),
                out / "run.txt", "LD_DEBUG=files "),
            0);
  const std::string opened = slurp(out / "run.txt");
  ASSERT_NE(opened.find("file=libsuffuse_core.so"), std::string::npos) << "no LD_DEBUG listing: " << opened;
  EXPECT_EQ(opened.find("file=libpetsc"), std::string::npos);
  EXPECT_EQ(opened.find("file=libvtkRendering"), std::string::npos);
  EXPECT_EQ(opened.find("file=libGL"), std::string::npos);
  // Its writer/vtk_particles loads VTK's XML output, through the module.
  EXPECT_NE(opened.find("/libsuffuse_vtk_files.so"), std::string::npos);
  EXPECT_NE(opened.find("file=libvtkIOXML"), std::string::npos);

  // The same bar with a CSV probe only: no VTK library at all (the plugin
  // loader opens every plugin library, the VTK writers' too).
  auto bar = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  bar["outputs"] = {{{"type", "writer/csv_probe"}, {"at", {0.0, 0.0}}, {"fields", {"displacement"}}}};
  std::ofstream(out / "bar.json") << bar.dump(2);
  ASSERT_EQ(run("run " + (out / "bar.json").string() + " --quiet --output " + (out / "csv").string(),
                out / "csv.txt", "LD_DEBUG=files "),
            0)
      << slurp(out / "csv.txt");
  const std::string csv_only = slurp(out / "csv.txt");
  ASSERT_NE(csv_only.find("/libsuffuse_writer_vtk_particles.so"), std::string::npos) << csv_only;
  EXPECT_EQ(csv_only.find("file=libvtk"), std::string::npos) << "a plugin library links VTK";
  EXPECT_TRUE(fs::exists(out / "csv/bar.csv"));
}

// A saturated run says which liquid bulk modulus it uses, in the log and in
// <name>.run.json beside the outputs.
TEST(EndToEnd, SaturatedRunRecordsItsNumericalChoices) {
  const fs::path out = fresh_dir("e2e_runinfo");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/terzaghi.json");
  j["time"]["end"] = 0.001;
  std::ofstream(out / "tz.json") << j.dump(2);
  ASSERT_EQ(run("run " + (out / "tz.json").string() + " --output " + out.string(), out / "log.txt"), 0)
      << slurp(out / "log.txt");
  EXPECT_NE(slurp(out / "log.txt").find("liquid 'water': bulk modulus 1e+08 Pa (lower than water's 2.2e9 Pa"),
            std::string::npos)
      << slurp(out / "log.txt");
  const auto info = suffuse::test::read_json(out / "tz.run.json");
  EXPECT_EQ(info["liquids"]["water"]["bulk_modulus"].get<double>(), 1e8);
  EXPECT_EQ(info["time_step_mode"], "automatic");
  EXPECT_EQ(info["saturated"], true);
  EXPECT_EQ(info["points"], 200);
  EXPECT_GT(info["time_step"].get<double>(), 0.0);
  // The saturated fields are in the frames.
  const auto frames = read_pvd(out / "tz.pvd");
  ASSERT_FALSE(frames.empty());
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((out / frames.back().file).c_str());
  reader->Update();
  for (const char* name : {"porosity", "pore_pressure", "liquid_velocity", "darcy_flux", "hydraulic_conductivity"})
    EXPECT_NE(reader->GetOutput()->GetPointData()->GetArray(name), nullptr) << name;
}

// docs/scene-reference.md is generated from the schemas: it must be current.
TEST(EndToEnd, SceneReferenceIsUpToDate) {
  const fs::path out = fresh_dir("e2e_reference");
  const std::string command = std::string("env -u SUFFUSE_PLUGIN_PATH ") + SUFFUSE_EXECUTABLE + " reference > " +
                              (out / "reference.md").string();
  ASSERT_EQ(WEXITSTATUS(std::system(command.c_str())), 0);
  EXPECT_EQ(slurp(out / "reference.md"), slurp(suffuse::test::source_dir() / "docs/scene-reference.md"))
      << "regenerate it: ./build/bin/suffuse reference > docs/scene-reference.md";
}

// share/schema/suffuse-schema.json (installed for editors and tools) is
// generated by `suffuse schema`: it must be current.
TEST(EndToEnd, InstalledSchemaIsUpToDate) {
  const fs::path out = fresh_dir("e2e_schema");
  const std::string command = std::string("env -u SUFFUSE_PLUGIN_PATH ") + SUFFUSE_EXECUTABLE + " schema > " +
                              (out / "schema.json").string();
  ASSERT_EQ(WEXITSTATUS(std::system(command.c_str())), 0);
  EXPECT_EQ(slurp(out / "schema.json"), slurp(suffuse::test::source_dir() / "share/schema/suffuse-schema.json"))
      << "regenerate it: ./build/bin/suffuse schema > share/schema/suffuse-schema.json";
}

}  // namespace

namespace {

// Every example scene is valid and takes a few steps without error: the
// examples cannot drift away from the code. Three explicit steps, one
// quasi-static step (a step of the levee section's flood is a dozen Newton
// iterations: its three took 96 s of the sanitized suite). One test per
// scene, EndToEnd/ExampleScene.Runs/<scene>, so that ctest runs them side
// by side (together they took 40 s of the sanitized suite, one after the
// other).
std::vector<std::string> example_scenes() {
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(suffuse::test::source_dir() / "share/scenes"))
    if (entry.path().extension() == ".json") names.push_back(entry.path().stem().string());
  std::sort(names.begin(), names.end());
  return names;
}

class ExampleScene : public testing::TestWithParam<std::string> {};

TEST_P(ExampleScene, Runs) {
  const fs::path file = suffuse::test::source_dir() / "share/scenes" / (GetParam() + ".json");
  auto j = suffuse::test::read_json(file);
  EXPECT_TRUE(j.contains("description") && j["description"].get<std::string>().size() > 80)
      << file << " needs a description of what it shows and how to read it";
  if (j.contains("path")) {  // an element test (suffuse element)
    suffuse::Registry registry;
    suffuse::PluginLoader loader(registry);
    const auto scene =
        suffuse::parse_element_scene(j.dump(), file.string(), file.parent_path(), registry, loader);
    std::ostringstream csv;
    for (std::size_t c = 0; c < scene.cases.size(); ++c)
      EXPECT_GT(suffuse::run_element_test(scene, c, registry, csv).increments, 0) << file;
    return;
  }
  j["outputs"] = nlohmann::json::array();
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);  // files a scene names are beside it (share/geometry/...)
  const suffuse::Scene scene = suffuse::parse_scene(j.dump(), file.string(), file.parent_path(), registry, loader);
  suffuse::Simulation sim(scene, registry);
  const int steps = scene.integration == suffuse::TimeIntegration::quasi_static ? 1 : 3;
  for (int k = 0; k < steps; ++k) sim.step();
  EXPECT_GT(sim.points().size(), 0u) << file;
}

// Test names take letters, digits and underscores only.
INSTANTIATE_TEST_SUITE_P(EndToEnd, ExampleScene, testing::ValuesIn(example_scenes()),
                         [](const testing::TestParamInfo<std::string>& info) {
                           std::string name = info.param;
                           for (char& c : name)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return name;
                         });

TEST(EndToEnd, ExampleScenesAreBundled) { EXPECT_GE(example_scenes().size(), 6u); }

}  // namespace

namespace {

// The cells of a CSV file as text, row by row.
std::vector<std::vector<std::string>> csv_cells(const fs::path& file) {
  std::ifstream in(file);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::stringstream s(line);
    for (std::string cell; std::getline(s, cell, ',');) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

// The default scene (suffusion column), cut to its first 8 s: the run prints
// the mass ledger, writes it as a CSV time series whose fines discharge
// through the top only grows and whose imbalance stays below 1e-10, and the
// frames carry the erosion fields.
TEST(EndToEnd, SuffusionColumnWritesItsLedger) {
  const fs::path out = fresh_dir("e2e_suffusion");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  j["time"]["end"] = 8.0;
  std::ofstream(out / "column.json") << j.dump(2);
  ASSERT_EQ(run("run " + (out / "column.json").string() + " --output " + out.string(), out / "log.txt"), 0)
      << slurp(out / "log.txt");
  const std::string log = slurp(out / "log.txt");
  EXPECT_NE(log.find("mass ledger"), std::string::npos) << log;
  EXPECT_NE(log.find("fines:  initial"), std::string::npos) << log;

  const auto rows = csv_cells(out / "column.ledger.csv");
  ASSERT_GT(rows.size(), 100u);
  const auto& header = rows.front();
  auto column = [&](const std::string& name) {  // by the name before its unit, "time [s]"
    const auto it = std::find_if(header.begin(), header.end(),
                                 [&](const std::string& h) { return h.substr(0, h.find(" [")) == name; });
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  };
  const std::size_t time = column("time"), out_top = column("fines_out_top"), fines = column("skeleton_fines"),
                    imbalance = column("fines_imbalance"), liquid = column("liquid_imbalance");
  double previous = 0;
  for (std::size_t r = 1; r < rows.size(); ++r) {
    ASSERT_EQ(rows[r].size(), header.size()) << "row " << r;
    EXPECT_GE(std::stod(rows[r][out_top]), previous) << "row " << r;
    previous = std::stod(rows[r][out_top]);
    EXPECT_LT(std::stod(rows[r][imbalance]), 1e-10) << "row " << r;
    EXPECT_LT(std::stod(rows[r][liquid]), 1e-10) << "row " << r;
  }
  EXPECT_DOUBLE_EQ(std::stod(rows.back()[time]), 8.0);
  EXPECT_LT(std::stod(rows.back()[fines]), std::stod(rows[1][fines])) << "fines were eroded";
  const double eroded = std::stod(rows.back()[column("eroded")]);
  EXPECT_GT(previous, 0.05 * eroded) << "fines left through the top";

  // The default scene's probe of the top: the ledger's discharge, to the last digit printed.
  const auto outflow = suffuse::test::read_csv(out / "column.outflow.csv");
  EXPECT_EQ(outflow.rows.back()[outflow.column("fines_discharged")],
            std::stod(rows.back()[out_top]) - std::stod(rows.back()[column("fines_in_top")]));

  const auto frames = read_pvd(out / "column.pvd", 0);
  ASSERT_FALSE(frames.empty());
  EXPECT_EQ(read_pvd(out / "column.pvd", 1).size(), frames.size()) << "a grid file with each frame of points";
  vtkNew<vtkXMLPolyDataReader> reader;
  reader->SetFileName((out / frames.back().file).c_str());
  reader->Update();
  for (const char* name : {"porosity", "fines_content", "concentration", "darcy_flux", "pore_pressure",
                           "eroded_fraction", "erosion_rate", "hydraulic_gradient", "hydraulic_conductivity"})
    EXPECT_NE(reader->GetOutput()->GetPointData()->GetArray(name), nullptr) << name;
}

}  // namespace

namespace {

// A named array of a VTK dataset's point or cell data, as doubles.
std::vector<double> vtk_values(vtkDataSetAttributes* data, const char* name) {
  vtkDataArray* a = data->GetArray(name);
  if (!a) return {};
  std::vector<double> v(static_cast<std::size_t>(a->GetNumberOfTuples() * a->GetNumberOfComponents()));
  for (vtkIdType t = 0; t < a->GetNumberOfTuples(); ++t)
    for (int c = 0; c < a->GetNumberOfComponents(); ++c)
      v[static_cast<std::size_t>(t * a->GetNumberOfComponents() + c)] = a->GetComponent(t, c);
  return v;
}

}  // namespace

// On a periodic grid (a saturated layer of level ground, two steps) the
// grid writer shows the seam's nodes once: the upper face's nodes carry
// the values of the lower face's, which they are (mass, velocity, pore
// pressure), not the part of them the points on one side give.
TEST(EndToEnd, GridWriterShowsAPeriodicGridsSeamNodesAsOne) {
  const fs::path out = fresh_dir("e2e_periodic_grid");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/infinite_slope.json");
  j.erase("factor_of_safety");
  j["gravity"] = {0.0, -9.81};  // level ground (saturated, the slope of atan(1/2) would slide)
  j["liquids"] = {{"water", {{"type", "phase/pore_liquid"}, {"density", 1000.0}, {"bulk_modulus", 2.2e9},
                             {"viscosity", 0.001}}}};
  j["materials"]["sand"]["density"] = 2650.0;
  j["materials"]["sand"]["permeability"] = {{"type", "permeability/constant"}, {"hydraulic_conductivity", 1e-4}};
  j["bodies"][0]["liquid"] = "water";
  j["bodies"][0]["porosity"] = 0.4;
  j["time"]["end"] = 2000.0;
  j["time"]["dt"] = 1000.0;
  j["outputs"] = {{{"type", "writer/vtk_grid"}, {"interval", 1000.0}}};
  std::ofstream(out / "layer.json") << j.dump(2);
  ASSERT_EQ(run("run " + (out / "layer.json").string() + " --output " + out.string() + " --quiet", out / "log.txt"), 0)
      << slurp(out / "log.txt");
  const auto grid = read_pvd(out / "layer.pvd", 0);
  ASSERT_FALSE(grid.empty());
  vtkNew<vtkXMLImageDataReader> reader;
  reader->SetFileName((out / grid.back().file).c_str());
  reader->Update();
  vtkImageData* image = reader->GetOutput();
  ASSERT_EQ(image->GetNumberOfPoints(), 5 * 13);
  int compared = 0;
  for (const char* name : {"mass", "velocity", "pore_pressure"}) {
    const auto v = vtk_values(image->GetPointData(), name);
    const std::size_t k = v.size() / 65;
    for (int row = 0; row < 13; ++row)
      for (std::size_t c = 0; c < k; ++c) {
        EXPECT_EQ(v[(row * 5 + 4) * k + c], v[(row * 5) * k + c]) << name << " at row " << row;
        compared += v[(row * 5) * k + c] != 0;
      }
  }
  EXPECT_GT(compared, 20);
}

// writer/vtk_grid on steady upward seepage (share/scenes/upward_seepage.json):
// its nodal Darcy flux and pore pressure against the closed form (tolerances
// of TwoPhase.SteadyUpwardSeepage, which checks the points), its cell
// averages against the points' own values recomputed here, and both writers
// as two parts of one .pvd at the same times.
TEST(EndToEnd, GridWriterOnSteadyUpwardSeepage) {
  const fs::path out = fresh_dir("e2e_grid");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/upward_seepage.json");
  j["outputs"] = {{{"type", "writer/vtk_particles"}, {"interval", 0.3}},
                  {{"type", "writer/vtk_grid"}, {"interval", 0.3}, {"cell_fields", {"porosity", "darcy_flux"}}}};
  std::ofstream(out / "seep.json") << j.dump(2);
  ASSERT_EQ(run("run " + (out / "seep.json").string() + " --output " + out.string() + " --quiet", out / "log.txt"), 0)
      << slurp(out / "log.txt");
  const auto points = read_pvd(out / "seep.pvd", 0), grid = read_pvd(out / "seep.pvd", 1);
  ASSERT_EQ(points.size(), 3u);
  ASSERT_EQ(grid.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) EXPECT_EQ(points[k].time, grid[k].time);

  vtkNew<vtkXMLImageDataReader> image_reader;
  image_reader->SetFileName((out / grid.back().file).c_str());
  image_reader->Update();
  vtkImageData* image = image_reader->GetOutput();
  ASSERT_EQ(image->GetNumberOfPoints(), 2 * 56);
  ASSERT_EQ(image->GetNumberOfCells(), 55);
  const suffuse::test::UpwardSeepage seepage;
  const double q_exact = seepage.flux();
  const auto q = vtk_values(image->GetPointData(), "darcy_flux");
  const auto p = vtk_values(image->GetPointData(), "pore_pressure");
  ASSERT_EQ(q.size(), 3u * 112);
  ASSERT_EQ(p.size(), 112u);
  ASSERT_FALSE(vtk_values(image->GetPointData(), "velocity").empty());
  ASSERT_FALSE(vtk_values(image->GetPointData(), "liquid_velocity").empty());
  double q_worst = 0, p_worst = 0;
  int checked = 0;
  for (vtkIdType n = 0; n < image->GetNumberOfPoints(); ++n) {
    double xyz[3];
    image->GetPoint(n, xyz);
    // Below the outlet cells (docs/two-phase.md) and above the base node row.
    if (xyz[1] < 0.02 || xyz[1] > 0.9) continue;
    q_worst = std::max(q_worst, std::abs(q[3 * n + 1] - q_exact) / q_exact);
    p_worst = std::max(p_worst, std::abs(p[n] - seepage.pressure(xyz[1])) / seepage.pressure(0));
    ++checked;
  }
  EXPECT_GT(checked, 80);
  EXPECT_LT(q_worst, 0.01);
  EXPECT_LT(p_worst, 0.02);

  // Cell averages: recomputed from the last frame of the points.
  vtkNew<vtkXMLPolyDataReader> point_reader;
  point_reader->SetFileName((out / points.back().file).c_str());
  point_reader->Update();
  vtkPolyData* poly = point_reader->GetOutput();
  const auto volume = vtk_values(poly->GetPointData(), "volume");
  const auto porosity = vtk_values(poly->GetPointData(), "porosity");
  const auto flux = vtk_values(poly->GetPointData(), "darcy_flux");
  ASSERT_FALSE(volume.empty());
  std::vector<double> weight(55), n_mean(55), qy_mean(55), count(55);
  for (vtkIdType k = 0; k < poly->GetNumberOfPoints(); ++k) {
    double xyz[3];
    poly->GetPoint(k, xyz);
    const auto cell = static_cast<std::size_t>(std::clamp(static_cast<int>(std::floor(xyz[1] / 0.02)), 0, 54));
    weight[cell] += volume[k];
    n_mean[cell] += volume[k] * porosity[k];
    qy_mean[cell] += volume[k] * flux[3 * k + 1];
    count[cell] += 1;
  }
  const auto cell_n = vtk_values(image->GetCellData(), "porosity");
  const auto cell_q = vtk_values(image->GetCellData(), "darcy_flux");
  const auto cell_count = vtk_values(image->GetCellData(), "point_count");
  ASSERT_EQ(cell_n.size(), 55u);
  ASSERT_EQ(cell_q.size(), 3u * 55);
  double total = 0;
  for (std::size_t c = 0; c < 55; ++c) {
    total += cell_count[c];
    EXPECT_EQ(cell_count[c], count[c]) << "cell " << c;
    if (weight[c] == 0) continue;
    EXPECT_NEAR(cell_n[c], n_mean[c] / weight[c], 1e-12) << "cell " << c;
    EXPECT_NEAR(cell_q[3 * c + 1], qy_mean[c] / weight[c], 1e-14) << "cell " << c;
  }
  EXPECT_EQ(total, static_cast<double>(poly->GetNumberOfPoints()));
}

// A grid writer asked for a point field the run lacks is refused at validation.
TEST(EndToEnd, GridWriterRefusesAMissingCellField) {
  const fs::path out = fresh_dir("e2e_grid_missing");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  j["outputs"] = {{{"type", "writer/vtk_grid"}, {"cell_fields", {"fines_content"}}}};
  std::ofstream(out / "bar.json") << j.dump(2);
  EXPECT_EQ(run("validate " + (out / "bar.json").string(), out / "log.txt"), 1);
  EXPECT_NE(slurp(out / "log.txt").find("reads point field 'fines_content', which this scene does not provide"),
            std::string::npos)
      << slurp(out / "log.txt");
}

// SIGTERM (or SIGINT) during a run: the step finishes, every output is
// closed with a frame at that time, a checkpoint is written, the exit status
// is 128 + the signal; the run then continues from the checkpoint to its end.
TEST(EndToEnd, TerminatedRunClosesItsOutputsAndResumes) {
  const fs::path out = fresh_dir("e2e_signal");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  // 2 s: a signal at the third frame (0.5 s) leaves three quarters of the
  // run to resume (0.7 s of the Release build's 0.9, 8 s sanitized).
  j["time"]["end"] = 2.0;
  for (auto& o : j["outputs"]) o["interval"] = 0.25;
  std::ofstream(out / "column.json") << j.dump(2);
  const std::string exe = SUFFUSE_EXECUTABLE, scene = (out / "column.json").string(), dir = out.string();
  const char* argv[] = {exe.c_str(), "run", scene.c_str(), "--output", dir.c_str(), "--quiet", nullptr};
  pid_t pid = 0;
  ASSERT_EQ(posix_spawn(&pid, exe.c_str(), nullptr, nullptr, const_cast<char* const*>(argv), environ), 0);
  // Signal once a few frames are out (the run is then well inside its loop).
  for (int i = 0; i < 600 && !fs::exists(out / "column_000002.vtp"); ++i) usleep(50000);
  ASSERT_TRUE(fs::exists(out / "column_000002.vtp")) << "the run did not start";
  kill(pid, SIGTERM);
  int status = 0;
  ASSERT_EQ(waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFEXITED(status)) << "killed instead of stopping";
  EXPECT_EQ(WEXITSTATUS(status), 128 + SIGTERM);

  // Every listed file is there and readable, the last frame is the stop time.
  const auto points = read_pvd(out / "column.pvd", 0), grid = read_pvd(out / "column.pvd", 1);
  ASSERT_GE(points.size(), 3u);
  ASSERT_EQ(grid.size(), points.size());
  ASSERT_LT(points.back().time, 2.0) << "the signal came before the end";
  for (const Frame& f : points) {
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((out / f.file).c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 640) << f.file;
  }
  const auto ledger = suffuse::test::read_csv(out / "column.ledger.csv");
  EXPECT_NEAR(ledger.rows.back()[0], points.back().time, 1e-12) << "a ledger row at the stop";
  ASSERT_TRUE(fs::exists(out / "column.checkpoint"));

  ASSERT_EQ(run("run " + scene + " --output " + dir + " --quiet --restart " + (out / "column.checkpoint").string(),
                out / "log.txt"),
            0)
      << slurp(out / "log.txt");
  const auto resumed = read_pvd(out / "column.pvd", 0);
  EXPECT_NEAR(resumed.back().time, 2.0, 1e-12);
  for (std::size_t k = 1; k < resumed.size(); ++k) EXPECT_GT(resumed[k].time, resumed[k - 1].time) << "each time once";
}

// Scenes that validate but cannot run well are refused before they allocate
// or step: memory beyond the machine, a fixed step above the stable one, a
// run of absurd length; a run that blows up anyway stops naming the point.
TEST(EndToEnd, ScenesThatCannotRunAreRefusedWithAnEstimate) {
  const fs::path out = fresh_dir("e2e_cannot_run");
  const auto bar = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  auto refused = [&](const nlohmann::json& j, const std::string& name) {
    std::ofstream(out / (name + ".json")) << j.dump(2);
    EXPECT_EQ(run("run " + (out / (name + ".json")).string() + " --quiet --output " + (out / name).string(),
                  out / (name + ".log")),
              1)
        << name;
    return slurp(out / (name + ".log"));
  };
  auto huge = bar;
  huge["grid"]["cells"] = {20000, 20000};
  huge["grid"]["cell_size"] = {1e-4, 1e-4};
  huge["bodies"][0]["max"] = {1.0, 1.0};
  EXPECT_NE(refused(huge, "huge").find("this scene needs about 463 GiB (4e+08 material points, 4e+08 grid nodes), more than"),
            std::string::npos)
      << slurp(out / "huge.log");
  EXPECT_FALSE(fs::exists(out / "huge")) << "nothing written";
  auto big_step = bar;
  big_step["time"]["dt"] = 0.002;  // four times the stable 5e-4 s
  EXPECT_NE(refused(big_step, "big_step").find("/time/dt = 0.002 s is above this scene's stable time step, 0.0005 s"),
            std::string::npos);
  auto stiff = bar;
  stiff["materials"]["steel_like"]["youngs_modulus"] = 1e300;
  EXPECT_NE(refused(stiff, "stiff").find("the run would take 1.51789327688e+149 steps"), std::string::npos);
  EXPECT_EQ(run("validate " + (out / "stiff.json").string(), out / "validate.log"), 1) << "validate says it too";
  EXPECT_NE(slurp(out / "validate.log").find("the run would take 1.51789327688e+149 steps"), std::string::npos);
  EXPECT_EQ(run("validate " + (suffuse::test::source_dir() / "share/scenes/elastic_bar.json").string(),
                out / "validate.log"),
            0);
  EXPECT_NE(slurp(out / "validate.log").find("  run: 80 material points, dt = 0.00025 s (automatic), 480 steps to t = 0.12 s"),
            std::string::npos)
      << slurp(out / "validate.log");
  auto blowing = big_step;
  blowing["time"]["dt_above_stable"] = true;
  EXPECT_NE(refused(blowing, "blowing").find("the run blew up at step 5 (t = 0.01 s): material point 2 (id 2) of body 'bar'"),
            std::string::npos)
      << slurp(out / "blowing.log");
  // Liquid forced in at 1000 m/s crosses cells in a step: the transport would no longer conserve its volume.
  auto gush = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/upward_seepage.json");
  nlohmann::json bcs = nlohmann::json::array();
  for (const auto& bc : gush["boundary_conditions"])
    if (!(bc["type"] == "bc/pore_pressure" && bc.value("face", "") == "bottom")) bcs.push_back(bc);
  bcs.push_back({{"type", "bc/inflow_flux"}, {"face", "bottom"}, {"flux", 1000.0}});
  gush["boundary_conditions"] = bcs;
  EXPECT_NE(refused(gush, "gush").find("darcy_flux = 750, the pore liquid crosses more than half a cell in one step"),
            std::string::npos)
      << slurp(out / "gush.log");
  const auto frames = read_pvd(out / "blowing" / "blowing.pvd");
  ASSERT_FALSE(frames.empty()) << "the frames before the blow-up stay listed";
  EXPECT_TRUE(fs::exists(out / "blowing" / frames.back().file));
}

// A phase that throws, or returns a stress that is not finite: the run stops
// naming the plugin (or the point and field), the step and the points; the
// frames written before stay listed and readable.
TEST(EndToEnd, FailingPluginIsNamedAndOutputsStayReadable) {
  const fs::path out = fresh_dir("e2e_failing");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/elastic_bar.json");
  j["plugin_paths"] = {std::string(SUFFUSE_TEST_PLUGIN_DIR) + "/failing"};
  j["materials"]["steel_like"] = {{"type", "phase/test_failing"}, {"failure", "throw"}};
  std::ofstream(out / "throws.json") << j.dump(2);
  j["materials"]["steel_like"]["failure"] = "nan";
  std::ofstream(out / "nan.json") << j.dump(2);
  for (const char* name : {"throws", "nan"}) {
    const fs::path scene = out / (std::string(name) + ".json"), dir = out / name;
    EXPECT_EQ(run("run " + scene.string() + " --quiet --output " + dir.string(), out / "log.txt"), 1) << name;
    const std::string log = slurp(out / "log.txt");
    if (std::string(name) == "throws")
      EXPECT_NE(log.find("step 1 (t = 0 s), stage stress: phase phase/test_failing of material 'steel_like' "
                         "(/materials/steel_like) failed on material points 0 to 79 of body 'bar': the test phase fails"),
                std::string::npos)
          << log;
    else
      EXPECT_NE(log.find("the run blew up at step 1 (t = 0.000790569 s): material point 79 (id 79) of body 'bar' at "
                         "(0.987508, 0.0375), material 'steel_like' (phase/test_failing): stress = NaN, not finite"),
                std::string::npos)
          << log;
    const auto frames = read_pvd(dir / (std::string(name) + ".pvd"));
    ASSERT_EQ(frames.size(), 1u) << "the initial frame, listed";
    vtkNew<vtkXMLPolyDataReader> reader;
    reader->SetFileName((dir / frames[0].file).c_str());
    reader->Update();
    EXPECT_EQ(reader->GetOutput()->GetNumberOfPoints(), 80);
  }
}

// An erosion law, a permeability law or a boundary condition that throws
// during a step: the run stops naming the plugin, its material (or the
// condition's pointer), the step and stage, and the points of the batch.
TEST(EndToEnd, FailingLawOrConditionIsNamedWithItsMaterialAndStep) {
  const fs::path out = fresh_dir("e2e_failing_laws");
  const auto column = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  const std::string material = "/materials/gap_graded_sand";
  struct Case {
    std::string name;
    nlohmann::json scene;
    std::vector<std::string> said;  // pieces of the message, in order
  };
  std::vector<Case> cases;
  auto scene = [&] {
    auto j = column;
    j["plugin_paths"] = {std::string(SUFFUSE_TEST_PLUGIN_DIR) + "/failing"};
    j["time"]["end"] = 2.0;
    j["outputs"] = nlohmann::json::array();
    return j;
  };
  auto erosion = scene();
  erosion["materials"]["gap_graded_sand"]["erosion"] = {{"type", "erosion/test_failing"}};
  cases.push_back({"erosion", erosion,
                   {"error: step 1 (t = 0 s), stage erosion: erosion law erosion/test_failing of material "
                    "'gap_graded_sand' (" + material + "/erosion) failed on material points 0 to ",
                    " of body 'column': the test erosion law fails"}});
  auto permeability = scene();
  permeability["materials"]["gap_graded_sand"]["permeability"] = {
      {"type", "permeability/test_failing"}, {"hydraulic_conductivity", 0.04}, {"fail_above_porosity", 0.3001}};
  cases.push_back({"permeability", permeability,
                   {"error: step ", "stage permeability: permeability law permeability/test_failing of material "
                    "'gap_graded_sand' (" + material + "/permeability) failed on material points ",
                    " of body 'column': the test permeability law fails at porosity 0.300"}});
  auto condition = scene();
  condition["boundary_conditions"].push_back({{"type", "bc/test_failing"}, {"fail_at", 0.01}});
  const std::string pointer = "/boundary_conditions/" + std::to_string(condition["boundary_conditions"].size() - 1);
  cases.push_back({"condition", condition,
                   {"error: step ", "), stage grid: boundary condition bc/test_failing (" + pointer +
                    ") failed: the test condition fails"}});
  for (const Case& c : cases) {
    const fs::path file = out / (c.name + ".json");
    std::ofstream(file) << c.scene.dump(2);
    EXPECT_EQ(run("run " + file.string() + " --quiet --output " + (out / c.name).string(), out / "log.txt"), 1)
        << c.name;
    const std::string log = slurp(out / "log.txt");
    std::size_t at = 0;
    for (const std::string& piece : c.said) {
      at = log.find(piece, at);
      ASSERT_NE(at, std::string::npos) << c.name << ": " << piece << "\nin: " << log;
    }
  }
}

// Every CSV column and every VTK array of a run says its unit
// (docs/outputs.md, Units): the probes, the ledger, the reactions, the
// element tests, the points' and the grid's arrays. In 2D, masses are per
// metre of thickness.
TEST(EndToEnd, EveryOutputSaysItsUnits) {
  const fs::path out = fresh_dir("e2e_units");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  j["time"]["end"] = 0.05;
  j["boundary_conditions"][0]["reaction"] = "base";
  j["outputs"] = {{{"type", "writer/vtk_particles"}},
                  {{"type", "writer/vtk_grid"}},
                  {{"type", "writer/csv_probe"}, {"name", "top"}, {"face", "top"}, {"fields", {"fines_discharged"}}},
                  {{"type", "writer/csv_probe"}, {"name", "point"}, {"at", {0.02, 0.2}},
                   {"fields", {"displacement", "porosity", "skeleton_fines", "stress"}}},
                  {{"type", "writer/csv_probe"}, {"name", "box"}, {"box_min", {0, 0}}, {"box_max", {0.04, 0.1}},
                   {"fields", {"liquid_mass"}}, {"reduce", "sum"}}};
  std::ofstream(out / "column.json") << j.dump(2);
  ASSERT_EQ(run("run " + (out / "column.json").string() + " --quiet --output " + (out / "run").string(),
                out / "log.txt"),
            0)
      << slurp(out / "log.txt");
  ASSERT_EQ(run("element " + (suffuse::test::source_dir() / "share/scenes/triaxial_mcc.json").string() +
                    " --quiet --output " + (out / "run").string(),
                out / "element.log"),
            0)
      << slurp(out / "element.log");

  const std::regex with_unit(R"(^[^\[\]]+ \[[^\[\]]+\]$)");
  std::map<std::string, std::string> units;  // "file: column" -> unit, for the spot checks below
  std::size_t csvs = 0, arrays = 0;
  for (const auto& e : fs::directory_iterator(out / "run")) {
    const fs::path file = e.path();
    const std::string name = file.filename();
    if (file.extension() == ".csv") {
      ++csvs;
      std::istringstream header(slurp(file).substr(0, slurp(file).find('\n')));
      for (std::string cell; std::getline(header, cell, ',');) {
        EXPECT_TRUE(std::regex_match(cell, with_unit)) << name << ": column \"" << cell << "\" gives no unit";
        const std::size_t bracket = cell.find(" [");
        if (bracket != std::string::npos) units[name + ": " + cell.substr(0, bracket)] = cell.substr(bracket + 2, cell.size() - bracket - 3);
      }
    }
    vtkDataSet* data = nullptr;
    vtkNew<vtkXMLPolyDataReader> points;
    vtkNew<vtkXMLImageDataReader> grid;
    if (file.extension() == ".vtp") {
      points->SetFileName(file.c_str());
      points->Update();
      data = points->GetOutput();
    } else if (file.extension() == ".vti") {
      grid->SetFileName(file.c_str());
      grid->Update();
      data = grid->GetOutput();
    }
    if (!data) continue;
    for (vtkFieldData* fields : {static_cast<vtkFieldData*>(data->GetPointData()),
                                 static_cast<vtkFieldData*>(data->GetCellData())})
      for (int a = 0; a < fields->GetNumberOfArrays(); ++a) {
        vtkAbstractArray* array = fields->GetAbstractArray(a);
        ++arrays;
        vtkInformation* info = array->GetInformation();
        const char* unit = info->Has(vtkDataArray::UNITS_LABEL()) ? info->Get(vtkDataArray::UNITS_LABEL()) : nullptr;
        ASSERT_TRUE(unit && *unit) << name << ": array " << array->GetName() << " gives no unit";
        units[std::string(file.extension() == ".vtp" ? "points" : "grid") + ": " + array->GetName()] = unit;
      }
  }
  EXPECT_EQ(csvs, 6u) << "ledger, reactions, three probes, the element test";
  EXPECT_GT(arrays, 20u);
  EXPECT_EQ(units["column.ledger.csv: skeleton_fines"], "kg/m");
  EXPECT_EQ(units["column.ledger.csv: fines_imbalance"], "-");
  EXPECT_EQ(units["column.box.csv: liquid_mass"], "kg/m");
  EXPECT_EQ(units["column.point.csv: skeleton_fines"], "kg/m");
  EXPECT_EQ(units["points: mass"], "kg/m");
  EXPECT_EQ(units["points: volume"], "m^2");
  EXPECT_EQ(units["points: porosity"], "-");
  EXPECT_EQ(units["grid: mass"], "kg/m");
  EXPECT_EQ(units["grid: pore_pressure"], "Pa");
  EXPECT_EQ(units["grid: point_count"], "-");
  EXPECT_EQ(units["triaxial_mcc.element.csv: increment"], "-");
}

// Warnings reach the user whatever --quiet says (on standard error): a body
// whose fines, washed out, would leave porosity 0.999.
TEST(EndToEnd, WarningsAreGivenUnderQuiet) {
  const fs::path out = fresh_dir("e2e_quiet_warning");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/suffusion_column.json");
  j["bodies"][0]["porosity"] = 0.9;
  j["bodies"][0]["fines_content"] = 0.99;
  j["time"]["end"] = 0.001;
  j["outputs"] = nlohmann::json::array();
  std::ofstream(out / "open.json") << j.dump(2);
  run("run " + (out / "open.json").string() + " --quiet --output " + (out / "run").string(), out / "log.txt");
  EXPECT_NE(slurp(out / "log.txt").find("warning: body 'column': washing out its erodible fines (fines_content 0.99"),
            std::string::npos)
      << slurp(out / "log.txt");
}

// --newton prints each quasi-static step's residuals: Terzaghi's column in
// two quasi-static steps, each line ending below the Newton tolerance
// (1e-8 of the forces) after a larger first residual.
TEST(EndToEnd, NewtonOptionPrintsEachQuasiStaticStep) {
  const fs::path out = fresh_dir("e2e_newton");
  auto j = suffuse::test::read_json(suffuse::test::source_dir() / "share/scenes/terzaghi.json");
  j.erase("damping");
  j["time"] = {{"end", 0.1}, {"integration", "quasi_static"}, {"dt", 0.05}};
  j["outputs"] = nlohmann::json::array();
  std::ofstream(out / "column.json") << j.dump(2);
  ASSERT_EQ(run("run " + (out / "column.json").string() + " --newton --quiet --output " + (out / "run").string(),
                out / "log.txt"),
            0)
      << slurp(out / "log.txt");
  std::istringstream log(slurp(out / "log.txt"));
  std::vector<std::vector<double>> steps;
  for (std::string line; std::getline(log, line);) {
    if (line.rfind("newton: step ", 0) != 0) continue;
    std::istringstream values(line.substr(line.find("s:") + 2));
    steps.emplace_back(std::istream_iterator<double>(values), std::istream_iterator<double>());
  }
  ASSERT_EQ(steps.size(), 2u) << slurp(out / "log.txt");
  for (const auto& r : steps) {
    ASSERT_GE(r.size(), 2u);
    EXPECT_LT(r.back(), 1e-8);
    EXPECT_GT(r.front(), r.back());
  }
}

// A quasi-static run on linear shape functions whose points moved more than
// a cell is warned about (docs/time-integration.md, Limits), under --quiet
// too; the same run on GIMP is not: a soft elastic block 1 m high settling
// about 0.2 m on 0.1 m cells.
TEST(EndToEnd, LargeStrainsOnLinearShapeFunctionsAreWarnedAbout) {
  const fs::path out = fresh_dir("e2e_linear_large_strain");
  auto j = nlohmann::json::parse(R"({
    "dimension": 2, "gravity": [0.0, 0.0],
    "grid": {"origin": [0.0, 0.0], "cell_size": [0.1, 0.1], "cells": [4, 11]},
    "shape_function": {"type": "shape/linear"},
    "materials": {"soft": {"type": "phase/linear_elastic", "density": 1000.0, "youngs_modulus": 1e5,
      "poisson_ratio": 0.3}},
    "bodies": [{"name": "block", "material": "soft", "min": [0.0, 0.0], "max": [0.4, 1.0], "points_per_cell": 2}],
    "boundary_conditions": [
      {"type": "bc/traction", "box_min": [0.0, 1.0], "box_max": [0.4, 1.0], "traction": [0.0, -30000.0],
       "factor": [[0, 0], [1, 1]]},
      {"type": "bc/velocity", "face": "left", "vx": 0.0},
      {"type": "bc/velocity", "face": "right", "vx": 0.0},
      {"type": "bc/velocity", "face": "bottom", "vx": 0.0, "vy": 0.0}],
    "time": {"end": 1.0, "integration": "quasi_static", "dt": 0.1},
    "outputs": []})");
  for (const char* shape : {"shape/linear", "shape/gimp"}) {
    j["shape_function"]["type"] = shape;
    std::ofstream(out / "block.json") << j.dump(2);
    ASSERT_EQ(run("run " + (out / "block.json").string() + " --quiet --output " + (out / "run").string(),
                  out / "log.txt"),
              0)
        << slurp(out / "log.txt");
    const bool warned = slurp(out / "log.txt").find("in a quasi-static run on shape/linear") != std::string::npos;
    EXPECT_EQ(warned, std::string(shape) == "shape/linear") << shape << ": " << slurp(out / "log.txt");
  }
}
