#pragma once
// The MPM time loop: owns the grid, the material points and the plugin
// instances of one scene, and advances them step by step (MUSL, see
// docs/architecture.md).
#include <array>
#include <chrono>
#include <cstdint>
#include <exception>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "suffuse/grid.hpp"
#include "suffuse/plugin.hpp"
#include "suffuse/points.hpp"
#include "suffuse/scene.hpp"

namespace suffuse {

// Wall time spent in each stage of the step, for the run summary.
struct StageTimes {
  double shape = 0, reset = 0, p2g = 0, grid_update = 0, g2p = 0, remap = 0, stress = 0, erosion = 0,
         transport = 0, output = 0;
};

struct Progress {
  std::size_t step;
  double time, end_time, dt;
  std::size_t points;
  double wall_seconds;
};

struct RunOptions {
  std::filesystem::path output_dir;           // where writers put their files
  std::function<void(const Progress&)> on_step;  // called after every step (may be empty)
};

// What crossed one open face of the grid (a LiquidOpening), cumulative [kg].
struct BoundaryDischarge {
  std::string face;
  double liquid_out = 0, liquid_in = 0;  // pore liquid, suspended fines included
  double fines_out = 0, fines_in = 0;    // suspended fines
};

// Mass of every species of a saturated run, in kg (per metre of thickness in
// 2D). Each balance is: what there was + what came in = what is there + what left.
struct MassLedger {
  double time = 0;
  double initial_solid = 0, initial_liquid = 0, initial_fines = 0;
  double solid = 0;            // skeleton, its fines included
  double skeleton_fines = 0;   // erodible fines still in the skeleton
  double suspended_fines = 0;  // fines carried by the pore liquid
  double liquid = 0;           // pore liquid, suspended fines included
  double eroded = 0;           // solid moved from skeleton to liquid, net of deposition
  std::vector<BoundaryDischarge> boundaries;

  double fines_discharged() const;
  // Relative imbalances: |in - there - out| / in (0 when nothing came in).
  double solid_imbalance() const;
  double liquid_imbalance() const;
  double fines_imbalance() const;
};

struct RunSummary {
  std::size_t steps = 0;
  std::size_t points = 0;
  double simulated_time = 0;
  double wall_seconds = 0;
  double point_updates_per_second = 0;
  StageTimes stages;
  std::optional<MassLedger> ledger;  // saturated runs: the final balance
};

class Simulation {
 public:
  // Builds grid, points and plugins from a validated scene. `threads` splits
  // every stage into that many contiguous chunks (OpenMP); results depend on
  // the thread count only through the order of floating-point sums.
  Simulation(const Scene& scene, const Registry& registry, int threads = 1);
  ~Simulation();
  Simulation(const Simulation&) = delete;
  Simulation& operator=(const Simulation&) = delete;

  // One explicit MUSL step of size dt().
  void step();
  // Steps until the end time, writing outputs; returns what it measured.
  RunSummary run(const RunOptions& options);

  double time() const { return time_; }
  double dt() const { return dt_; }
  int threads() const { return threads_; }
  std::size_t steps() const { return step_; }
  const Scene& scene() const { return scene_; }
  const PointSet& points() const { return points_; }
  PointSet& points() { return points_; }
  const GridGeometry& grid() const { return grid_; }
  const NodeState& nodes() const { return nodes_; }
  const StageTimes& stage_times() const { return times_; }
  // The liquid of /liquids entry `index` (scene order).
  const Liquid& liquid(std::size_t index) const { return *liquids_[index]; }

  double total_mass() const;
  // Saturated runs: the mass of every species now (throws in dry runs).
  MassLedger mass_ledger() const;
  std::array<double, 3> total_momentum() const;
  // The automatic time step: cfl * h_min / max over materials of sqrt(M / rho).
  double critical_time_step() const;

 private:
  struct MaterialRange {
    std::size_t material;
    PointRange range;
    bool saturated;
  };
  // Node arrays a scatter adds into, at most 8.
  struct ScatterTargets {
    std::array<double*, 8> array{};
    std::array<std::size_t, 8> size{};
    int count = 0;
    void add(std::vector<double>& v) { array[count] = v.data(), size[count++] = v.size(); }
  };
  // Runs kernel(begin, end, targets) on chunks of the points; threads other
  // than the first write into private buffers that are summed afterwards.
  template <class Kernel>
  void scatter(const ScatterTargets& targets, Kernel&& kernel);
  void add_saturated_fields();
  void points_to_grid_saturated();
  void update_conductivity(const MaterialRange& r);
  void set_geostatic_state(const BodySpec& body, PointRange range);
  void add_species_fields();
  void set_species_state(const BodySpec& body, PointRange range);
  void setup_openings();
  void write_ledger_row(std::ostream& out, bool header) const;

  void create_points();
  void write_run_info(const std::filesystem::path& file) const;
  void check_points_in_grid() const;
  void compute_shape_functions();
  void reset_grid();
  void points_to_grid();
  void apply_external_forces();
  void update_grid();
  void grid_to_points();
  void remap_momentum();
  void update_stress();
  void erode();
  void update_permeability();
  void transport_liquid();
  void constrain_velocity();
  // Calls body(thread, begin, end) on threads() contiguous chunks of [0, n).
  template <class Body>
  void for_chunks(std::size_t n, Body&& body);

  int threads_ = 1;
  std::vector<std::vector<double>> scatter_;  // per extra thread: private node arrays
  std::vector<std::exception_ptr> chunk_errors_;  // per thread, for for_chunks

  Scene scene_;
  GridGeometry grid_;
  NodeState nodes_;
  PointSet points_;
  std::unique_ptr<ShapeFunction> shape_;
  std::vector<std::unique_ptr<Phase>> phases_;
  std::vector<std::unique_ptr<BoundaryCondition>> bcs_;
  std::vector<std::unique_ptr<Writer>> writers_;
  std::vector<std::unique_ptr<Liquid>> liquids_;
  std::vector<std::unique_ptr<PermeabilityLaw>> permeability_;  // per material, may be null

  // Saturated runs only.
  bool saturated_ = false;  // some body has a pore liquid
  struct SaturatedFields {
    FieldId porosity, pressure, liquid_velocity, conductivity, darcy_flux, liquid_density, liquid_mass, moving_liquid_mass,
        bulk_modulus, pressure_rate;
  } sf_{};
  std::vector<double> node_drag_, node_pressure_rate_, node_volume_;
  std::vector<MaterialRange> ranges_;

  // Species (liquid, fines) of saturated runs: docs/erosion.md.
  bool fines_ = false;  // some body carries erodible or suspended fines
  struct SpeciesFields {
    FieldId skeleton_fines, suspended_fines, eroded_mass, fines_content, ultimate_fines_content, concentration,
        eroded_fraction, erosion_rate, hydraulic_gradient, grain_density, water_density;
  } ef_{};
  std::vector<std::unique_ptr<ErosionLaw>> erosion_;  // per material, may be null
  std::vector<double> flux_magnitude_;                // per point, scratch of the erosion stage
  struct OpeningNode {
    std::int64_t node;
    double area;
  };
  struct Opening {  // what enters per volume is in inflow_liquid_ / inflow_fines_
    GridFace face;
    std::vector<OpeningNode> nodes;
  };
  std::vector<Opening> openings_;
  std::vector<BoundaryDischarge> discharge_;  // per opening, cumulative
  std::vector<std::array<double, 4>> discharge_step_, discharge_carry_;  // this step's share; summation carry
  double initial_solid_ = 0, initial_liquid_ = 0, initial_fines_ = 0;
  std::vector<double> node_darcy_, node_face_;  // dim per node: nodal Darcy flux, face volumes of the transport
  std::vector<double> node_pore_, node_liquid_, node_fines_, node_out_, node_dliquid_,
      node_dfines_, node_free_liquid_, node_free_fines_;
  std::vector<double> inflow_liquid_, inflow_fines_;  // per node and axis: what enters per volume, NaN: no inlet
  std::vector<std::string> body_names_;
  std::vector<PointRange> body_ranges_;

  int npp_ = 0;                          // nodes per point
  std::vector<std::int64_t> node_ids_;   // n * npp
  std::vector<double> weights_;          // n * npp
  std::vector<double> gradients_;        // n * npp * dim

  double time_ = 0, dt_ = 0;
  std::size_t step_ = 0;
  StageTimes times_;
};

}  // namespace suffuse
