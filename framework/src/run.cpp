// Simulation::run: the time loop around step(), with outputs and timing.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>

#include <fstream>
#include <nlohmann/json.hpp>

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
  info["points"] = points_.size();
  info["time_step"] = dt_;
  info["time_step_mode"] = scene_.dt ? "fixed" : "automatic";
  info["cfl"] = scene_.cfl;
  info["mass_scaling"] = scene_.mass_scaling;
  info["end_time"] = scene_.end_time;
  info["damping"] = scene_.damping;
  info["threads"] = threads_;
  info["saturated"] = saturated_;
  for (std::size_t l = 0; l < liquids_.size(); ++l) {
    info["liquids"][scene_.liquids[l].name] = {{"density", liquids_[l]->density()},
                                               {"bulk_modulus", liquids_[l]->bulk_modulus()},
                                               {"viscosity", liquids_[l]->viscosity()}};
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
  // Saturated runs: the mass ledger, a row every end/200 s, flushed so that a
  // run that fails midway leaves the rows written so far.
  std::ofstream ledger;
  const double ledger_interval = end / 200;
  double next_ledger = ledger_interval;
  if (saturated_ && !options.output_dir.empty()) {
    std::filesystem::create_directories(options.output_dir);
    const auto file = options.output_dir / (scene_.name + ".ledger.csv");
    ledger.open(file);
    if (!ledger) throw Error("cannot write " + file.string());
    write_ledger_row(ledger, true);
    ledger.flush();
  }
  auto write = [&](std::size_t w) {
    const auto t0 = Clock::now();
    writers_[w]->write(OutputFrame{points_, grid_, step_, time_});
    times_.output += std::chrono::duration<double>(Clock::now() - t0).count();
  };
  for (std::size_t w = 0; w < writers_.size(); ++w) {
    write(w);
    next[w] = interval[w];
  }

  const double dt_nominal = dt_;
  const double t0 = time_;
  const std::size_t first_step = step_;
  // Time is t0 + k dt, not a running sum, so round-off neither adds a tiny
  // last step nor delays frames; eps absorbs the last bits.
  const double eps = 1e-9 * dt_nominal;
  std::size_t k = 0;
  while (time_ < end - eps) {
    dt_ = std::min(dt_nominal, end - time_);
    step();
    ++k;
    time_ = std::min(end, t0 + static_cast<double>(k) * dt_nominal);
    if (time_ >= end - eps) time_ = end;
    for (std::size_t w = 0; w < writers_.size(); ++w) {
      if (time_ >= next[w] - eps || time_ >= end) {
        write(w);
        // The next multiple of the interval after now (one frame per step at most).
        next[w] = (std::floor((time_ + eps) / interval[w]) + 1) * interval[w];
      }
    }
    if (ledger.is_open() && (time_ >= next_ledger - eps || time_ >= end)) {
      write_ledger_row(ledger, false);
      ledger.flush();
      next_ledger = (std::floor((time_ + eps) / ledger_interval) + 1) * ledger_interval;
    }
    if (options.on_step) {
      options.on_step(Progress{step_, time_, end, dt_, points_.size(),
                               std::chrono::duration<double>(Clock::now() - start).count()});
    }
  }
  dt_ = dt_nominal;
  for (auto& w : writers_) w->close();

  RunSummary summary;
  summary.steps = step_ - first_step;
  summary.points = points_.size();
  summary.simulated_time = time_;
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double stepping = summary.wall_seconds - times_.output;
  summary.point_updates_per_second =
      stepping > 0 ? static_cast<double>(summary.steps) * static_cast<double>(summary.points) / stepping : 0.0;
  summary.stages = times_;
  if (saturated_) summary.ledger = mass_ledger();
  return summary;
}

}  // namespace suffuse
