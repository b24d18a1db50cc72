#pragma once
// Helpers shared by the tests: the bundled plugins and scenes built in code.
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <span>
#include <nlohmann/json.hpp>
#include <sstream>
#include <stdexcept>
#include <string>
#include <suffuse/element_test.hpp>
#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <suffuse/simulation.hpp>
#include <vector>

namespace suffuse::test {

// Steady upward seepage (share/scenes/upward_seepage.json;
// ../shared/reference/physics.md, section 4): a column of height L under its
// water table, the head at its base dh higher. Heights y from the base,
// depths z from the top; stresses compression positive.
struct UpwardSeepage {
  double L = 1.0, dh = 0.5, K = 0.01, n = 0.4, rho_s = 2650, rho_w = 1000, g = 9.81;
  double gamma_w() const { return rho_w * g; }
  double gradient() const { return dh / L; }
  double flux() const { return K * gradient(); }  // upward
  double buoyant_weight() const { return (1 - n) * (rho_s - rho_w) * g; }
  double effective_stress(double z) const { return (buoyant_weight() - gradient() * gamma_w()) * z; }
  double pressure(double y) const { return gamma_w() * (L + dh - y * (1 + gradient())); }
};

// Sets SUFFUSE_KERNELS (the vector kernels' instruction set) for the
// simulations built in its lifetime, then restores what the user had set.
class KernelChoice {
 public:
  explicit KernelChoice(const char* isa) {
    const char* before = std::getenv("SUFFUSE_KERNELS");
    had_ = before != nullptr;
    if (had_) before_ = before;
    setenv("SUFFUSE_KERNELS", isa, 1);
  }
  ~KernelChoice() {
    if (had_)
      setenv("SUFFUSE_KERNELS", before_.c_str(), 1);
    else
      unsetenv("SUFFUSE_KERNELS");
  }
  KernelChoice(const KernelChoice&) = delete;
  KernelChoice& operator=(const KernelChoice&) = delete;

 private:
  bool had_ = false;
  std::string before_;
};

// Terzaghi's series, z measured down from the drained top (terms below
// e^-50 dropped).
inline double terzaghi_pressure(double u0, double z, double H, double Tv) {
  double u = 0;
  for (int m = 0; m < 200; ++m) {
    const double M = (2 * m + 1) * std::numbers::pi / 2;
    if (M * M * Tv > 50) break;
    u += 2 * u0 / M * std::sin(M * z / H) * std::exp(-M * M * Tv);
  }
  return u;
}

inline nlohmann::json read_json(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return nlohmann::json::parse(s.str());
}

inline std::filesystem::path source_dir() { return SUFFUSE_SOURCE_DIR; }

// An empty directory temp/suffuse_<name>, the scratch space of one test: a
// name per test, since ctest runs the tests of a file in parallel.
inline std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path dir = std::filesystem::temp_directory_path() / ("suffuse_" + name);
  std::filesystem::remove_all(dir);
  std::filesystem::create_directories(dir);
  return dir;
}

// A number as a scene's text gives it (the shortest form a stream writes).
inline std::string text(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}

// The whole of a file, byte for byte (empty if it cannot be read).
inline std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// Largest |a - b| relative to the largest |a|: how far a run drifted from a
// reference run of the same field (0 if both are zero).
inline double max_relative_difference(std::span<const double> a, std::span<const double> b) {
  double scale = 0, diff = 0;
  for (std::size_t k = 0; k < a.size(); ++k) {
    scale = std::max(scale, std::abs(a[k]));
    diff = std::max(diff, std::abs(a[k] - b[k]));
  }
  return scale > 0 ? diff / scale : diff;
}

// Index in scene["boundary_conditions"] of the one condition that has every
// key of `match` with the same value, e.g. {{"type", "bc/velocity"}, {"face",
// "left"}}: tests edit a condition by what it is, not by its position. Throws
// (a test failure naming the match) unless exactly one condition matches.
inline std::size_t boundary_condition_index(const nlohmann::json& scene, const nlohmann::json& match) {
  const nlohmann::json& bcs = scene.at("boundary_conditions");
  std::vector<std::size_t> found;
  for (std::size_t i = 0; i < bcs.size(); ++i) {
    bool same = true;
    for (const auto& [key, value] : match.items()) same = same && bcs[i].contains(key) && bcs[i][key] == value;
    if (same) found.push_back(i);
  }
  if (found.size() != 1)
    throw std::logic_error("boundary_conditions: expected exactly one condition with " + match.dump() + ", found " +
                           std::to_string(found.size()) + " in " + bcs.dump());
  return found[0];
}

inline nlohmann::json& boundary_condition(nlohmann::json& scene, const nlohmann::json& match) {
  return scene["boundary_conditions"][boundary_condition_index(scene, match)];
}

// The JSON pointer a diagnostic gives for that condition.
inline std::string boundary_condition_pointer(const nlohmann::json& scene, const nlohmann::json& match) {
  return "/boundary_conditions/" + std::to_string(boundary_condition_index(scene, match));
}

// A sand column 1 m high, `width` wide, on a fixed base between smooth
// walls, explicit; its pores drain above a water table at `table` (h_d =
// 0.05 m, docs/phreatic.md). Water at 1e7 Pa and a stiffness of 10 MPa keep
// the step near 1.7e-4 s.
inline nlohmann::json drained_column(double width, double table, double conductivity) {
  nlohmann::json scene = nlohmann::json::parse(R"({
    "dimension": 2, "gravity": [0.0, -9.81], "damping": 0.0,
    "grid": { "origin": [0.0, 0.0], "cell_size": [0.05, 0.05], "cells": [2, 22] },
    "shape_function": { "type": "shape/linear" },
    "materials": {
      "sand": { "type": "phase/linear_elastic", "density": 2650.0, "youngs_modulus": 1.0e7, "poisson_ratio": 0.3,
                "permeability": { "type": "permeability/constant", "hydraulic_conductivity": 1.0e-3 },
                "phreatic": { "drainage_head": 0.05, "residual_conductivity": 1.0e-3 } } },
    "liquids": { "water": { "type": "phase/pore_liquid", "density": 1000.0, "bulk_modulus": 1.0e7 } },
    "bodies": [ { "name": "column", "material": "sand", "liquid": "water", "porosity": 0.3, "k0": 0.5,
                  "min": [0.0, 0.0], "max": [0.1, 1.0], "points_per_cell": 2 } ],
    "boundary_conditions": [
      { "type": "bc/velocity", "face": "bottom", "vx": 0.0, "vy": 0.0 },
      { "type": "bc/velocity", "face": "left", "vx": 0.0 },
      { "type": "bc/velocity", "face": "right", "vx": 0.0 } ],
    "time": { "end": 2.0, "cfl": 0.5 },
    "outputs": []
  })");
  scene["grid"]["cells"][0] = static_cast<int>(std::lround(width / 0.05));
  scene["bodies"][0]["max"][0] = width;
  scene["bodies"][0]["water_table"] = table;
  scene["materials"]["sand"]["permeability"]["hydraulic_conductivity"] = conductivity;
  return scene;
}

// The drained column full of water (its table at the top) over a drain
// along its base: p = 0 there, the skeleton held, the liquid free to leave.
inline nlohmann::json draining_column(double width, double conductivity) {
  nlohmann::json s = drained_column(width, 1.0, conductivity);
  s["boundary_conditions"][0]["phase"] = "solid";
  s["boundary_conditions"].push_back({{"type", "bc/pore_pressure"}, {"face", "bottom"}, {"pressure", 0.0}});
  return s;
}

// Griffiths and Lane's slope (a scene from share/scenes/slope_stability.json)
// made porous and drained above a water table `table` above its base (h_d =
// 0.05 m, K = 1e-7 m/s, porosity 0.4, water at 2.2 GPa; docs/phreatic.md).
inline void drain_slope(nlohmann::json& j, double table) {
  j["liquids"] = {{"water", {{"type", "phase/pore_liquid"}, {"density", 1000.0}, {"bulk_modulus", 2.2e9}}}};
  j["materials"]["soil"]["permeability"] = {{"type", "permeability/constant"}, {"hydraulic_conductivity", 1e-7}};
  j["materials"]["soil"]["phreatic"] = {{"drainage_head", 0.05}};
  j["bodies"][0]["liquid"] = "water";
  j["bodies"][0]["porosity"] = 0.4;
  j["bodies"][0]["water_table"] = table;
}

// A Scene from JSON, with the bundled plugins loaded into `registry`.
inline Scene scene_from(const nlohmann::json& j, Registry& registry) {
  PluginLoader loader(registry);
  return parse_scene(j.dump(), "test.json", source_dir(), registry, loader);
}

// The flow per metre [m^2/s] of a 2D saturated run through the vertical
// strip of two cells of width h about x0: sum V q_x over the strip's width.
inline double flow_through(const Simulation& sim, double x0, double h) {
  const PointSet& pts = sim.points();
  const double* x = pts.data(pts.core().position);
  const double* V = pts.data(pts.core().volume);
  const double* q = pts.data(pts.id("darcy_flux"));
  double sum = 0;
  for (std::size_t p = 0; p < pts.size(); ++p)
    if (std::abs(x[2 * p] - x0) < h) sum += V[p] * q[2 * p];
  return sum / (2 * h);
}

// What building the run of a valid scene refuses (a check that needs the
// grid or the conditions set up), or "(accepted)".
inline std::string setup_error(const nlohmann::json& j) {
  Registry registry;
  const Scene scene = scene_from(j, registry);
  try {
    Simulation sim(scene, registry);
  } catch (const Error& e) {
    return e.what();
  }
  return "(accepted)";
}

// A CSV of numbers: a header row, then rows. A column is found by its whole
// header ("p [Pa]") or by the name before its unit ("p").
struct CsvTable {
  std::vector<std::string> header;
  std::vector<std::vector<double>> rows;
  std::size_t column(const std::string& name) const {
    for (std::size_t k = 0; k < header.size(); ++k)
      if (header[k] == name || header[k].substr(0, header[k].find(" [")) == name) return k;
    throw std::logic_error("no column " + name);
  }
  double at(std::size_t row, const std::string& name) const { return rows[row][column(name)]; }
};

inline CsvTable parse_csv(const std::string& text) {
  CsvTable t;
  std::stringstream in(text);
  std::string line;
  std::getline(in, line);
  for (std::stringstream h(line); std::getline(h, line, ',');) t.header.push_back(line);
  while (std::getline(in, line)) {
    std::vector<double> row;
    // strtod, not stod: round-off in a ledger can be subnormal (1e-314), which stod refuses.
    for (std::stringstream c(line); std::getline(c, line, ',');) row.push_back(std::strtod(line.c_str(), nullptr));
    t.rows.push_back(row);
  }
  return t;
}

inline CsvTable read_csv(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return parse_csv(s.str());
}

// The CSV text of the first case of an element scene given as JSON.
inline std::string element_csv(const nlohmann::json& j) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const auto scene = suffuse::parse_element_scene(j.dump(), "element.json", ".", registry, loader);
  std::ostringstream out;
  suffuse::run_element_test(scene, 0, registry, out);
  return out.str();
}

// share/scenes/levee_suffusion.json at 20 cm cells, quasi-static to `end`
// seconds as levee_suffusion_quasi_static.json runs it (no damping, steps
// of 0.05 to 0.5 s, eroded_fraction_tolerance 5e-4, the foundation's
// erosion-induced strain in substeps), without outputs.
inline nlohmann::json coarse_quasi_static_levee(double end) {
  auto j = read_json(source_dir() / "share/scenes/levee_suffusion.json");
  j["outputs"] = nlohmann::json::array();
  j.erase("damping");
  j["grid"]["cell_size"] = {0.2, 0.2};
  j["grid"]["cells"] = {40, 14};
  j["time"] = {{"end", end},
               {"integration", "quasi_static"},
               {"dt", 0.05},
               {"max_dt", 0.5},
               {"eroded_fraction_tolerance", 5e-4}};
  j["materials"]["gap_graded_foundation"]["integration"] = "substeps";
  return j;
}

}  // namespace suffuse::test
