#pragma once
// A run of one scene: the parts that own its state, composed, and the MPM
// time loop that advances them (MUSL; docs/architecture.md).
//
//   Domain            grid, material points, shape functions, threads
//   Materials         one phase per material: the stress update
//   DryMomentum       the momentum balance of a dry run, or
//   SaturatedMixture  the two-phase mixture: liquid momentum, drag, pore
//                     pressure, permeability (saturated runs)
//   SpeciesTransport  erosion, transport of liquid and fines, mass ledger
//                     (saturated runs)
#include <array>
#include <atomic>
#include <cstddef>
#include <filesystem>
#include <functional>
#include <limits>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "suffuse/grid.hpp"
#include "suffuse/mass_ledger.hpp"
#include "suffuse/plugin.hpp"
#include "suffuse/points.hpp"
#include "suffuse/scene.hpp"

namespace suffuse {

namespace detail {
class Domain;
class Materials;
class Reactions;
class MomentumBalance;
class DryMomentum;
class SaturatedMixture;
class SpeciesTransport;
class GridProjection;
class StepGuard;
class QuasiStatic;
class StrengthReduction;
class PointOrder;
class StandingWaterLoad;
}  // namespace detail

// The stages of a step, in order, and the writing of outputs.
// Quasi-static steps add "solve" (the implicit u-p equilibrium, stresses
// included) and reuse shape, g2p, erosion, transport, permeability, check;
// "safety" is the time the factors of safety took (/factor_of_safety).
enum class Stage {
  shape, p2g, grid, g2p, remap, strain, pore_pressure, erosion, permeability, stress, transport, check, output, solve,
  safety
};
inline constexpr std::size_t stage_count = 15;
const char* stage_name(Stage stage);

// Wall time spent in each stage, for the run summary [s].
struct StageTimes {
  std::array<double, stage_count> seconds{};
  double& operator[](Stage s) { return seconds[static_cast<std::size_t>(s)]; }
  double operator[](Stage s) const { return seconds[static_cast<std::size_t>(s)]; }
};

struct Progress {
  std::size_t step;
  double time, end_time, dt;
  std::size_t points;
  double wall_seconds;
};

struct RunOptions {
  std::filesystem::path output_dir;              // where outputs go; empty: nothing is written
  std::function<void(const Progress&)> on_step;  // called after every step (may be empty)
  // Simulated time between checkpoints (<output_dir>/<scene>.checkpoint);
  // absent: the scene's /checkpoint/interval, if any.
  std::optional<double> checkpoint_interval;
  // Continue the run saved in this checkpoint instead of starting anew; the
  // outputs in output_dir continue after the checkpoint's time.
  std::filesystem::path restart;
  // When it turns true (a signal handler may set it), the run finishes the
  // step, writes every output and a checkpoint at that time, and returns
  // with RunSummary::interrupted set.
  const std::atomic<bool>* stop = nullptr;
};

// The factor of safety of a state by shear strength reduction
// (Simulation::factor_of_safety, docs/slope-stability.md).
struct SafetyFactor {
  double factor = 1;  // the largest F at which an equilibrium was found: the factor of safety
  // The smallest F tried without one (infinity: every F up to max_factor held).
  double failed_at = std::numeric_limits<double>::infinity();
  int solves = 0;              // equilibria tried
  int newton_iterations = 0;   // over every solve
  // The out-of-balance force the solve at full strength starts from, over
  // the forces: how far the state is from the equilibrium whose pore
  // pressures the solves hold (the configuration moved since).
  double start_residual = 0;
};

// A quasi-static run's structure failed (/failure): the time of its last
// equilibrium, and why no later one counts.
struct RunFailure {
  double time = 0;     // [s]
  std::string reason;  // a sentence: the equilibrium lost, or the factor of safety below the limit
};

struct RunSummary {
  std::size_t steps = 0;
  std::size_t points = 0;
  double simulated_time = 0;
  double wall_seconds = 0;
  double point_updates_per_second = 0;
  StageTimes stages;
  std::optional<MassLedger> ledger;  // saturated runs: the final balance
  // Quasi-static runs with a transport: its explicit substeps, and the steps
  // whose rest was one backward-Euler step once the transport was steady.
  std::size_t transport_substeps = 0, steady_transport_steps = 0;
  // Quasi-static runs: the Newton iterations of the steps that converged,
  // and the attempts that did not (each halved its step).
  std::size_t newton_iterations = 0, halved_steps = 0;
  // Quasi-static runs: the factorisations of their systems (on many
  // processes, PETSc's solves that set their preconditioner up anew), and
  // the GMRES iterations of the iterations that reused them.
  std::size_t factorisations = 0, gmres_iterations = 0;
  // Quasi-static runs: the material points converged steps held with the
  // creep term (without stiffness, or separated across a plane): the end of
  // the first step that held any and how many, and the most one step held
  // and when (times NaN if none did). Where they form a layer (a heave, a
  // fluidised bed), its deformation is the creep term's, not a prediction
  // (docs/time-integration.md, Fluidisation).
  std::size_t creep_held_first = 0, creep_held_most = 0;
  double creep_held_from = std::numeric_limits<double>::quiet_NaN();
  double creep_held_most_at = std::numeric_limits<double>::quiet_NaN();
  // Times the points were sorted again into the grid's order
  // (/sort_points_at_spread), points moving between processes.
  std::size_t point_sorts = 0;
  // Scenes with /factor_of_safety: each evaluation's time [s] and result.
  std::vector<std::pair<double, SafetyFactor>> factors_of_safety;
  // Scenes with /failure whose structure failed: the run stopped there, with
  // every output and a checkpoint at that time; or, with /failure/collapse,
  // an explicit run followed the collapse from there for collapse_steps
  // steps (of `steps`), to simulated_time.
  std::optional<RunFailure> failure;
  std::size_t collapse_steps = 0;
  // The collapse's largest movement: of any point since the failure [m],
  // and where that point is now (point field collapse_displacement). A
  // structure that collapses moves cells; one whose equilibrium was lost
  // by the solver, not by the structure, stays where it was.
  double collapse_movement = 0;
  std::array<double, 3> collapse_movement_at{};
  bool interrupted = false;          // stopped by RunOptions::stop before the end time
  // Runs on many processes: the values this process received from the
  // others in the scatters' exchanges (8 bytes each), over the run.
  std::size_t exchanged_values = 0;
};

// Simulated time, advanced in one place. A step of size dt() ends at
// t0 + k dt_nominal, not at a running sum, so round-off neither adds a tiny
// last step nor delays frames; the last step before an end time is shortened.
class SimulationClock {
 public:
  explicit SimulationClock(double dt) : nominal_(dt), dt_(dt) {}
  double time() const { return time_; }
  double dt() const { return dt_; }  // of the next step
  double nominal_dt() const { return nominal_; }
  std::size_t steps() const { return steps_; }
  // Steps from now on end at `end` at the latest.
  void run_until(double end);
  bool reached_end() const { return time_ >= end_ - eps(); }
  // Ends a step.
  void advance();

  // What a checkpoint keeps of it.
  struct State {
    double nominal, time, origin;
    std::size_t steps, since_origin;
  };
  State state() const { return {nominal_, time_, origin_, steps_, since_origin_}; }
  void restore(const State& s);
  // The next steps last dt (quasi-static runs adapt it): counted from now.
  void set_step(double dt);

 private:
  double eps() const { return 1e-9 * nominal_; }
  double nominal_, dt_, time_ = 0, origin_ = 0, end_ = std::numeric_limits<double>::infinity();
  std::size_t steps_ = 0, since_origin_ = 0;
};

class Simulation {
 public:
  // More steps than this are refused (a run of a week at 1e6 steps per hour).
  static constexpr double max_steps = 2e8;
  // Builds the parts of a validated scene. `threads` splits every stage into
  // that many contiguous chunks (OpenMP); results depend on the thread count
  // only through the order of floating-point sums.
  Simulation(const Scene& scene, const Registry& registry, int threads = 1);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // One step of size dt(): explicit (MUSL), or quasi-static (an implicit
  // equilibrium; the step may be halved until it converges, and the next
  // one adapts to the erosion).
  void step();
  // Steps until the end time, writing outputs; returns what it measured.
  RunSummary run(const RunOptions& options);

  double time() const { return clock_.time(); }
  double dt() const { return clock_.dt(); }
  std::size_t steps() const { return clock_.steps(); }
  int threads() const;
  // The instruction set of the vector kernels: "avx2" or "portable (sse2)"
  // ("portable" off x86-64); chosen from the processor, or from
  // SUFFUSE_KERNELS (docs/quickstart.md).
  std::string kernels() const;
  const Scene& scene() const { return scene_; }
  // This process's material points (all of them on one process).
  const PointSet& points() const;
  PointSet& points();
  // Points over every process of the run; the processes (mpirun -np N:
  // docs/parallel.md), and this one's rank (0: the one that writes outputs).
  std::size_t point_count() const;
  int processes() const;
  int process_rank() const;
  const GridGeometry& grid() const;
  const NodeState& nodes() const;
  const StageTimes& stage_times() const { return times_; }
  // Quasi-static runs, since this object was built (see RunSummary).
  std::size_t transport_substeps() const { return transport_substeps_; }
  std::size_t steady_transport_steps() const { return steady_transport_steps_; }
  std::size_t newton_iterations() const { return newton_iterations_; }
  std::size_t halved_steps() const { return halved_steps_; }
  // Times the points were sorted again into the grid's order (their
  // numbers then change: /sort_points_at_spread).
  std::size_t point_sorts() const;
  bool saturated() const { return mixture_ != nullptr; }
  // The liquid of /liquids entry `index` (scene order); saturated runs only.
  const Liquid& liquid(std::size_t index) const;

  // Quasi-static runs whose scene has a phase that reduces its strength
  // (phase/mohr_coulomb): the factor of safety of the state now, with the
  // scene's /factor_of_safety controls (their defaults if absent). The
  // state is as before afterwards; the point field "safety_shear_strain"
  // (scenes with /factor_of_safety) holds the mechanism.
  SafetyFactor factor_of_safety();
  // Scenes with /failure: set once the structure failed (a step found no
  // equilibrium even halved; run() also sets it when a factor of safety
  // falls below the limit), after which step() is not to be called.
  const std::optional<RunFailure>& failure() const { return failure_; }
  // Quasi-static runs: the last step's Newton iterations, as the
  // out-of-balance force relative to the forces before the first solve and
  // after each iteration (docs/time-integration.md, Tangents). Empty in
  // explicit runs.
  const std::vector<double>& newton_residuals() const { return newton_residuals_; }

  double total_mass() const;
  // Saturated runs: the mass of every species now (throws in dry runs).
  MassLedger mass_ledger() const;
  std::array<double, 3> total_momentum() const;
  // The automatic time step: cfl * h_min / max over materials of the wave
  // speed (the undrained wave in saturated bodies), times sqrt(mass scaling).
  double critical_time_step() const;

 private:
  template <class Work>
  void timed(Stage stage, Work&& work);
  void step_explicit();
  void step_quasi_static();
  std::optional<double> find_equilibrium();
  void create_bodies();
  std::vector<double> unit_weights() const;
  void refuse_or_keep_standing_water();
  void apply_loads(NodeState& nodes, double time);  // boundary conditions' external forces
  // The points the conditions that load points read (serial numbers), or
  // every point if one of them does not say (BoundaryCondition::loaded_points).
  std::vector<std::size_t> loaded_points_;
  // Per condition, the points it named at setup_points (their ids, the
  // point field "id", once the points may be sorted).
  std::vector<std::vector<std::size_t>> loaded_ids_;
  // Tells the conditions that keep point numbers their points' numbers now
  // (after a sort, or a restart from a checkpoint written after one).
  void renumber_loaded_points();
  bool load_every_point_ = false;
  // Stage "shape": the shape functions at the points, which are first
  // sorted again into the grid's order if they mixed (/sort_points_at_spread).
  void locate_points();
  // After the points were sorted again: the conditions' and the writers'
  // point numbers follow.
  void points_renumbered();
  void constrain_velocity(double time);
  // The same, measuring the reactions the scene asks for (the grid update's).
  void constrain_velocity_recording_reactions(double time, double dt, double damping);
  void write_run_info(const std::filesystem::path& file) const;
  void refuse_what_one_process_only_runs() const;  // on many processes
  void check_time_step() const;  // refuses a fixed step above the stable one, and endless runs
  // Checkpoints (checkpoint.cpp): `frames` is how many frames each writer
  // wrote; `ends_run_at`: the end time of the run whose end it stands for
  // (written before a last step shortened to land on that end).
  void save_checkpoint(const std::filesystem::path& file, const WriterCheckpoint& writers,
                       std::optional<double> ends_run_at = std::nullopt) const;
  struct Restored {
    WriterCheckpoint writers;           // each writer's frame count and state
    std::optional<double> ends_run_at;  // as saved
  };
  // Replaces the evolving state by the checkpoint's.
  Restored load_checkpoint(const std::filesystem::path& file);
  // What a quasi-static run's next step starts from besides the points (the
  // last equilibrium's nodal pressures, run.cpp); empty in explicit runs.
  std::vector<double> solver_state() const;
  void restore_solver_state(std::vector<double> values);
  // /failure/collapse (collapse.cpp): the explicit step that follows it, and
  // the hand-over from the last equilibrium; the time the run ends.
  double collapse_time_step() const;
  void check_collapse_steps() const;
  double collapse_output_interval() const;
  void start_collapse();
  double end_time() const;
  // The fields of a scene with /failure/collapse: each point's displacement
  // at the failure (kept, not written) and its movement since then.
  void add_collapse_fields();
  void measure_collapse();
  void summarise_collapse(RunSummary& summary) const;

  Scene scene_;
  std::unique_ptr<detail::Domain> domain_;
  std::unique_ptr<detail::Materials> materials_;
  std::unique_ptr<detail::Reactions> reactions_;
  std::vector<std::unique_ptr<BoundaryCondition>> bcs_;
  std::unique_ptr<detail::SaturatedMixture> mixture_;  // saturated runs
  std::unique_ptr<detail::DryMomentum> dry_;           // dry runs
  detail::MomentumBalance* momentum_ = nullptr;        // the one of the two this run has
  std::unique_ptr<detail::SpeciesTransport> species_;  // saturated runs
  std::unique_ptr<detail::StandingWaterLoad> water_;   // saturated runs with water levels
  std::vector<std::unique_ptr<Writer>> writers_;
  std::unique_ptr<detail::GridProjection> grid_projection_;  // for writers of grid fields
  std::unique_ptr<detail::StepGuard> guard_;                 // stops a run that blew up
  std::unique_ptr<detail::QuasiStatic> quasi_static_;        // quasi-static runs
  std::unique_ptr<detail::StrengthReduction> strength_reduction_;  // quasi-static runs, made when first asked
  std::optional<FieldId> safety_shear_strain_;               // scenes with /factor_of_safety
  std::optional<RunFailure> failure_;                        // scenes with /failure, once failed
  std::optional<double> collapse_from_;  // /failure/collapse: the time the explicit run took over
  std::optional<FieldId> failure_displacement_, collapse_displacement_;  // scenes with /failure/collapse
  std::vector<double> newton_residuals_;  // the last quasi-static step's
  std::unique_ptr<detail::PointOrder> point_order_;          // sorts the points when they mixed
  SimulationClock clock_{0};
  StageTimes times_;
  std::size_t transport_substeps_ = 0, steady_transport_steps_ = 0, newton_iterations_ = 0, halved_steps_ = 0;
  std::size_t creep_held_first_ = 0, creep_held_most_ = 0;  // RunSummary's creep_held_*
  double creep_held_from_ = std::numeric_limits<double>::quiet_NaN();
  double creep_held_most_at_ = std::numeric_limits<double>::quiet_NaN();
};

}  // namespace suffuse
