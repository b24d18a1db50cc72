// Runs on many processes (issue 18, docs/parallel.md): `mpirun -np N suffuse
// run` equals the serial run bit for bit (the checkpoint holds every point
// field, the ledger's boundary sums and the clock), on scenes whose
// scatters take each of the core's two orders of summation, with processes
// that own no point. Quasi-static runs, whose solves go through PETSc, are
// close to the serial run to a stated tolerance (refused by name in builds
// without PETSc).
// Built when CMake finds MPI; run with mpirun --oversubscribe (2 cores here).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using suffuse::test::fresh_dir;
using nlohmann::json;

using suffuse::test::slurp;

// `suffuse run` of `scene` into `out` on `processes` processes (1: without
// mpirun), `threads` threads each; its exit status, its output in out/log.
int run(const fs::path& scene, const fs::path& out, int processes, int threads = 1) {
  fs::create_directories(out);
  std::string command;
  // Processes that disagree wait for each other for ever: ended after 10
  // minutes (exit status 124), not at CI's limit.
  if (processes > 1)
    command = std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 timeout 600 ") + SUFFUSE_MPIEXEC +
              " --oversubscribe -np " + std::to_string(processes) + " ";
  command += std::string(SUFFUSE_EXECUTABLE) + " run " + scene.string() + " --output " + out.string() +
             " --threads " + std::to_string(threads) + " > " + (out / "log").string() + " 2>&1";
  return WEXITSTATUS(std::system(command.c_str()));
}

json scene_file(const std::string& name) {
  std::ifstream in(fs::path(SUFFUSE_SOURCE_DIR) / "share" / "scenes" / (name + ".json"));
  return json::parse(in);
}

fs::path write_scene(const fs::path& dir, const std::string& name, const json& scene) {
  const fs::path file = dir / (name + ".json");
  std::ofstream(file) << scene.dump(1);
  return file;
}

// The last row of a ledger CSV, as numbers.
std::vector<double> last_ledger_row(const fs::path& csv) {
  std::ifstream in(csv);
  std::string line, last;
  while (std::getline(in, line))
    if (!line.empty()) last = line;
  std::vector<double> values;
  std::stringstream cells(last);
  for (std::string cell; std::getline(cells, cell, ',');) values.push_back(std::stod(cell));
  return values;
}

// Every file the serial run of `name` wrote is, byte for byte, the one each
// run on `counts` processes wrote (fresh_dir("parallel_" + name), expect_equal_to_serial);
// returns how many files were compared.
std::size_t expect_every_file_equal(const std::string& name, const std::vector<int>& counts) {
  const fs::path dir = fs::temp_directory_path() / ("suffuse_parallel_" + name);
  std::size_t files = 0;
  for (const auto& entry : fs::directory_iterator(dir / "serial")) {
    const std::string file = entry.path().filename().string();
    if (file == "log" || file.ends_with(".run.json")) continue;  // these say how it ran
    ++files;
    for (int n : counts) {
      const fs::path other = dir / ("np" + std::to_string(n)) / file;
      EXPECT_TRUE(slurp(entry.path()) == slurp(other)) << file << " on " << n << " processes";
    }
  }
  return files;
}

// Runs `scene` serially and on each process count; every run's checkpoint
// must be the serial one, byte for byte.
void expect_equal_to_serial(const std::string& name, const json& scene, const std::vector<int>& counts) {
  const fs::path dir = fresh_dir("parallel_" + name);
  const fs::path file = write_scene(dir, name, scene);
  ASSERT_EQ(run(file, dir / "serial", 1), 0) << slurp(dir / "serial" / "log");
  const std::string serial = slurp(dir / "serial" / (name + ".checkpoint"));
  ASSERT_GT(serial.size(), 1000u);
  for (int n : counts) {
    const fs::path out = dir / ("np" + std::to_string(n));
    ASSERT_EQ(run(file, out, n), 0) << slurp(out / "log");
    EXPECT_NE(slurp(out / "log").find(std::to_string(n) + " processes"), std::string::npos) << slurp(out / "log");
    if (fs::exists(dir / "serial" / (name + ".run.json"))) {  // written with other outputs
      const json info = json::parse(slurp(out / (name + ".run.json")));
      EXPECT_EQ(info.at("processes").get<int>(), n);
    }
    EXPECT_TRUE(slurp(out / (name + ".checkpoint")) == serial) << name << " on " << n << " processes";
    // The ledger's totals add the chunks' sums in chunk order: the same rows.
    if (fs::exists(dir / "serial" / (name + ".ledger.csv"))) {
      EXPECT_TRUE(slurp(out / (name + ".ledger.csv")) == slurp(dir / "serial" / (name + ".ledger.csv"))) << name;
    }
  }
}

// One scatter chunk: the last process holds every point, the others none.
TEST(Parallel, ElasticBarEqualsSerialWithProcessesThatOwnNoPoint) {
  expect_equal_to_serial("elastic_bar", scene_file("elastic_bar"), {2, 4});
}

// The default suffusion column: one chunk, on the last process; the others
// (the first, which writes, among them) hold no point but take part in
// every exchange. Every file its six
// writers write (points, grid, probes, ledger) is the serial run's.
TEST(Parallel, DefaultColumnAndEveryOutputEqualSerial) {
  json scene = scene_file("suffusion_column");
  scene["time"]["end"] = 2.0;
  for (json& out : scene["outputs"])
    if (out.contains("interval")) out["interval"] = 0.5;
  expect_equal_to_serial("suffusion_column", scene, {2, 4});
  EXPECT_GE(expect_every_file_equal("suffusion_column", {2, 4}), 16u)
      << "checkpoint, ledger, .pvd, 2 x 5 frames, 4 probes";
}

// Pores that drain above the phreatic surface (docs/phreatic.md, Explicit
// runs): a sand column full of water draining through its base, split
// across its height. The suction's nodal projection, the free surfaces
// closed to inflow and the drain's hold on the suction read nodes other
// processes' points reach: every file is the serial run's.
TEST(Parallel, DrainingColumnEqualsSerial) {
  json scene = suffuse::test::draining_column(0.1, 1e-2);
  scene["bodies"][0]["water_table"] = 0.7;
  scene["time"]["end"] = 1.0;
  scene["outputs"] = {{{"type", "writer/vtk_particles"}, {"interval", 0.5}}};
  expect_equal_to_serial("draining_column", scene, {2, 3});
  EXPECT_GE(expect_every_file_equal("draining_column", {2, 3}), 5u) << "checkpoint, ledger, .pvd, 3 frames";
}

// 99,840 points in 49 chunks, GIMP, two phases, erosion and transport of the
// fines: scatters whose even chunks (and odd ones) touch no common node.
// Each process updates only the nodes its points reach and a halo, so every
// sum over nodes (the ledger's outflow at the top and through the free
// surface, the reaction at the base) and every grid output (fields, a probe
// integrating the Darcy flux over the top face) takes each node from the
// process that owns it: every file is the serial run's.
TEST(Parallel, ErodingColumnAndItsGridOutputsEqualSerial) {
  json scene = scene_file("bench_suffusion_column");
  scene["time"]["end"] = 0.002;
  scene["boundary_conditions"][0]["reaction"] = "base";
  scene["outputs"] = {
      {{"type", "writer/vtk_grid"}, {"interval", 0.001}},
      {{"type", "writer/csv_probe"}, {"name", "top"}, {"face", "top"}, {"fields", {"darcy_flux", "fines_discharged"}}},
      {{"type", "writer/csv_probe"}, {"name", "inside"}, {"at", {4.0, 5.0}}, {"fields", {"pore_pressure"}}},
  };
  expect_equal_to_serial("eroding_column", scene, {2, 3});
  EXPECT_GE(expect_every_file_equal("eroding_column", {2, 3}), 9u)
      << "checkpoint, ledger, reactions, .pvd, 3 grid frames, 2 probes";
}

// The footing on Tresca clay, 12,800 points in 7 chunks: the reactions of
// the footing's nodes (all reached by the last process's points only) and
// of the left face's (reached by every process's, the nodes between them by
// two), and the volumetric strain averaged per cell (a scatter into cells).
TEST(Parallel, FootingReactionsEqualSerial) {
  json scene = scene_file("footing_mc");
  scene["bodies"][0]["points_per_cell"] = 4;
  scene["boundary_conditions"][1]["reaction"] = "left";
  scene["time"]["end"] = 0.05;
  scene["outputs"] = json::array();
  expect_equal_to_serial("footing", scene, {2, 3});
  EXPECT_GE(expect_every_file_equal("footing", {2, 3}), 2u) << "checkpoint, reactions";
}

// A block thrown at the floor: every point travels across the nodes other
// processes' points held at the start (a process's nodes follow its points),
// then the block hits the floor.
TEST(Parallel, FallingBlockEqualsSerial) {
  json scene = scene_file("bench_column");
  scene["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.05, 0.05}}, {"cells", {80, 80}}};
  scene["shape_function"]["type"] = "shape/linear";
  scene["bodies"][0]["min"] = {0.0, 1.5};
  scene["bodies"][0]["max"] = {4.0, 3.5};
  scene["bodies"][0]["velocity"] = {0.0, -10.0};
  scene["time"]["end"] = 0.2;
  expect_equal_to_serial("falling_block", scene, {2, 3});
#ifdef SUFFUSE_TEST_THREADS
  // Threads within processes: each process's loops split its points (6,400
  // each) and its nodes where each thread gets 1,024 of them.
  const fs::path dir = fs::temp_directory_path() / "suffuse_parallel_falling_block";
  ASSERT_EQ(run(dir / "falling_block.json", dir / "np2x2", 2, 2), 0) << slurp(dir / "np2x2" / "log");
  EXPECT_TRUE(slurp(dir / "np2x2" / "falling_block.checkpoint") == slurp(dir / "serial" / "falling_block.checkpoint"));
#endif
}

// A saturated block falling onto the floor, a grid frame every step: its
// outer points cross node lines within steps, so the nodes the step's shape
// functions reached (where the Darcy flux is the step's) are not those the
// frame's projection reaches. Every frame and the face probe of the Darcy
// flux are the serial run's.
TEST(Parallel, SaturatedFallingBlockGridFramesEqualSerial) {
  json scene = scene_file("bench_suffusion_column");
  scene["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.05, 0.05}}, {"cells", {40, 80}}};
  scene["shape_function"]["type"] = "shape/linear";
  json& body = scene["bodies"][0];
  body["min"] = {0.0, 1.0};
  body["max"] = {2.0, 3.0};
  body["water_table"] = 3.0;
  body["velocity"] = {0.0, -5.0};
  scene["boundary_conditions"] = {{{"type", "bc/velocity"}, {"face", "bottom"}, {"vx", 0.0}, {"vy", 0.0}}};
  scene["time"]["end"] = 0.01;
  scene["outputs"] = {
      {{"type", "writer/vtk_grid"}, {"interval", 1e-7}},
      {{"type", "writer/csv_probe"}, {"name", "bottom"}, {"face", "bottom"}, {"fields", {"darcy_flux"}}},
  };
  expect_equal_to_serial("saturated_block", scene, {2, 3});
  EXPECT_GE(expect_every_file_equal("saturated_block", {2, 3}), 100u) << "a grid frame per step";
}

// 3D: 200,704 points, trilinear, two phases with erosion and transport.
TEST(Parallel, ErodingColumn3DEqualsSerial) {
  json scene = scene_file("bench_suffusion_column_3d");
  scene["time"]["end"] = 0.002;
  expect_equal_to_serial("eroding_column_3d", scene, {2, 4});
}

// 3D GIMP: a chunk spans less than two layers of cells, so chunks two apart
// share nodes and the scatters take the buffered order (executor.hpp).
TEST(Parallel, GimpBlock3DEqualsSerial) {
  json scene = scene_file("bench_column_3d");
  scene["grid"]["cells"] = {16, 16, 12};
  scene["bodies"][0]["max"] = {5.0, 5.0, 3.125};
  scene["shape_function"]["type"] = "shape/gimp";
  scene["time"]["end"] = 0.01;
  scene["outputs"] = {{{"type", "writer/vtk_particles"}, {"interval", 0.005}}};
  expect_equal_to_serial("gimp_block", scene, {2, 4});
}

// A checkpoint does not depend on the process count: a serial run's,
// continued on two processes, ends where the serial run does, bit for bit,
// and so does the first process's ledger CSV.
TEST(Parallel, RestartOnOtherProcessCountsContinuesExactly) {
  const fs::path dir = fresh_dir("parallel_restart");
  json scene = scene_file("bench_suffusion_column");
  scene["time"]["dt"] = 8e-5;  // the first run ends on a step, not on a shortened one
  scene["time"]["end"] = 0.002;
  const fs::path whole = write_scene(dir, "column", scene);
  ASSERT_EQ(run(whole, dir / "whole", 1), 0) << slurp(dir / "whole" / "log");
  scene["time"]["end"] = 12 * 8e-5;
  fs::create_directories(dir / "half");
  const fs::path half = write_scene(dir / "half", "column", scene);
  ASSERT_EQ(run(half, dir / "continued", 1), 0) << slurp(dir / "continued" / "log");
  const std::string checkpoint = (dir / "continued" / "column.checkpoint").string();
  const std::string command = std::string("OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 ") +
                              SUFFUSE_MPIEXEC + " --oversubscribe -np 2 " + SUFFUSE_EXECUTABLE + " run " +
                              whole.string() + " --output " + (dir / "continued").string() + " --restart " +
                              checkpoint + " > " + (dir / "restart.log").string() + " 2>&1";
  ASSERT_EQ(WEXITSTATUS(std::system(command.c_str())), 0) << slurp(dir / "restart.log");
  EXPECT_TRUE(slurp(dir / "continued" / "column.checkpoint") == slurp(dir / "whole" / "column.checkpoint"));
  EXPECT_DOUBLE_EQ(last_ledger_row(dir / "continued" / "column.ledger.csv")[0], 0.002);
  EXPECT_TRUE(slurp(dir / "continued" / "column.ledger.csv") == slurp(dir / "whole" / "column.ledger.csv"));
}

// A periodic grid's explicit steps (docs/boundaries.md, Periodic grids):
// the infinite slope's layer made elastic, 8 m long (2,560 points, 2 chunks
// of 2,048 and 512), settling for 0.5 s; each process adds its images to
// the nodes they are after its scatters, as the serial run does.
TEST(Parallel, PeriodicLayerEqualsSerial) {
  json scene = scene_file("infinite_slope");
  scene.erase("factor_of_safety");
  scene["materials"]["sand"] = {{"type", "phase/linear_elastic"}, {"density", 2000.0}, {"youngs_modulus", 5e7},
                                {"poisson_ratio", 0.3}};
  scene["grid"]["cells"] = {16, 12};
  scene["bodies"][0]["max"] = {8.0, 5.0};
  scene["bodies"][0]["points_per_cell"] = 4;
  scene["damping"] = 0.2;
  scene["time"] = {{"end", 0.5}, {"cfl", 0.5}};
  scene["outputs"] = json::array();
  expect_equal_to_serial("periodic_layer", scene, {2, 3});
}

// A load carried by the points (bc/traction) reads every point on every
// process: a surcharge on the 2D column, its top points on the last process.
TEST(Parallel, PointLoadsEqualSerial) {
  json scene = scene_file("bench_column");
  scene["time"]["end"] = 0.005;
  scene["boundary_conditions"].push_back({{"type", "bc/traction"},
                                          {"box_min", {0.0, 10.0}},
                                          {"box_max", {9.75, 10.0}},
                                          {"traction", {0.0, -20000.0}}});
  expect_equal_to_serial("surcharged_column", scene, {2, 3});
  json terzaghi = scene_file("terzaghi");  // its load: bc/traction
  terzaghi["time"]["end"] = 0.05;
  expect_equal_to_serial("terzaghi", terzaghi, {2, 4});
}

// A checkpoint's numbers (checkpoint.cpp): every point field by name, the
// ledger's and the reactions' saved values, the clock.
struct Checkpoint {
  json header;
  std::vector<std::pair<std::string, std::vector<double>>> values;
};

Checkpoint read_checkpoint(const fs::path& file) {
  const std::string bytes = slurp(file);
  const std::size_t first = bytes.find('\n'), second = bytes.find('\n', first + 1);
  Checkpoint c;
  c.header = json::parse(bytes.substr(first + 1, second - first - 1));
  std::size_t at = second + 1;
  auto take = [&](const std::string& name, std::size_t n) {
    std::vector<double> v(n);
    if (at + n * sizeof(double) > bytes.size()) throw std::runtime_error("checkpoint too short: " + file.string());
    std::memcpy(v.data(), bytes.data() + at, n * sizeof(double));
    at += n * sizeof(double);
    c.values.emplace_back(name, std::move(v));
  };
  const std::size_t points = c.header.at("points");
  for (const json& f : c.header.at("fields")) take(f.at("name"), points * f.at("components").get<std::size_t>());
  take("ledger", c.header.at("ledger_values"));
  take("reactions", c.header.at("reaction_values"));
  return c;
}

// Slabs narrower than the halo are not refused: each process takes the
// nodes it needs beyond its own from whichever processes hold them. The
// default column widened to 5.12 m and cut to 4 cm (4 cell layers, in a
// grid of 8): 8,192 points in 4 chunks of one cell layer each, so on 4
// processes each holds one cell layer, less than the 2 node layers of the
// transport's halo on either side. Saturated, with fines brought by the
// inlet: checkpoint (the ledger's sums in it) byte for byte.
TEST(Parallel, SlabsNarrowerThanTheHaloEqualSerial) {
  json scene = scene_file("suffusion_column");
  scene["grid"]["cells"] = {512, 8};
  scene["bodies"][0]["max"] = {5.12, 0.04};
  scene["bodies"][0]["water_table"] = 0.04;
  for (json& bc : scene["boundary_conditions"])
    if (bc["type"] == "bc/pore_pressure" && bc["face"] == "bottom") {
      bc["head"] = 0.06;
      bc["initial_head"] = 0.04;
      bc["ramp_time"] = 0.05;
    }
  scene["time"]["end"] = 0.01;
  scene["outputs"] = json::array();
  expect_equal_to_serial("narrow_slabs", scene, {3, 4});
}

// Points sorted again when they mix (docs/parallel.md, Points that mix):
// the Mohr-Coulomb column collapse at 2.5 cm cells, 4,608 points in 3
// scatter chunks, to 0.6 s. The spreading column mixes its points, which
// are sorted once, at the default threshold; 1,266 of them then move to the
// other process on 2 processes. Checkpoints and the followed point's probe
// are the serial run's, byte for byte, each id once in the checkpoint. The
// surcharged column sorted at every step: bc/traction's top points,
// renumbered each time, load it as in the serial run.
TEST(Parallel, SortedPointsMoveBetweenProcessesAndEqualSerial) {
  json scene = scene_file("column_collapse_mc");
  scene["grid"]["cell_size"] = {0.025, 0.025};
  scene["grid"]["cells"] = {100, 36};
  scene["bodies"][0]["points_per_cell"] = 3;
  scene["time"]["end"] = 0.6;
  scene["outputs"] = {{{"type", "writer/csv_probe"}, {"name", "toe"}, {"fields", {"displacement", "stress"}},
                       {"at", {0.39, 0.02}}, {"interval", 0.02}}};
  expect_equal_to_serial("sorted_collapse", scene, {2, 3});
  EXPECT_GE(expect_every_file_equal("sorted_collapse", {2, 3}), 2u);
  const fs::path dir = fs::temp_directory_path() / "suffuse_parallel_sorted_collapse";
  EXPECT_NE(slurp(dir / "np2" / "log").find("sorted again into the grid's order 1 time"), std::string::npos)
      << slurp(dir / "np2" / "log");
  const Checkpoint c = read_checkpoint(dir / "np2" / "sorted_collapse.checkpoint");
  std::size_t moved = 0;
  std::vector<int> seen(4608, 0);
  for (const auto& [field, values] : c.values) {
    if (field != "id") continue;
    ASSERT_EQ(values.size(), seen.size());
    // On 2 processes the first holds chunk 0 (points 0 to 2,047), the second the rest.
    for (std::size_t p = 0; p < values.size(); ++p) {
      moved += (p < 2048) != (values[p] < 2048);
      if (values[p] >= 0 && values[p] < 4608) ++seen[static_cast<std::size_t>(values[p])];
    }
  }
  EXPECT_EQ(std::count(seen.begin(), seen.end(), 1), 4608) << "every id once";
  EXPECT_GT(moved, 1000u) << "points that moved to the other process";

  json surcharged = scene_file("bench_column");
  surcharged["time"]["end"] = 0.005;
  surcharged["sort_points_at_spread"] = 0.5;
  surcharged["boundary_conditions"].push_back({{"type", "bc/traction"},
                                               {"box_min", {0.0, 10.0}},
                                               {"box_max", {9.75, 10.0}},
                                               {"traction", {0.0, -20000.0}}});
  expect_equal_to_serial("surcharged_column_sorted", surcharged, {2, 3});
}

// Runs `scene` serially and on each process count; each run's checkpoint
// must hold the serial one's steps and time, and each of its fields (every
// point field, the ledger's and reactions' sums) within `tolerance` of that
// field's largest magnitude, or within 1e-12 (SI units) where that is below
// 1e-12 (a field that is zero but for round-off, as the velocity gradient
// of a body that translates), and never closer than 1e-15: a field that is
// the difference of two values of order one (the porosity increment, of a
// porosity near 0.4) carries their round-off, 1e-16, at any magnitude. For
// runs whose linear solves go through PETSc: its factorisation sums in
// another order than the serial run's.
void expect_close_to_serial(const std::string& name, const json& scene, const std::vector<int>& counts,
                            double tolerance) {
  const fs::path dir = fresh_dir("parallel_" + name);
  const fs::path file = write_scene(dir, name, scene);
  ASSERT_EQ(run(file, dir / "serial", 1), 0) << slurp(dir / "serial" / "log");
  const Checkpoint serial = read_checkpoint(dir / "serial" / (name + ".checkpoint"));
  for (int n : counts) {
    const fs::path out = dir / ("np" + std::to_string(n));
    ASSERT_EQ(run(file, out, n), 0) << slurp(out / "log");
    EXPECT_NE(slurp(out / "log").find(std::to_string(n) + " processes"), std::string::npos) << slurp(out / "log");
    const Checkpoint other = read_checkpoint(out / (name + ".checkpoint"));
    EXPECT_EQ(other.header.at("steps"), serial.header.at("steps")) << name << " on " << n << " processes";
    // The end's checkpoint holds the state before the last, shortened step:
    // its time is the sum of adaptive steps, which follow the round-off of
    // the erosion they limit, so it is held to the fields' tolerance (the
    // end it stands for is the same).
    EXPECT_EQ(other.header.value("ends_run_at", -1.0), serial.header.value("ends_run_at", -1.0));
    EXPECT_NEAR(other.header.at("time").get<double>(), serial.header.at("time").get<double>(),
                tolerance * serial.header.at("time").get<double>());
    ASSERT_EQ(other.values.size(), serial.values.size());
    for (std::size_t f = 0; f < serial.values.size(); ++f) {
      const auto& [field, a] = serial.values[f];
      const std::vector<double>& b = other.values[f].second;
      ASSERT_EQ(a.size(), b.size()) << field;
      double scale = 0, difference = 0;
      for (std::size_t k = 0; k < a.size(); ++k) {
        scale = std::max(scale, std::abs(a[k]));
        difference = std::max(difference, std::abs(a[k] - b[k]));
      }
      EXPECT_LE(difference, scale < 1e-12 ? 1e-12 : std::max(tolerance * scale, 1e-15)) << name << " on " << n << " processes: " << field << " (largest "
                                               << scale << ")";
    }
  }
}

// Every Newton iteration factorises its own matrix, on one process and on
// many (reuse_factors false): with reused factors the later iterations
// solve by GMRES to 1e-6, which moves the iterates within the Newton
// tolerance, not by round-off, and a failure's last iterate with them
// (QuasiStaticLeveeReusesFactorsAsTheSerialRunDoes compares those).
json quasi_static(json scene, double dt) {
  scene["time"]["integration"] = "quasi_static";
  scene["time"]["dt"] = dt;
  scene["time"]["reuse_factors"] = false;
  scene["time"].erase("cfl");  // controls of explicit dynamics
  scene.erase("damping");
  return scene;
}

#ifdef SUFFUSE_TEST_PETSC
// Quasi-static runs on many processes: each process assembles its points'
// terms, the matrix is PETSc's (MUMPS), and every process holds the whole
// solution. Their results differ from the serial run's (Eigen's LDL') by the
// solvers' round-off: the tolerance, 1e-7 of each field's largest value, is
// far above the differences seen (at most 3e-11 on every field that is not
// itself round-off, such as velocities of 1e-11 m/s in equilibrium, which
// reach 2.5e-9) and far below what a lost process's terms would cause.
//
// Terzaghi's column: one chunk, so the last process holds every point and
// the others none; its load (bc/traction) reads the loaded points in the
// serial numbering.
TEST(Parallel, QuasiStaticTerzaghiCloseToSerial) {
  json scene = quasi_static(scene_file("terzaghi"), 0.01);
  scene["time"]["end"] = 0.1;
  scene["outputs"] = json::array();
  expect_close_to_serial("terzaghi_quasi_static", scene, {2, 4}, 1e-7);
}

// A dry elastic block sheared by a traction on its top (6,144 points, 3
// chunks, GIMP; the base's reaction): its top and right edges cross node
// lines by slivers, so every step has nodes the body barely reaches, which
// follow the points (their sums over the processes; a sliver moves its
// points too little for a lost share of that sum to show at 1e-7).
TEST(Parallel, QuasiStaticDryBlockCloseToSerial) {
  json scene = quasi_static(scene_file("self_weight_column"), 0.1);
  scene["grid"] = {{"origin", {0.0, 0.0}}, {"cell_size", {0.05, 0.05}}, {"cells", {20, 14}}};
  scene["bodies"][0]["min"] = {0.2013, 0.0};
  scene["bodies"][0]["max"] = {0.6013, 0.6001};
  scene["bodies"][0]["points_per_cell"] = 8;
  scene["boundary_conditions"] = {
      {{"type", "bc/velocity"}, {"face", "bottom"}, {"vx", 0.0}, {"vy", 0.0}, {"reaction", "base"}},
      {{"type", "bc/traction"}, {"box_min", {0.2, 0.6001}}, {"box_max", {0.61, 0.6001}}, {"traction", {20000.0, 0.0}}}};
  scene["time"]["end"] = 3.0;
  scene["outputs"] = json::array();
  expect_close_to_serial("dry_block_quasi_static", scene, {2, 3}, 1e-7);
}

// With /time/inertia (implicit dynamics): a column 10 m wide and high
// loaded by its weight at once, swinging on its base (6,400 points, 4
// chunks; the base's reaction records the nodes' inertia too). The mixture's
// nodal mass and momentum are summed over the processes, and the first adds
// M / dt^2 to the matrix: counted twice or lost, the swing would differ far
// above 1e-7. Measured: 5e-15 of the top's displacement.
TEST(Parallel, QuasiStaticInertiaCloseToSerial) {
  json scene = quasi_static(scene_file("self_weight_column"), 0.02);
  scene["time"]["max_dt"] = 0.02;
  scene["time"]["inertia"] = true;
  scene["time"]["end"] = 0.2;
  scene["grid"]["cells"] = {40, 42};
  scene["bodies"][0]["max"] = {10.0, 10.0};
  scene["boundary_conditions"][0]["reaction"] = "base";
  scene["outputs"] = json::array();
  expect_close_to_serial("inertia_quasi_static", scene, {2, 3}, 1e-7);
}

// A periodic grid (docs/boundaries.md, Periodic grids): the infinite
// slope's layer, 8 m long (2,560 points, 2 chunks of 2,048 and 512), carried 1 m by its base in four
// steps, so that points cross the seam. Each process assembles its points'
// terms to the lower face's nodes where they reach the upper face's, and
// each puts its own points back into the period.
TEST(Parallel, QuasiStaticPeriodicLayerCloseToSerial) {
  json scene = scene_file("infinite_slope");
  scene.erase("factor_of_safety");
  scene["grid"]["cells"] = {16, 12};
  scene["bodies"][0]["max"] = {8.0, 5.0};
  scene["bodies"][0]["points_per_cell"] = 4;
  scene["boundary_conditions"][0]["vx"] = 1.0;
  scene["time"]["dt"] = 0.25;
  scene["time"]["max_dt"] = 0.25;
  scene["outputs"] = json::array();
  expect_close_to_serial("periodic_quasi_static", scene, {2}, 1e-7);
}

// A cohesionless column free on one side has no quasi-static equilibrium
// (8,192 points, 4 chunks): the creep term holds the points at the apex of
// Mohr-Coulomb's cone (summed over the processes), and the error says where
// the forces did not balance and which points had no stiffness, counted and
// bounded over every process: the serial run's words and numbers.
TEST(Parallel, QuasiStaticFailureSaysWhatTheSerialRunSays) {
  const fs::path dir = fresh_dir("parallel_no_equilibrium");
  json scene = quasi_static(scene_file("column_collapse_mc"), 0.1);
  scene.erase("mass_scaling");
  scene["time"].erase("mass_scaling");
  scene["time"]["end"] = 0.5;
  scene["time"]["max_iterations"] = 5;
  scene["bodies"][0]["points_per_cell"] = 8;
  const fs::path file = write_scene(dir, "no_equilibrium", scene);
  ASSERT_EQ(run(file, dir / "serial", 1), 1) << slurp(dir / "serial" / "log");
  const std::string serial = slurp(dir / "serial" / "log");
  const std::size_t at = serial.find("At the last attempt");
  ASSERT_NE(at, std::string::npos) << serial;
  const std::string said = serial.substr(at, serial.find('\n', at) - at);
  EXPECT_NE(said.find("material points had no stiffness"), std::string::npos) << said;
  ASSERT_EQ(run(file, dir / "np2", 2), 1) << slurp(dir / "np2" / "log");
  EXPECT_NE(slurp(dir / "np2" / "log").find(said), std::string::npos) << slurp(dir / "np2" / "log") << "\n" << said;
}

// The one-hour suffusion column, widened to 16 cells (2,560 points, 2
// chunks of 2,048 and 512: the processes hold unequal shares), for its
// first minute (32 cells took the same path in 4.5 times as long): an
// erosion front, steps halved and grown, transport substeps (Heun, whose
// halo is doubled) and steps ended by one implicit transport step (PETSc
// too), and the base's reaction.
TEST(Parallel, QuasiStaticErodingColumnCloseToSerial) {
  json scene = scene_file("suffusion_column_1h");
  scene["grid"]["cells"] = {16, 40};
  scene["bodies"][0]["max"] = {0.16, 0.4};
  scene["boundary_conditions"][0]["reaction"] = "base";
  scene["time"]["end"] = 60.0;
  scene["outputs"] = json::array();
  expect_close_to_serial("eroding_column_quasi_static", scene, {2}, 1e-7);
}

// The numbers of a run summary's line `equilibrium: ...; F factorisations, G
// GMRES iterations`.
std::pair<long, long> factorisations_and_gmres(const std::string& log) {
  const std::size_t at = log.find(" factorisations, ");
  if (at == std::string::npos) return {-1, -1};
  const std::size_t start = log.rfind(' ', at - 1) + 1;
  return {std::stol(log.substr(start, at - start)), std::stol(log.substr(at + 17))};
}

// The N of a run summary's `equilibrium: N Newton iterations in ...`.
long newton_iterations(const std::string& log) {
  const std::size_t at = log.find("equilibrium: ");
  return at == std::string::npos ? -1 : std::stol(log.substr(at + 13));
}

// Newton iterations after a step's first reuse its factors on many processes
// as on one (PETSc's GMRES preconditioned by the LU MUMPS set up last, the
// same tolerances as the serial solve's): the levee at 20 cm cells to 4 s
// (Mohr-Coulomb and the suffosion foundation yield at the toe), 121 Newton
// iterations in 39 steps. The equilibria are the serial run's within 1e-9
// of each field's largest value (the bound of the serial run against its
// own factorised iterations, QuasiStatic.ReusedFactorsReachTheEquilibriaOf
// FactorisedOnes), and the solves take the serial run's path: the same
// factorisations within 2 (measured: the same 39; a solve near GMRES's
// limits may fall on either side of it with PETSc's and Eigen's round-off),
// GMRES iterations within 5% (measured: the same 284).
TEST(Parallel, QuasiStaticLeveeReusesFactorsAsTheSerialRunDoes) {
  const json scene = suffuse::test::coarse_quasi_static_levee(4.0);
  ASSERT_TRUE(scene["time"].value("reuse_factors", true));
  expect_close_to_serial("levee_reused_factors", scene, {2}, 1e-9);
  const fs::path dir = fs::temp_directory_path() / "suffuse_parallel_levee_reused_factors";
  const auto serial = factorisations_and_gmres(slurp(dir / "serial" / "log"));
  const auto parallel = factorisations_and_gmres(slurp(dir / "np2" / "log"));
  ASSERT_GT(serial.second, 0) << slurp(dir / "serial" / "log");
  EXPECT_NEAR(static_cast<double>(parallel.first), static_cast<double>(serial.first), 2.0)
      << slurp(dir / "np2" / "log");
  EXPECT_LT(2 * parallel.first, newton_iterations(slurp(dir / "np2" / "log"))) << "most Newton iterations reuse factors";
  EXPECT_NEAR(static_cast<double>(parallel.second), static_cast<double>(serial.second), 0.05 * serial.second);
}
#else
// Without PETSc quasi-static runs are refused on many processes, naming it.
TEST(Parallel, RefusesQuasiStaticWithoutPetsc) {
  const fs::path dir = fresh_dir("parallel_refused");
  json qs = quasi_static(scene_file("terzaghi"), 0.01);
  qs["time"]["end"] = 0.05;
  const fs::path file = write_scene(dir, "quasi_static", qs);
  ASSERT_EQ(run(file, dir / "one", 1), 0) << slurp(dir / "one" / "log");  // the scene runs on one process
  EXPECT_EQ(run(file, dir / "qs", 2), 1);
  EXPECT_NE(slurp(dir / "qs" / "log").find("runs on many processes through PETSc, which this build lacks"),
            std::string::npos)
      << slurp(dir / "qs" / "log");
}
#endif

}  // namespace
