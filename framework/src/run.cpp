// Simulation::run: the time loop around step(), with outputs and timing.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "domain.hpp"
#include "reactions.hpp"
#include "saturated_mixture.hpp"
#include "species_transport.hpp"
#include "stage_timer.hpp"
#include "suffuse/error.hpp"
#include "suffuse/simulation.hpp"
#include "suffuse/version.hpp"

namespace suffuse {

// The numerical choices of the run, next to its outputs, so that a reduced
// liquid bulk modulus or a chosen time step is never silent.
void Simulation::write_run_info(const std::filesystem::path& file) const {
  nlohmann::ordered_json info;
  info["suffuse_version"] = framework_version;
  info["scene"] = scene_.file.string();
  info["dimension"] = scene_.dim;
  info["points"] = domain_->points.size();
  info["time_step"] = clock_.nominal_dt();
  info["time_step_mode"] = scene_.dt ? "fixed" : "automatic";
  info["cfl"] = scene_.cfl;
  info["mass_scaling"] = scene_.mass_scaling;
  info["end_time"] = scene_.end_time;
  info["damping"] = scene_.damping;
  info["threads"] = threads();
  info["saturated"] = saturated();
  for (std::size_t l = 0; mixture_ && l < scene_.liquids.size(); ++l) {
    const Liquid& liquid = mixture_->liquid(l);
    info["liquids"][scene_.liquids[l].name] = {
        {"density", liquid.density()}, {"bulk_modulus", liquid.bulk_modulus()}, {"viscosity", liquid.viscosity()}};
  }
  std::ofstream out(file);
  out << info.dump(2) << "\n";
  if (!out) throw Error("cannot write " + file.string());
}

RunSummary Simulation::run(const RunOptions& options) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  const double end = scene_.end_time;

  // Output schedule: every writer writes the initial state, then at multiples
  // of its interval, and the final state.
  std::vector<double> interval(writers_.size()), next(writers_.size());
  if (!writers_.empty()) {
    std::filesystem::create_directories(options.output_dir);
    write_run_info(options.output_dir / (scene_.name + ".run.json"));
  }
  for (std::size_t w = 0; w < writers_.size(); ++w) {
    interval[w] = scene_.outputs[w].interval.value_or(end / 20);
    // One output keeps the scene's name; several get a suffix each.
    writers_[w]->open(options.output_dir,
                      writers_.size() == 1 ? scene_.name : scene_.name + "_" + std::to_string(w));
  }
  // Saturated runs: the mass ledger; scenes that ask for reactions: their
  // CSV. A row every end/200 s, flushed so that a run that fails midway
  // leaves the rows written so far.
  auto open_csv = [&](std::ofstream& csv, const std::string& suffix) {
    std::filesystem::create_directories(options.output_dir);
    const auto file = options.output_dir / (scene_.name + suffix);
    csv.open(file);
    if (!csv) throw Error("cannot write " + file.string());
    csv.precision(10);
  };
  std::ofstream ledger, reactions;
  const double ledger_interval = end / 200;
  double next_ledger = ledger_interval;
  if (species_ && !options.output_dir.empty()) {
    open_csv(ledger, ".ledger.csv");
    species_->write_ledger_row(ledger, clock_.time(), true);
    ledger.flush();
  }
  if (!reactions_->empty() && !options.output_dir.empty()) {
    open_csv(reactions, ".reactions.csv");
    reactions_->write_header(reactions);
    reactions.flush();
  }
  auto write = [&](std::size_t w) {
    detail::StageTimer timer(times_, Stage::output);
    writers_[w]->write(OutputFrame{domain_->points, domain_->grid, clock_.steps(), clock_.time()});
  };
  for (std::size_t w = 0; w < writers_.size(); ++w) {
    write(w);
    next[w] = interval[w];
  }

  const std::size_t first_step = clock_.steps();
  const double eps = 1e-9 * clock_.nominal_dt();
  clock_.run_until(end);
  while (!clock_.reached_end()) {
    const double dt = clock_.dt();
    step();
    const double now = clock_.time();
    for (std::size_t w = 0; w < writers_.size(); ++w) {
      if (now >= next[w] - eps || now >= end) {
        write(w);
        // The next multiple of the interval after now (one frame per step at most).
        next[w] = (std::floor((now + eps) / interval[w]) + 1) * interval[w];
      }
    }
    if (now >= next_ledger - eps || now >= end) {
      if (ledger.is_open()) {
        species_->write_ledger_row(ledger, now, false);
        ledger.flush();
      }
      if (reactions.is_open()) {
        reactions_->write_row(reactions, now);
        reactions.flush();
      }
      next_ledger = (std::floor((now + eps) / ledger_interval) + 1) * ledger_interval;
    }
    if (options.on_step) {
      options.on_step(Progress{clock_.steps(), now, end, dt, domain_->points.size(),
                               std::chrono::duration<double>(Clock::now() - start).count()});
    }
  }
  clock_.run_until(std::numeric_limits<double>::infinity());
  for (auto& w : writers_) w->close();

  RunSummary summary;
  summary.steps = clock_.steps() - first_step;
  summary.points = domain_->points.size();
  summary.simulated_time = clock_.time();
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double stepping = summary.wall_seconds - times_[Stage::output];
  summary.point_updates_per_second =
      stepping > 0 ? static_cast<double>(summary.steps) * static_cast<double>(summary.points) / stepping : 0.0;
  summary.stages = times_;
  if (species_) summary.ledger = mass_ledger();
  return summary;
}

}  // namespace suffuse
