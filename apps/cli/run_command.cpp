// suffuse run: a scene's run with a progress line, its summary and mass
// ledger; SIGINT and SIGTERM stop it after a step with every output closed.
#include <algorithm>
#include <signal.h>
#include <sys/resource.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <string>

#include <suffuse/error.hpp>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>
#include <iomanip>
#include <sstream>
#include <suffuse/liquid.hpp>
#include <suffuse/mass_ledger.hpp>
#include <suffuse/simulation.hpp>
#include <suffuse/version.hpp>

#include "commands.hpp"

namespace fs = std::filesystem;

namespace suffuse::cli {

namespace {

std::string format_duration(double s) {
  if (!std::isfinite(s)) return "?";
  std::ostringstream out;
  const long total = std::lround(s);
  if (total >= 3600) out << total / 3600 << "h" << std::setw(2) << std::setfill('0') << (total % 3600) / 60 << "m";
  else if (total >= 60) out << total / 60 << "m" << std::setw(2) << std::setfill('0') << total % 60 << "s";
  else out << std::fixed << std::setprecision(1) << s << "s";
  return out.str();
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

// SIGINT and SIGTERM ask the run to stop after its step (outputs closed, a
// checkpoint written); a second signal kills at once (SA_RESETHAND). The flag
// is the one piece of global state: a signal handler can reach nothing else.
std::atomic<bool> stop_requested{false};
std::atomic<int> stop_signal{0};

extern "C" void request_stop(int signal) {
  stop_signal.store(signal);
  stop_requested.store(true);
}

// Quasi-static runs on linear shape functions whose points moved more than
// a cell: each point crossing a node adds an error that grows as the steps
// shrink (docs/time-integration.md, Limits), which GIMP does not have.
void warn_about_linear_large_strain(const suffuse::Scene& scene, const suffuse::Simulation& sim, std::ostream& out) {
  if (scene.integration != suffuse::TimeIntegration::quasi_static || scene.shape_function.type != "shape/linear")
    return;
  const suffuse::PointSet& pts = sim.points();
  const double* u = pts.data(pts.core().displacement);
  const auto dim = static_cast<std::size_t>(scene.dim);
  double largest = 0;
  for (std::size_t p = 0; p < pts.size(); ++p) {
    double sq = 0;
    for (std::size_t i = 0; i < dim; ++i) sq += u[p * dim + i] * u[p * dim + i];
    largest = std::max(largest, sq);
  }
  const double cell = *std::min_element(scene.grid_cell_size.begin(), scene.grid_cell_size.begin() + scene.dim);
  if (std::sqrt(largest) > cell)
    out << "warning: points moved up to " << std::sqrt(largest) << " m, more than a cell (" << cell
        << " m), in a quasi-static run on shape/linear: each point that crosses a node adds an error that grows as "
           "the steps shrink (a soft block settled 0.26 m in steps of 0.02 s where the physics gives 0.19 m); use "
           "shape/gimp (docs/time-integration.md, Limits)\n";
}

void stop_on_signals() {
  struct sigaction action {};
  action.sa_handler = request_stop;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

}  // namespace

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
    std::cout << " cells, " << sim.point_count() << " material points, dt = " << sim.dt() << " s";
    if (scene.integration == suffuse::TimeIntegration::quasi_static)
      std::cout << " (quasi-static: the first step, then adaptive)";
    else if (scene.dt)
      std::cout << " (fixed)";
    else
      std::cout << " (automatic, cfl " << scene.cfl << ")";
    std::cout << ", end " << scene.end_time << " s\n";
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
    if (!command.restart.empty())
      std::cout << "  continuing the run saved in " << command.restart.string() << "\n";
  }

  // Warnings whatever --quiet says (on standard error, once on many processes).
  if (sim.process_rank() == 0) warn_about_open_skeletons(scene, std::cerr);

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
  // --newton: a line per quasi-static step on standard output (the
  // collapse's explicit steps have none).
  if (command.newton && sim.process_rank() == 0) {
    options.on_step = [&sim, progress = std::move(options.on_step)](const suffuse::Progress& p) {
      if (progress) progress(p);
      const std::vector<double> r = sim.newton_residuals();
      if (r.empty() || sim.failure()) return;
      std::cout << "newton: step " << p.step << ", t = " << p.time << " s, dt = " << p.dt << " s:";
      for (const double v : r) std::cout << ' ' << std::setprecision(2) << v;
      std::cout << std::setprecision(6) << '\n';
    };
  }
  const suffuse::RunSummary s = sim.run(options);
  if (terminal) std::fprintf(stderr, "\n");
  if (sim.process_rank() == 0 && s.collapse_steps == 0) warn_about_linear_large_strain(scene, sim, std::cerr);
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
      if (!s.factors_of_safety.empty()) {
        // The lowest over the run, and the last.
        auto lowest = std::min_element(s.factors_of_safety.begin(), s.factors_of_safety.end(),
                                       [](const auto& a, const auto& b) { return a.second.factor < b.second.factor; });
        std::cout << "  factor of safety (strength reduction, " << s.factors_of_safety.size() << " evaluations): "
                  << std::setprecision(4) << lowest->second.factor << " at t = " << std::setprecision(6)
                  << lowest->first << " s, the lowest; " << std::setprecision(4)
                  << s.factors_of_safety.back().second.factor << " at t = " << std::setprecision(6)
                  << s.factors_of_safety.back().first << " s, the last (" << scene.name << ".factor_of_safety.csv)\n";
      }
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
  if (s.failure && sim.process_rank() == 0) {
    std::cout << "failed: at t = " << std::setprecision(8) << s.failure->time << " s, " << s.failure->reason
              << " (/failure). ";
    if (scene.failure->collapse) {
      std::cout << "An explicit run followed the collapse from there to t = " << s.simulated_time << " s ("
                << s.collapse_steps << " steps); the largest movement since the failure, " << std::setprecision(3)
                << s.collapse_movement << " m, is of the point now at (";
      for (int a = 0; a < scene.dim; ++a)
        std::cout << (a ? ", " : "") << s.collapse_movement_at[static_cast<std::size_t>(a)];
      std::cout << ") m (point field collapse_displacement)";
      if (!output.empty())
        std::cout << "; " << (output / (scene.name + ".failure.checkpoint")).string()
                  << " holds the state at the failure";
    } else {
      std::cout << "The run stopped there";
      if (!output.empty())
        std::cout << "; every output ends at that time, and " << (output / (scene.name + ".checkpoint")).string()
                  << " holds that state";
    }
    std::cout << "\n";
  }
  return 0;
}

}  // namespace suffuse::cli
