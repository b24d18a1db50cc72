// suffuse: the command-line front end.
//   suffuse run SCENE.json [--output DIR] [--threads N] [--quiet] [--checkpoint-every S] [--restart FILE]
//   suffuse validate SCENE.json
//   suffuse plugins
//   suffuse describe NAME
//   suffuse schema
//   suffuse plot --png OUT.png --x COLUMN --y COLUMN [options] FILE.csv [FILE.csv ...]
//   suffuse plot profile|map|animate [options] RUN
//   suffuse gradation PSD.csv [--json] [--png FILE.png]
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>

#include <boost/program_options.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iomanip>
#include <iostream>
#include <fstream>
#include <nlohmann/json.hpp>
#include <optional>
#include <sstream>
#include <string>
#include <suffuse/element_test.hpp>
#include <suffuse/error.hpp>
#include <suffuse/parallel.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <suffuse/simulation.hpp>
#include <suffuse/version.hpp>
#include <vector>

#include "figures_module.hpp"
#include "gradation_command.hpp"
#if __has_include(<malloc.h>)
#include <malloc.h>  // glibc's mallopt
#endif

namespace po = boost::program_options;
namespace fs = std::filesystem;

namespace {

const char* usage =
    "Usage:\n"
    "  suffuse run SCENE.json [--output DIR] [--threads N] [--quiet]\n"
    "                         [--checkpoint-every SECONDS] [--restart CHECKPOINT]\n"
    "                         run a scene; outputs go to DIR (default ./output/<scene name>);\n"
    "                         --restart continues a run from DIR/<scene>.checkpoint (a later end time extends it)\n"
    "  suffuse validate SCENE.json   check a scene against the plugin schemas, run nothing\n"
    "  suffuse element SCENE.json [--output DIR] [--quiet]\n"
    "                                drive one point of a phase along a test path (element test);\n"
    "                                writes DIR/<scene>[.<case>].element.csv (default ./output/<scene name>)\n"
    "  suffuse plugins               list the plugins found, with their libraries\n"
    "  suffuse describe NAME         print the parameters of a plugin (or a core section:\n"
    "                                scene, grid, time, body, output)\n"
    "  suffuse schema                every parameter of every plugin and section, as JSON\n"
    "  suffuse reference             the scene reference manual, as Markdown\n"
    "  suffuse plot --png OUT.png --x COLUMN --y COLUMN [--y COLUMN ...] [options] FILE.csv [FILE.csv ...]\n"
    "                                line charts of CSV columns (e.g. element-test results) to a PNG,\n"
    "                                no display needed; suffuse plot --help lists its options\n"
    "  suffuse plot profile --png OUT.png --field NAME --from X,Y --to X,Y [--times T,T,...] RUN\n"
    "                                a field along a line at several times (RUN: output directory or .pvd)\n"
    "  suffuse plot map --png OUT.png --field NAME [--times T,T,...] [--range MIN MAX] RUN\n"
    "                                a colour map of a field over the body (--slice of a 3D run)\n"
    "  suffuse plot animate --field NAME [--frames DIR] [--gif OUT.gif] RUN\n"
    "                                that map at every frame: numbered PNGs and an animated GIF\n"
    "                                (suffuse plot profile --help, ... list their options)\n"
    "  suffuse gradation PSD.csv [--json] [--png FILE.png]\n"
    "                                internal stability of a particle-size distribution by the published\n"
    "                                criteria (Kezdi, Kenney-Lau, Burenkova, ...); suffuse gradation --help\n"
    "Plugins are searched in the scene's plugin_paths, then $SUFFUSE_PLUGIN_PATH, then\n"
    "the bundled plugin directory.\n";

std::string format_duration(double s) {
  if (!std::isfinite(s)) return "?";
  std::ostringstream out;
  const long total = std::lround(s);
  if (total >= 3600) out << total / 3600 << "h" << std::setw(2) << std::setfill('0') << (total % 3600) / 60 << "m";
  else if (total >= 60) out << total / 60 << "m" << std::setw(2) << std::setfill('0') << total % 60 << "s";
  else out << std::fixed << std::setprecision(1) << s << "s";
  return out.str();
}

std::string format_number(double v) {
  std::ostringstream out;
  out << v;
  return out.str();
}

void load_default_plugins(suffuse::PluginLoader& loader) {
  for (const auto& path : suffuse::PluginLoader::default_search_path()) loader.load_path(path);
}

void print_schema_table(const std::string& title, const std::string& description,
                        const suffuse::ParameterSchema& schema) {
  std::cout << title << "\n  " << description << "\n";
  if (schema.params().empty()) {
    std::cout << "  (no parameters)\n";
    return;
  }
  std::cout << "\n";
  for (const suffuse::Param& p : schema.params()) {
    std::cout << "  " << p.name << "\n";
    std::cout << "      " << p.description << "\n";
    std::cout << "      type: " << p.expectation(0);
    if (p.default_value && p.type == suffuse::ParamType::Vector &&
        std::get<std::vector<double>>(*p.default_value).empty())
      std::cout << "; default: zeros";
    else if (p.default_value) std::cout << "; default: " << suffuse::to_string(*p.default_value);
    else if (p.optional) std::cout << "; optional";
    else std::cout << "; required";
    std::cout << "\n";
  }
}

int cmd_plugins() {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  load_default_plugins(loader);
  for (const auto& lib : loader.libraries()) {
    std::cout << lib.path.string() << "  (built for suffuse " << lib.framework_version << ", ABI " << lib.abi_major
              << "." << lib.abi_minor << ")\n";
    for (const auto& name : lib.plugins) {
      const suffuse::PluginInfo* info = registry.find(name);
      std::cout << "  " << std::left << std::setw(20) << suffuse::to_string(info->kind) << std::setw(28) << name
                << info->description << "\n";
    }
  }
  return 0;
}

int cmd_describe(const std::string& name) {
  for (const auto& section : suffuse::core_sections()) {
    if (section.name == name) {
      print_schema_table("core section " + name, section.description, section.schema);
      return 0;
    }
  }
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  load_default_plugins(loader);
  const suffuse::PluginInfo* info = registry.find(name);
  if (!info) {
    std::string names;
    for (const auto& [n, i] : registry.all()) names += (names.empty() ? "" : ", ") + n;
    throw suffuse::Error("no plugin or core section named '" + name + "'; known plugins: " + names);
  }
  print_schema_table(name + " (" + suffuse::to_string(info->kind) + ", from " + info->library + ")",
                     info->description, info->schema());
  return 0;
}

nlohmann::json schema_json(const suffuse::ParameterSchema& schema) {
  nlohmann::json params = nlohmann::json::array();
  for (const suffuse::Param& p : schema.params()) {
    nlohmann::json j = {{"name", p.name}, {"type", suffuse::to_string(p.type)}, {"unit", p.unit},
                        {"description", p.description}, {"expected", p.expectation(0)},
                        {"required", p.required()}};
    if (p.default_value) j["default"] = suffuse::to_string(*p.default_value);
    if (!p.choices.empty()) j["choices"] = p.choices;
    params.push_back(j);
  }
  return params;
}

int cmd_schema() {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  load_default_plugins(loader);
  nlohmann::json out;
  out["suffuse_version"] = suffuse::framework_version;
  for (const auto& s : suffuse::core_sections())
    out["core"][s.name] = {{"description", s.description}, {"parameters", schema_json(s.schema)}};
  for (const auto& [name, info] : registry.all())
    out["plugins"][name] = {{"kind", suffuse::to_string(info.kind)}, {"description", info.description},
                            {"parameters", schema_json(info.schema())}};
  std::cout << out.dump(2) << "\n";
  return 0;
}

std::string markdown_table(const suffuse::ParameterSchema& schema) {
  if (schema.params().empty()) return "No parameters.\n";
  std::string t = "| key | expected | default | description |\n|---|---|---|---|\n";
  for (const suffuse::Param& p : schema.params()) {
    std::string def = p.default_value ? "`" + suffuse::to_string(*p.default_value) + "`"
                      : p.optional    ? "optional"
                                      : "**required**";
    if (def == "`[]`" && p.type == suffuse::ParamType::Vector) def = "zeros";
    t += "| `" + p.name + "` | " + p.expectation(0) + " | " + def + " | " + p.description + " |\n";
  }
  return t;
}

// The scene reference manual, generated from the schemas (docs/scene-reference.md).
int cmd_reference() {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  load_default_plugins(loader);
  std::cout << "# Scene reference\n\n"
               "Generated by `suffuse reference` from the parameter schemas that the core and each plugin "
               "declare; do not edit by hand. Units are SI. A vector has one component per dimension unless "
               "stated. Every node that names a plugin has a `\"type\"` key; all other keys are checked against "
               "the plugin's schema and an unknown key is an error.\n\n"
               "A scene is one JSON object:\n\n"
               "```\n"
               "{ description, dimension, plugin_paths, gravity, damping, volumetric_strain,\n"
               "  grid: {...}, time: {...},\n"
               "  shape_function: { type: \"shape/...\", ... },\n"
               "  materials: { NAME: { type: \"phase/...\", ... }, ... },\n"
               "  bodies: [ { material: NAME, min, max, ... }, ... ],\n"
               "  boundary_conditions: [ { type: \"bc/...\", reaction, ... }, ... ],\n"
               "  outputs: [ { type: \"writer/...\", interval, ... }, ... ] }\n"
               "```\n\n## Core sections\n\n";
  for (const auto& s : suffuse::core_sections())
    std::cout << "### " << s.name << "\n\n" << s.description << ".\n\n" << markdown_table(s.schema) << "\n";
  std::cout << "## Plugins\n\n";
  for (auto kind : suffuse::all_plugin_kinds) {
    for (const auto& name : registry.names_of(kind)) {
      const suffuse::PluginInfo* info = registry.find(name);
      std::cout << "### " << name << " (" << suffuse::to_string(kind) << ")\n\n"
                << info->description << ".\n\n" << markdown_table(info->schema()) << "\n";
    }
  }
  return 0;
}

// The internal-stability criteria on each body's gradation, and a warning
// where an erosion law erodes a soil that every criterion finds stable.
void print_gradations(const suffuse::Scene& scene) {
  for (const suffuse::BodySpec& body : scene.bodies) {
    if (!body.internal_stability) continue;
    const suffuse::InternalStability& s = *body.internal_stability;
    std::cout << "\nbody '" << body.name << "': gradation " << body.gradation_source << "\n";
    suffuse::gradation_command::print_table(std::cout, s, "  ");
    if (body.fines_content_from_gradation)
      std::cout << "  fines_content = " << body.fines_content << " (fines_content_from_gradation)\n";
    const suffuse::MaterialSpec& material = scene.materials[body.material];
    if (material.erosion && s.stable())
      std::cout << "warning: body '" << body.name << "': every applicable criterion finds its gradation stable, yet "
                << "material '" << material.name << "' erodes it (" << material.erosion->type
                << "): suffusion is not expected in this soil\n";
  }
}

// A body whose erodible fines, all washed out, would leave a porosity no soil
// skeleton has (sands stay below about 0.5, the loosest clays near 0.9):
// fines content 0.99 in a soil of porosity 0.9 ends at 0.999.
void warn_about_open_skeletons(const suffuse::Scene& scene, std::ostream& out) {
  for (const suffuse::BodySpec& body : scene.bodies) {
    if (!body.liquid || !scene.materials[body.material].erosion) continue;
    const double n = body.porosity;
    const double final_porosity = n + (1 - n) * (body.fines_content - body.ultimate_fines_content);
    if (final_porosity > 0.9)
      out << "warning: body '" << body.name << "': washing out its erodible fines (fines_content "
          << body.fines_content << " - ultimate " << body.ultimate_fines_content << " of the solid) would leave "
          << "porosity " << final_porosity << ", more open than any soil skeleton (above 0.9): check porosity and "
          << "fines_content\n";
  }
}

int cmd_validate(const fs::path& scene_file) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::Scene scene = suffuse::load_scene(scene_file, registry, loader);
  // What the run would be: building it checks memory and the time step, as
  // `run` does, and gives the numbers (nothing is written).
  const suffuse::Simulation sim(scene, registry, 1);
  std::cout << scene_file.string() << " is valid: " << scene.dim << "D, " << scene.materials.size()
            << " material(s), " << scene.bodies.size() << " body(ies), " << scene.boundary_conditions.size()
            << " boundary condition(s), " << scene.outputs.size() << " output(s)\n";
  print_gradations(scene);
  warn_about_open_skeletons(scene, std::cout);
  if (scene.integration == suffuse::TimeIntegration::quasi_static) {
    // Steps adapt: only the largest is known, and so the fewest steps.
    const double largest = scene.quasi_static.max_dt > 0 ? scene.quasi_static.max_dt : sim.dt();
    std::cout << "  run: " << sim.point_count() << " material points, quasi-static, first dt = " << sim.dt()
              << " s, at most " << largest << " s: at least "
              << std::llround(std::ceil(scene.end_time / largest - 1e-9)) << " steps to t = " << scene.end_time
              << " s\n";
    return 0;
  }
  std::cout << "  run: " << sim.point_count() << " material points, dt = " << sim.dt() << " s ("
            << (scene.dt ? "fixed" : "automatic") << "), " << std::llround(std::ceil(scene.end_time / sim.dt() - 1e-9))
            << " steps to t = " << scene.end_time << " s\n";
  return 0;
}

// The end-of-run mass balance of a saturated run (the time series is in
// <scene>.ledger.csv beside the outputs).
void print_ledger(const suffuse::MassLedger& l, int dim, const std::string& name) {
  const char* unit = dim == 2 ? "kg/m" : "kg";
  std::cout << std::setprecision(6) << "mass ledger [" << unit << (dim == 2 ? ", per metre of thickness" : "")
            << "] (time series: " << name << ".ledger.csv)\n";
  double in_fines = 0, in_liquid = 0, out_liquid = 0;
  for (const auto& b : l.boundaries) in_fines += b.fines_in, in_liquid += b.liquid_in, out_liquid += b.liquid_out;
  if (l.initial_fines + in_fines > 0)
    std::cout << "  fines:  initial " << l.initial_fines << ", brought in " << in_fines << ", in the skeleton "
            << l.skeleton_fines << ", suspended " << l.suspended_fines << ", discharged " << l.fines_discharged();
  for (const auto& b : l.boundaries)
    if (b.fines_out > 0) std::cout << " (" << b.face << " " << b.fines_out << ")";
  if (l.initial_fines + in_fines > 0)
    std::cout << "; imbalance " << std::setprecision(2) << l.fines_imbalance() << "\n";
  std::cout << std::setprecision(6) << "  liquid: initial " << l.initial_liquid << ", in " << in_liquid
            << ", out " << out_liquid << ", eroded into it " << l.eroded << ", now " << l.liquid
            << "; imbalance " << std::setprecision(2) << l.liquid_imbalance() << "\n"
            << std::setprecision(6) << "  solid:  initial " << l.initial_solid << ", now " << l.solid
            << "; imbalance " << std::setprecision(2) << l.solid_imbalance() << "\n";
}

int cmd_element(const fs::path& scene_file, const fs::path& output, bool quiet) {
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::ElementScene scene = suffuse::load_element_scene(scene_file, registry, loader);
  fs::create_directories(output);
  if (!quiet)
    std::cout << "suffuse " << suffuse::framework_version << ": element test of " << scene.material.type
              << (scene.material_base ? " around " + scene.material_base->type : std::string()) << ", "
              << scene.cases.size() << " case(s)\n";
  for (std::size_t c = 0; c < scene.cases.size(); ++c) {
    const std::string& name = scene.cases[c].name;
    const fs::path file = output / (scene.name + (name.empty() ? "" : "." + name) + ".element.csv");
    std::ofstream csv(file);
    if (!csv) throw suffuse::Error("cannot write " + file.string());
    const suffuse::ElementResult result = suffuse::run_element_test(scene, c, registry, csv);
    if (quiet) continue;
    std::cout << "  " << (name.empty() ? "" : name + ": ") << result.increments << " increments, rows in "
              << file.string() << "\n";
    for (const suffuse::ElementEvent& e : result.events) std::cout << "    " << e.message() << "\n";
  }
  return 0;
}

// SIGINT and SIGTERM ask the run to stop after its step (outputs closed, a
// checkpoint written); a second signal kills at once (SA_RESETHAND). The flag
// is the one piece of global state: a signal handler can reach nothing else.
std::atomic<bool> stop_requested{false};
std::atomic<int> stop_signal{0};

extern "C" void request_stop(int signal) {
  stop_signal.store(signal);
  stop_requested.store(true);
}

void stop_on_signals() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

// What `suffuse run` takes besides the scene.
struct RunCommand {
  fs::path output;
  int threads = 1;
  bool quiet = false;
  std::optional<double> checkpoint_every;  // [s] of simulated time
  fs::path restart;                        // a checkpoint to continue from
};

int cmd_run(const fs::path& scene_file, const RunCommand& command) {
  const fs::path& output = command.output;
  const int threads = command.threads;
#ifndef SUFFUSE_HAVE_OPENMP
  if (threads != 1) throw suffuse::Error("--threads " + std::to_string(threads) + ": this build has no OpenMP");
#endif
  suffuse::Registry registry;
  suffuse::PluginLoader loader(registry);
  const suffuse::Scene scene = suffuse::load_scene(scene_file, registry, loader);
  suffuse::Simulation sim(scene, registry, threads);
  // On many processes the first one reports (docs/parallel.md).
  const bool quiet = command.quiet || sim.process_rank() != 0;

  // Progress: on a terminal a bar on standard error, redrawn 4 times a second;
  // otherwise (a log file, a pipe) a plain line on standard output at every
  // tenth of the simulated time.
  const bool terminal = !quiet && isatty(STDERR_FILENO);
  if (!quiet) {
    std::cout << "suffuse " << suffuse::framework_version << ": " << scene_file.string() << "\n"
              << "  " << scene.dim << "D grid " << scene.grid_cells[0] << " x " << scene.grid_cells[1];
    if (scene.dim == 3) std::cout << " x " << scene.grid_cells[2];
    std::cout << " cells, " << sim.point_count() << " material points, dt = " << sim.dt() << " s"
              << (scene.integration == suffuse::TimeIntegration::quasi_static
                      ? " (quasi-static: the first step, then adaptive)"
                      : scene.dt ? " (fixed)" : " (automatic, cfl " + format_number(scene.cfl) + ")")
              << ", end "
              << scene.end_time << " s\n";
    if (scene.mass_scaling != 1)
      std::cout << "  mass scaling " << scene.mass_scaling
                << ": every inertia is multiplied by it (quasi-static use only)\n";
    for (std::size_t l = 0; sim.saturated() && l < scene.liquids.size(); ++l) {
      // A lowered bulk modulus is a numerical choice that changes the physics: say it.
      const double KL = sim.liquid(l).bulk_modulus();
      std::cout << "  liquid '" << scene.liquids[l].name << "': bulk modulus " << KL << " Pa"
                << (KL < suffuse::water_bulk_modulus
                        ? " (lower than water's 2.2e9 Pa: a larger time step, a more compressible liquid)"
                        : "")
                << "\n";
    }
    if (!scene.outputs.empty())
      std::cout << "  output: " << output.string() << " (run settings in " << scene.name << ".run.json)\n";
    warn_about_open_skeletons(scene, std::cout);
    if (!command.restart.empty())
      std::cout << "  continuing the run saved in " << command.restart.string() << "\n";
  }

  suffuse::RunOptions options;
  options.output_dir = output;
  options.checkpoint_interval = command.checkpoint_every;
  options.restart = command.restart;
  options.stop = &stop_requested;
  stop_on_signals();
  auto last = std::chrono::steady_clock::now();
  int next_tenth = 1;
  // A restarted run starts at a later step and time: rates count from there.
  std::optional<std::size_t> first_step;
  double first_time = 0;
  if (!quiet) {
    options.on_step = [&](const suffuse::Progress& p) {
      if (!first_step) {
        first_step = p.step - 1;
        first_time = p.time - p.dt;
        while (first_time > 0 && first_time >= next_tenth / 10.0 * p.end_time) ++next_tenth;
      }
      const double share = p.end_time > 0 ? std::min(1.0, p.time / p.end_time) : 1.0;
      const double rate = p.wall_seconds > 0 ? static_cast<double>(p.step - *first_step) / p.wall_seconds : 0.0;
      const double left =
          p.time > first_time ? p.wall_seconds * (p.end_time - p.time) / (p.time - first_time) : NAN;
      if (terminal) {
        const auto now = std::chrono::steady_clock::now();
        if (now - last < std::chrono::milliseconds(250) && p.time < p.end_time) return;
        last = now;
        const int width = 24, filled = static_cast<int>(share * width);
        std::fprintf(stderr, "\r  [%s%s] %3.0f%%  t = %.4g of %.4g s  %.0f steps/s  left %s   ",
                     std::string(filled, '#').c_str(), std::string(width - filled, '.').c_str(), 100 * share, p.time,
                     p.end_time, rate, format_duration(left).c_str());
        std::fflush(stderr);
      } else if (share >= next_tenth / 10.0 - 1e-12) {
        while (share >= next_tenth / 10.0 - 1e-12) ++next_tenth;
        // On standard output, in order with the summary a log collects.
        char line[160];
        std::snprintf(line, sizeof line, "  %3.0f%%  t = %.4g of %.4g s, step %zu, %.0f steps/s, wall %s, left %s\n",
                      100 * share, p.time, p.end_time, p.step, rate, format_duration(p.wall_seconds).c_str(),
                      format_duration(left).c_str());
        std::cout << line << std::flush;
      }
    };
  }
  const suffuse::RunSummary s = sim.run(options);
  if (terminal) std::fprintf(stderr, "\n");
  if (s.interrupted && sim.process_rank() != 0) return 128 + stop_signal.load();
  if (s.interrupted) {
    const fs::path checkpoint = output / (scene.name + ".checkpoint");
    std::cerr << "suffuse: interrupted (signal " << stop_signal.load() << ") at t = " << s.simulated_time
              << " s, step " << sim.steps() << ": every output is closed";
    if (!output.empty()) std::cerr << "; continue with --restart " << checkpoint.string();
    std::cerr << "\n";
    return 128 + stop_signal.load();
  }
  if (!quiet) {
    const auto& t = s.stages;
    std::cout << "done: " << s.steps << " steps to t = " << s.simulated_time << " s in "
              << format_duration(s.wall_seconds) << "; " << std::setprecision(3) << s.point_updates_per_second / 1e6
              << " million point updates per second (" << sim.threads() << (sim.threads() == 1 ? " thread, " : " threads, ")
              << (sim.processes() > 1 ? std::to_string(sim.processes()) + " processes, " : "") << sim.kernels()
              << " kernels)\n"
              << "  stage times [s]:";
    // The stages this run has (a dry run has no pore pressure, erosion or transport).
    const char* sep = " ";
    for (std::size_t k = 0; k < suffuse::stage_count; ++k) {
      const auto stage = static_cast<suffuse::Stage>(k);
      if (t[stage] == 0 && stage != suffuse::Stage::output) continue;
      std::cout << sep << suffuse::stage_name(stage) << " " << t[stage];
      sep = ", ";
    }
    std::cout << "\n";
    // Peak resident memory of the process (program and libraries included),
    // over the points: issue 17's figure of memory per point.
    rusage usage{};
    // On many processes: the first one's, over its own points (if any).
    if (getrusage(RUSAGE_SELF, &usage) == 0) {
      std::cout << "  peak memory: " << std::setprecision(4) << usage.ru_maxrss / 1024.0 << " MB resident"
                << (sim.processes() > 1 ? " (first process)" : "");
      if (sim.points().size() > 0)
        std::cout << ", " << std::setprecision(3)
                  << usage.ru_maxrss * 1024.0 / static_cast<double>(sim.points().size()) << " bytes per material point"
                  << (sim.processes() > 1 ? " of its own" : "");
      std::cout << "\n";
    }
    if (sim.processes() > 1 && s.steps > 0)
      std::cout << "  exchanged: " << std::setprecision(3)
                << 8.0 * static_cast<double>(s.exchanged_values) / static_cast<double>(s.steps) / 1e6
                << " MB received per step by the first process\n";
    if (s.point_sorts > 0)
      std::cout << "  point order: the points mixed and were sorted again into the grid's order " << s.point_sorts
                << (s.point_sorts == 1 ? " time" : " times") << " (/sort_points_at_spread)\n";
    if (scene.integration == suffuse::TimeIntegration::quasi_static) {
      std::cout << "  equilibrium: " << s.newton_iterations << " Newton iterations in " << s.steps << " steps; "
                << s.halved_steps << " attempts halved";
      std::cout << "; " << s.factorisations << " factorisations, " << s.gmres_iterations << " GMRES iterations";
      std::cout << "\n";
      if (s.creep_held_most > 0)
        std::cout << "  creep: material points without stiffness in some direction (separated, or at a yield "
                     "surface's apex; the creep term, /time/creep, holds them unless zero): "
                  << s.creep_held_first << " at t = " << std::setprecision(6) << s.creep_held_from << " s, the first; "
                  << s.creep_held_most << " at t = " << s.creep_held_most_at
                  << " s, the most. Where they form a layer (a heave, a fluidised bed), its deformation is the "
                     "creep term's, not a prediction: run that explicit (docs/time-integration.md, Fluidisation)\n";
    }
    if (s.transport_substeps > 0)
      std::cout << "  transport: " << s.transport_substeps << " substeps; " << s.steady_transport_steps << " of "
                << s.steps << " steps ended by one implicit step once the transport was steady\n";
    if (s.ledger) print_ledger(*s.ledger, scene.dim, scene.name);
  }
  return 0;
}

// Every output frame compresses each field with zlib, whose state (a few
// blocks of 64 KB) is freed after each field; glibc then gave the top of the
// heap back to the system each time, and every such return flushes the TLB of
// every processor running the program (threads of OpenMP and VTK): half of
// the default column's output stage. Freed memory is now kept for reuse up
// to 256 MB. Blocks of up to 32 MB come from the heap (glibc's own largest
// default once it adapts), larger ones are mapped and returned at once. The
// threads' own heaps (64 MB each) are then kept until the run ends: peak
// memory is what a run holds anyway.
void keep_freed_memory_for_reuse() {
#ifdef M_TRIM_THRESHOLD
  mallopt(M_MMAP_THRESHOLD, 32 << 20);
  mallopt(M_TRIM_THRESHOLD, 256 << 20);
#endif
}

}  // namespace

int main(int argc, char** argv) {
  keep_freed_memory_for_reuse();
  const suffuse::ParallelProcesses processes(argc, argv);  // mpirun: docs/parallel.md
  try {
    // plot has options and a list of files of its own.
    if (argc >= 2 && std::string(argv[1]) == "plot") return suffuse::figures::plot_command(argc - 1, argv + 1);
    if (argc >= 2 && std::string(argv[1]) == "gradation") return suffuse::gradation_command::run(argc - 1, argv + 1);
    po::options_description opts("Options");
    opts.add_options()("help,h", "show this help")("version", "print the version")(
        "output,o", po::value<std::string>(), "output directory (run)")(
        "threads,t", po::value<int>()->default_value(1), "number of threads (run)")(
        "quiet,q", "no progress line and no summary (run)")(
        "checkpoint-every", po::value<double>(),
        "simulated seconds between checkpoints, OUTPUT/<scene>.checkpoint (run; default: the scene's "
        "/time/checkpoint_interval; one is written at the end unless /time/checkpoint_at_end is false)")(
        "restart", po::value<std::string>(),
        "continue the run saved in this checkpoint; its outputs continue in the output directory (run)");
    po::options_description hidden;
    hidden.add_options()("command", po::value<std::string>())("argument", po::value<std::string>());
    po::options_description all;
    all.add(opts).add(hidden);
    po::positional_options_description positional;
    positional.add("command", 1).add("argument", 1);
    po::variables_map vm;
    po::store(po::command_line_parser(argc, argv).options(all).positional(positional).run(), vm);
    po::notify(vm);

    if (vm.count("help")) {
      std::cout << usage << "\n" << opts;
      return 0;
    }
    if (vm.count("version")) {
      std::cout << "suffuse " << suffuse::framework_version << " (plugin ABI " << suffuse::abi_major << "."
                << suffuse::abi_minor << ")\n";
      return 0;
    }
    if (!vm.count("command")) {
      std::cerr << usage;
      return 2;
    }
    const std::string command = vm["command"].as<std::string>();
    const bool has_arg = vm.count("argument") != 0;
    const std::string arg = has_arg ? vm["argument"].as<std::string>() : "";
    auto need_arg = [&](const char* what) {
      if (!has_arg) throw suffuse::Error(std::string("suffuse ") + command + " needs " + what);
    };
    if (command == "run") {
      need_arg("a scene file");
      const int threads = vm["threads"].as<int>();
      if (threads < 1) throw suffuse::Error("--threads must be at least 1");
      const fs::path out = vm.count("output") ? fs::path(vm["output"].as<std::string>())
                                              : fs::path("output") / fs::path(arg).stem();
      RunCommand run{out, threads, vm.count("quiet") != 0, std::nullopt, {}};
      if (vm.count("checkpoint-every")) {
        run.checkpoint_every = vm["checkpoint-every"].as<double>();
        if (!(*run.checkpoint_every > 0) || !std::isfinite(*run.checkpoint_every))
          throw suffuse::Error("--checkpoint-every must be a positive number of seconds");
      }
      if (vm.count("restart")) run.restart = vm["restart"].as<std::string>();
      return cmd_run(arg, run);
    }
    if (command == "element") {
      need_arg("an element-test scene file");
      const fs::path out = vm.count("output") ? fs::path(vm["output"].as<std::string>())
                                              : fs::path("output") / fs::path(arg).stem();
      return cmd_element(arg, out, vm.count("quiet") != 0);
    }
    if (command == "validate") {
      need_arg("a scene file");
      return cmd_validate(arg);
    }
    if (command == "plugins") return cmd_plugins();
    if (command == "describe") {
      need_arg("a plugin name");
      return cmd_describe(arg);
    }
    if (command == "schema") return cmd_schema();
    if (command == "reference") return cmd_reference();
    std::cerr << "suffuse: unknown command '" << command << "'\n" << usage;
    return 2;
  } catch (const std::exception& e) {
    if (processes.size() == 1) {
      std::cerr << "suffuse: error: " << e.what() << "\n";
      return 1;
    }
    // The other processes may wait in an exchange this one will not join.
    std::cerr << "suffuse: error (process " << processes.rank() << " of " << processes.size() << "): " << e.what()
              << "\n";
    processes.abort(1);
  }

}
