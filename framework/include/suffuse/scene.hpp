#pragma once
// A scene: the validated, typed description of one run. Built from JSON once;
// nothing downstream reads JSON again.
#include <array>
#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "suffuse/diagnostics.hpp"
#include "suffuse/internal_stability.hpp"
#include "suffuse/parameters.hpp"
#include "suffuse/plugin.hpp"
#include "suffuse/plugin_loader.hpp"
#include "suffuse/polygon.hpp"

namespace suffuse {

struct PluginNode {
  std::string type;     // plugin name, e.g. "phase/linear_elastic"
  std::string pointer;  // JSON pointer of the node
  Parameters params;    // validated against the plugin's schema
};

// A soil whose pores drain above the phreatic surface (docs/phreatic.md):
// above it the pore pressure is zero and the pores hold water by a retention
// curve of the water potential psi below zero, S = 1 / (1 + (psi / (gamma_w
// drainage_head))^2), with the conductivity's relative factor residual +
// (1 - residual) S^3.
struct DrainageSpec {
  double drainage_head = 0.05;           // [m] the head over which the pores drain
  double residual_conductivity = 1e-3;   // [-] of the saturated conductivity, where the pores are drained
};

struct MaterialSpec {
  std::string name;
  PluginNode phase;
  std::optional<PluginNode> base;          // the phase `phase` wraps, if its plugin wraps one
  std::optional<PluginNode> permeability;  // required when a saturated body uses it
  std::optional<PluginNode> erosion;       // an erosion law: the skeleton's fines can be washed out
  std::optional<DrainageSpec> phreatic;    // its pores drain above the phreatic surface
};

struct LiquidSpec {
  std::string name;
  PluginNode liquid;
};

struct BodySpec {
  std::string name;
  std::size_t material = 0;  // index into Scene::materials
  // The box the body fills, or, with a polygon, the box that holds it.
  std::array<double, 3> min{}, max{};
  // A polygon body (docs/geometry.md): in 2D in the x-y plane; in 3D in the
  // plane of the two axes but extrusion_axis (in increasing order), extruded
  // from min to max along that axis. Points lie on the grid's lattice
  // (points_per_cell per cell and axis), those whose centre is inside.
  std::optional<Polygon> polygon;
  int extrusion_axis = 2;
  // A body of points read from a file (docs/geometry.md): each point's
  // position and volume, row after row (dim + 1 values); it has no shape.
  std::vector<double> points;
  // Such a body's initial fields per point, where its file gives them: one
  // entry per row of `points`, in order (stress: 6 per point, Voigt,
  // effective, tension positive; velocities: dim per point). An empty field
  // takes the body's key at every point (the liquid's velocity: the
  // skeleton's; the saturation: the one its water table gives).
  struct PointValues {
    std::vector<double> stress, pore_pressure, porosity, velocity, fines_content, liquid_velocity, saturation;
  } point_values;
  int points_per_cell = 2;  // per axis
  std::array<double, 3> velocity{};
  std::optional<std::size_t> liquid;  // index into Scene::liquids: a saturated body
  double porosity = 0;                // initial, saturated bodies only
  std::array<double, 6> stress{};     // initial (effective) stress, Voigt
  double pore_pressure = 0;           // initial, saturated bodies only
  std::optional<double> water_table;  // hydrostatic initial pore pressure below it
  std::optional<double> k0;           // geostatic initial effective stress
  double fines_content = 0;           // f_c: erodible fines / solid volume, initial [-]
  double ultimate_fines_content = 0;  // f_c_inf: the part of f_c that never erodes [-]
  double concentration = 0;           // c: suspended fines / pore liquid volume, initial [-]
  std::string gradation_source;       // the body's PSD: its file, or its JSON pointer when inline
  std::optional<InternalStability> internal_stability;  // the criteria on its gradation, if it has one
  bool fines_content_from_gradation = false;            // fines_content is the gradation's erodible fines
};

struct OutputSpec {
  PluginNode writer;
  std::optional<double> interval;  // [s]; absent: end time / the writer's default frame count
  std::optional<std::string> name;  // names its files (output_basename)
};


// A boundary condition whose reaction the run records: the force its
// velocity constraints exert on the skeleton's nodes, and how far it moved
// them (<scene>.reactions.csv).
struct ReactionSpec {
  std::size_t condition;  // index into Scene::boundary_conditions
  std::string name;       // names its columns
};

// /factor_of_safety (docs/slope-stability.md): when and how finely the shear
// strength reduction finds the factor of safety of a quasi-static run.
struct FactorOfSafetySpec {
  std::optional<double> interval;  // [s] between evaluations; absent: at the start and the end only
  double tolerance = 0.01;         // the bracket's width in F at which the search stops
  double increment = 0.2;          // the first steps of F from 1, until a solve fails
  double max_factor = 10;          // F is not raised beyond it (a factor "at least" it)
  int max_iterations = 60;         // Newton iterations after which a solve counts as failed
};

// When a quasi-static run counts its structure as failed (/failure): a step
// without equilibrium even halved, or a factor of safety below this; and
// whether an explicit run then follows the collapse from the last
// equilibrium, for how long, at which Courant number, with frames how often.
struct FailureSpec {
  double factor_of_safety = 1.0;
  std::optional<double> collapse;                  // [s] of explicit dynamics after the failure
  double collapse_cfl = 0.5;                       // [-] its automatic step, as /time/cfl
  std::optional<double> collapse_output_interval;  // [s] between its frames; absent: a tenth of it
};

// How each point's volumetric strain rate is obtained: from its own velocity
// gradient, or as the volume-weighted mean over the points of its cell.
enum class VolumetricStrain { point, cell_average };

// How time is integrated (docs/time-integration.md): explicit dynamics
// (MUSL, steps bounded by the wave speeds), or a sequence of equilibria
// (implicit u-p consolidation, steps bounded by the slow processes).
enum class TimeIntegration { explicit_dynamics, quasi_static };

// The direct solver that factorises a quasi-static step's linear systems on
// one process (/time/linear_solver; on many, always PETSc's). automatic:
// MUMPS on grids of mumps_from_grid_nodes or more where the build has PETSc
// (the flood levee, 2,821 nodes: its first day in 8.0 s against Eigen's
// 16.7; a levee on 615 nodes took 16 s against Eigen's 12, PETSc's set-up
// of each solve costing more than the factorisation saves).
enum class LinearSolver { automatic, mumps, eigen };
inline constexpr std::size_t mumps_from_grid_nodes = 2000;

// The step control of a quasi-static run (/time).
struct QuasiStaticControls {
  double max_dt = 0;                     // [s] the largest step; 0: the first step's
  double growth = 1.5;                   // a step is at most this times the previous one
  double eroded_fraction_tolerance = 0.05;  // largest change of the eroded fraction of a point per step
  double transport_courant = 0.2;        // q dt_sub / (n h) of the transport substeps
  double steady_transport_tolerance = 1e-3;  // below it, the rest of a step is one implicit transport step
  double newton_tolerance = 1e-8;        // relative residual of the equilibrium
  int max_iterations = 25;               // per step, before the step is halved
  double creep = 1e-4;                   // regularising stiffness, a fraction of the skeleton's
  bool reuse_factors = true;             // later Newton iterations: GMRES with an earlier iteration's factors
  bool inertia = false;                  // the mixture's inertia in the equilibrium (implicit dynamics)
  LinearSolver linear_solver = LinearSolver::automatic;
};

struct Scene {
  std::filesystem::path file;
  std::string name;  // file stem, names output series
  std::string description;
  int dim = 2;
  std::array<double, 3> grid_origin{}, grid_cell_size{1, 1, 1};
  std::array<int, 3> grid_cells{1, 1, 1};
  std::array<bool, 3> grid_periodic{};  // axes along which the grid wraps (/grid/periodic)
  PluginNode shape_function;
  std::vector<MaterialSpec> materials;
  std::vector<LiquidSpec> liquids;
  std::vector<BodySpec> bodies;
  std::vector<PluginNode> boundary_conditions;
  std::vector<ReactionSpec> reactions;
  std::array<double, 3> gravity{};
  double damping = 0;  // local non-viscous damping coefficient
  std::optional<double> damping_until;  // [s]; absent: the damping acts for the whole run
  // The damping coefficient at time t: a damped start brings an explicit
  // run to its own equilibrium under its first loads, then lets it move freely.
  double damping_at(double t) const { return damping_until && t >= *damping_until ? 0.0 : damping; }
  VolumetricStrain volumetric_strain = VolumetricStrain::point;
  double sort_points_at_spread = 1.5;  // 0: the points keep their order (PointOrder)
  double end_time = 0;
  std::optional<double> dt;  // absent: automatic from the CFL condition (explicit); quasi-static: the first step
  double cfl = 0.5;
  TimeIntegration integration = TimeIntegration::explicit_dynamics;
  QuasiStaticControls quasi_static;
  double mass_scaling = 1;  // inertia factor for quasi-static runs
  bool dt_above_stable = false;  // a fixed dt above the stable one is accepted
  std::optional<double> checkpoint_interval;  // [s]; absent: no checkpoints during the run
  bool checkpoint_at_end = true;
  // Hash of the scene without what a restart may change (/time/end, the
  // checkpoint keys, /description): a checkpoint is only for its own scene.
  std::string fingerprint;
  std::vector<OutputSpec> outputs;
  std::optional<FactorOfSafetySpec> factor_of_safety;
  std::optional<FailureSpec> failure;

  bool erodible() const {
    for (const MaterialSpec& m : materials)
      if (m.erosion) return true;
    return false;
  }
  bool saturated() const {
    for (const BodySpec& b : bodies)
      if (b.liquid) return true;
    return false;
  }
  // A material's pores drain above a phreatic surface.
  bool phreatic() const {
    for (const MaterialSpec& m : materials)
      if (m.phreatic) return true;
    return false;
  }
};

// The stem of an output's files: <scene>.<name>, or <scene> when it is the
// only writer of its type, else <scene>_<index in /outputs>.
std::string output_basename(const Scene& scene, std::size_t output);

// Reads a scene file, loads the plugins it needs (scene paths, then the
// default search path) into `registry`, and validates the whole scene against
// the core and plugin schemas. Throws SceneError listing every problem found,
// or Error for unreadable files and libraries that fail to load.
Scene load_scene(const std::filesystem::path& file, Registry& registry, PluginLoader& loader);
// The same from JSON text; `name` stands for the file in messages and relative
// plugin paths are resolved against `base_dir`.
Scene parse_scene(const std::string& text, const std::string& name, const std::filesystem::path& base_dir,
                  Registry& registry, PluginLoader& loader);

// Schemas of the core sections of a scene, for `suffuse describe` and the docs.
struct CoreSection {
  std::string name;  // "scene", "grid", "time", "body", "output"
  std::string description;
  ParameterSchema schema;
};
std::vector<CoreSection> core_sections();

}  // namespace suffuse
