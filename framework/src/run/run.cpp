// Simulation::run: the time loop around step(), with outputs and timing.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>

#include "mpm/domain.hpp"
#include "mpm/point_order.hpp"
#include "quasi_static/quasi_static.hpp"
#include "scene/scene_reader.hpp"
#include "mpm/reactions.hpp"
#include "mixture/standing_water.hpp"
#include "run/named_condition.hpp"
#include "io/run_outputs.hpp"
#include "mixture/saturated_mixture.hpp"
#include "transport/species_transport.hpp"
#include "common/stage_timer.hpp"
#include "suffuse/error.hpp"
#include "suffuse/simulation.hpp"
#include "suffuse/version.hpp"
#include "suffuse/writer.hpp"

namespace suffuse {

// The numerical choices of the run, next to its outputs, so that a reduced
// liquid bulk modulus or a chosen time step is never silent.
void Simulation::write_run_info(const std::filesystem::path& file) const {
  nlohmann::ordered_json info;
  info["suffuse_version"] = framework_version;
  info["scene"] = scene_.file.string();
  info["dimension"] = scene_.dim;
  info["points"] = point_count();
  info["processes"] = processes();
  info["time_step"] = clock_.nominal_dt();
  info["time_step_mode"] = scene_.dt ? "fixed" : "automatic";
  info["cfl"] = scene_.cfl;
  info["mass_scaling"] = scene_.mass_scaling;
  info["end_time"] = scene_.end_time;
  info["damping"] = scene_.damping;
  if (scene_.damping_until) info["damping_until"] = *scene_.damping_until;
  info["threads"] = threads();
  info["kernels"] = kernels();
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
  double end = scene_.end_time;  // a collapse's end once it follows a failure
  const std::filesystem::path& dir = options.output_dir;

  detail::RunOutputs outputs(scene_, writers_, dir, *domain_, species_.get(), *reactions_, *grid_projection_, times_);
  // Factors of safety (/factor_of_safety): after the first step, at
  // multiples of the interval and at the end, each a row of
  // <scene>.factor_of_safety.csv (complete after each row), evaluated before
  // that time's frames so that they show its mechanism. Not before the first
  // step: the initial stresses (K0 under a slope) are not an equilibrium, and
  // a strength reduction from them (its pressures held) found 0.99 for a
  // levee whose first steps converge, 1.72 for Griffiths and Lane's slope
  // on 1 m cells against 1.80 after its first step.
  std::vector<std::pair<double, SafetyFactor>> factors;
  std::ofstream safety_csv;
  const std::optional<FactorOfSafetySpec>& safety = scene_.factor_of_safety;
  auto next_safety = [&](double now) {
    return safety && safety->interval
               ? (std::floor((now + 1e-9 * *safety->interval) / *safety->interval) + 1) * *safety->interval
               : std::numeric_limits<double>::infinity();
  };
  auto open_safety_csv = [&](std::optional<double> resume_time) {
    if (!safety || dir.empty() || !domain_->comm.root()) return;
    const std::filesystem::path file = dir / (scene_.name + ".factor_of_safety.csv");
    const bool append = resume_time && keep_csv_rows_until(file, *resume_time);
    std::filesystem::create_directories(dir);
    safety_csv.open(file, append ? std::ios::app : std::ios::trunc);
    if (!safety_csv) throw Error("cannot write " + file.string());
    safety_csv.precision(10);
    if (!append)
      safety_csv << "time [s],factor_of_safety [-],failed_at [-],solves [-],newton_iterations [-]\n" << std::flush;
  };
  auto evaluate_safety = [&] {
    const SafetyFactor f = factor_of_safety();
    factors.emplace_back(clock_.time(), f);
    if (scene_.failure && f.factor < scene_.failure->factor_of_safety)
      failure_ = RunFailure{clock_.time(), "the factor of safety, " + detail::format(f.factor) +
                                               ", fell below /failure/factor_of_safety = " +
                                               detail::format(scene_.failure->factor_of_safety)};
    if (!safety_csv.is_open()) return;
    safety_csv << clock_.time() << ',' << f.factor << ',';
    if (std::isfinite(f.failed_at)) safety_csv << f.failed_at;  // empty: every factor up to max_factor held
    safety_csv << ',' << f.solves << ',' << f.newton_iterations << '\n' << std::flush;
  };
  if (!options.restart.empty()) {
    const Restored restored = load_checkpoint(options.restart);
    end = end_time();  // a checkpoint of a collapse goes on with it
    // A finished run's checkpoint stands for its end, even when it holds the
    // state before its last, shortened step (below).
    const double at = std::max(clock_.time(), restored.ends_run_at.value_or(clock_.time()));
    if (at >= end)
      throw Error("cannot restart from " + options.restart.string() + ": it is at t = " + std::to_string(at) +
                  " s, the " + (collapse_from_ ? "collapse" : "scene") + " ends at " + std::to_string(end) +
                  " s; raise " + (collapse_from_ ? "/failure/collapse" : "/time/end") + " to extend the run");
    outputs.resume(clock_.time(), clock_.steps(), restored.writers);
    if (collapse_from_) outputs.follow_collapse(*collapse_from_, collapse_output_interval());
    open_safety_csv(clock_.time());
  } else {
    open_safety_csv(std::nullopt);
    outputs.start(clock_.time(), clock_.steps());
  }
  double safety_due = options.restart.empty() ? clock_.time() : next_safety(clock_.time());
  if (!dir.empty() && (!writers_.empty() || species_ || !reactions_->empty()) && domain_->comm.root())
    write_run_info(dir / (scene_.name + ".run.json"));

  // Checkpoints: at multiples of the interval and at the end, replacing one
  // file (the run's state is a few times its points' fields). The end's is
  // the state before the last step where that step is shortened to land on
  // the end time: a run extended from it then takes the steps a run given
  // the later end from the start takes, bit for bit (a checkpoint after the
  // shortened step would continue off that run's steps). It is written
  // beside, and takes the checkpoint's name once the step has reached the
  // end (a quasi-static step may be halved instead).
  const std::optional<double> checkpoint_interval =
      options.checkpoint_interval ? options.checkpoint_interval : scene_.checkpoint_interval;
  const std::filesystem::path checkpoint = dir / (scene_.name + ".checkpoint");
  auto next_checkpoint = [&](double now) {
    return checkpoint_interval ? (std::floor((now + 1e-9 * *checkpoint_interval) / *checkpoint_interval) + 1) *
                                     *checkpoint_interval
                               : std::numeric_limits<double>::infinity();
  };
  double checkpoint_due = next_checkpoint(clock_.time());
  const std::filesystem::path end_checkpoint = checkpoint.string() + ".end";
  struct RemoveUnused {  // a last step that fails leaves no end checkpoint behind
    const std::filesystem::path& file;
    bool writer;  // the process that writes checkpoints
    ~RemoveUnused() {
      std::error_code ignored;
      if (writer) std::filesystem::remove(file, ignored);
    }
  } remove_unused{end_checkpoint, domain_->comm.root()};

  const std::size_t first_step = clock_.steps();
  std::size_t collapse_first_step = clock_.steps();  // once a collapse follows a failure
  const std::size_t exchanged_before = domain_->exec.exchanged_values();
  clock_.run_until(end);
  while (!clock_.reached_end() && (!failure_ || collapse_from_)) {
    const double dt = clock_.dt();
    const bool end_saved_before = !dir.empty() && scene_.checkpoint_at_end && dt < clock_.nominal_dt();
    if (end_saved_before) {
      detail::StageTimer timer(times_, Stage::output);
      save_checkpoint(end_checkpoint, outputs.checkpoint(), end);
    }
    step();  // a step without equilibrium under /failure leaves the time as it was
    if (collapse_from_) measure_collapse();
    const double now = clock_.time();
    const bool at_end = clock_.reached_end();
    if (end_saved_before && at_end && domain_->comm.root()) std::filesystem::rename(end_checkpoint, checkpoint);
    // Every process stops at the same step (a signal may reach them apart).
    const bool stopping = !at_end && domain_->comm.any(options.stop && options.stop->load());
    if (safety && !failure_ && (now >= safety_due - 1e-9 * clock_.nominal_dt() || at_end)) {
      evaluate_safety();
      safety_due = next_safety(now);
    }
    // An interrupted or failed run ends like a finished one: a frame of
    // every output and a checkpoint (at a failure, the state handed on).
    const bool failed = failure_ && !collapse_from_;
    // A stop at the failure's step hands nothing over: its checkpoint is the
    // run's, from which a restart fails again and follows the collapse.
    const bool collapse_follows = failed && scene_.failure->collapse && !stopping;
    outputs.after_step(now, clock_.steps(), at_end || stopping || failed);
    if (!dir.empty() && !(end_saved_before && at_end) &&
        (now >= checkpoint_due - 1e-9 * clock_.nominal_dt() || (at_end && scene_.checkpoint_at_end) || stopping ||
         failed)) {
      // The state at the hand-over keeps a file of its own: the collapse's
      // checkpoints and its end's take the run's name.
      detail::StageTimer timer(times_, Stage::output);
      save_checkpoint(collapse_follows ? dir / (scene_.name + ".failure.checkpoint") : checkpoint,
                      outputs.checkpoint());
      checkpoint_due = next_checkpoint(now);
    }
    if (collapse_follows) {
      start_collapse();
      end = end_time();
      outputs.follow_collapse(now, collapse_output_interval());
      collapse_first_step = clock_.steps();
    }
    if (options.on_step) {
      options.on_step(Progress{clock_.steps(), now, end, dt, point_count(),
                               std::chrono::duration<double>(Clock::now() - start).count()});
    }
    if (stopping) break;
  }
  // Stopped: before the end, and not at a failure the run ends at (one
  // whose collapse was to follow was stopped before it started).
  const bool interrupted =
      !clock_.reached_end() && (!failure_ || collapse_from_ || (scene_.failure && scene_.failure->collapse));
  clock_.run_until(std::numeric_limits<double>::infinity());
  outputs.close();

  RunSummary summary;
  summary.steps = clock_.steps() - first_step;
  summary.points = point_count();
  summary.simulated_time = clock_.time();
  summary.wall_seconds = std::chrono::duration<double>(Clock::now() - start).count();
  const double stepping = summary.wall_seconds - times_[Stage::output] - times_[Stage::safety];
  summary.point_updates_per_second =
      stepping > 0 ? static_cast<double>(summary.steps) * static_cast<double>(summary.points) / stepping : 0.0;
  summary.stages = times_;
  summary.transport_substeps = transport_substeps_;
  summary.steady_transport_steps = steady_transport_steps_;
  summary.newton_iterations = newton_iterations_;
  summary.halved_steps = halved_steps_;
  summary.creep_held_first = creep_held_first_;
  summary.creep_held_from = creep_held_from_;
  summary.creep_held_most = creep_held_most_;
  summary.creep_held_most_at = creep_held_most_at_;
  summary.point_sorts = point_order_->sorts();
  if (quasi_static_) {
    summary.factorisations = quasi_static_->factorisations();
    summary.gmres_iterations = quasi_static_->gmres_iterations();
  }
  if (species_) summary.ledger = mass_ledger();
  summary.factors_of_safety = std::move(factors);
  summary.interrupted = interrupted;
  summary.failure = failure_;
  if (collapse_from_) {
    summary.collapse_steps = clock_.steps() - collapse_first_step;
    summarise_collapse(summary);
  }
  summary.exchanged_values = domain_->exec.exchanged_values() - exchanged_before;
  return summary;
}

std::vector<double> Simulation::solver_state() const {
  return quasi_static_ ? quasi_static_->equilibrium_pressures() : std::vector<double>{};
}

void Simulation::restore_solver_state(std::vector<double> values) {
  if (quasi_static_) quasi_static_->restore_equilibrium_pressures(std::move(values));
  else if (!values.empty())  // (a checkpoint is of the same scene: cannot happen)
    throw Error("cannot restart: the checkpoint holds a quasi-static solver's state, this run is explicit");
}

// The loads of the conditions and the water levels on the nodes at `time`.
void Simulation::apply_loads(NodeState& nodes, double time) {
  if (water_) water_->add_forces(*domain_, mixture_->fields(), nodes, time);
  // On many processes a condition that loads points reads every point, in
  // the serial run's numbering, on every process (gathered once per step):
  // each process adds the serial run's forces to its whole grid.
  const PointSet* every = nullptr;
  for (const auto& bc : bcs_) {
    bc->apply_forces(domain_->grid, nodes, time);
    if (!domain_->comm.parallel()) {
      bc->apply_point_forces(domain_->grid, domain_->points, nodes, time);
    } else if (bc->loads_points()) {
      if (!every) every = load_every_point_ ? &domain_->every_point() : &domain_->points_at(loaded_points_);
      bc->apply_point_forces(domain_->grid, *every, nodes, time);
    }
  }
  // The conditions spread their loads with the compact supports: what they
  // put on a periodic grid's images belongs to the nodes they are.
  domain_->periodic.fold(nodes.force, scene_.dim);
  if (!nodes.liquid_force.empty()) domain_->periodic.fold(nodes.liquid_force, scene_.dim);
}

}  // namespace suffuse
