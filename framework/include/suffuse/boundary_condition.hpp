#pragma once
// Boundary conditions act on sets of grid nodes at named stages of the step,
// and may act through material points (a load carried by a body's surface).
#include <limits>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "suffuse/grid.hpp"
#include "suffuse/points.hpp"

namespace suffuse {

// A grid face, or a part of one, the pore liquid may cross (a drained face,
// a seepage inlet or outlet, a toe drain). Every other boundary of the grid
// is impermeable to the transport of the liquid and its suspended fines.
// Liquid entering carries `concentration` of fines. The mass ledger books
// what crosses it under `name` (default: the face's name).
struct LiquidOpening {
  GridFace face;
  double concentration = 0;          // volume of fines / volume of liquid entering [-]
  std::vector<std::int64_t> nodes;   // the face's nodes it opens (grid_face.hpp's face_nodes); empty: all
  std::string name;                  // its account in the ledger; empty: the face's name
};

// Still water outside the bodies (a river, a ditch, a flood over the
// ground), its surface at `level`: on the bodies' surface below it the
// water presses gamma_w (level - elevation), on the skeleton and on the pore
// liquid, along the stretch [from, to] of the first axis (x). The core
// integrates that pressure over the bodies (docs/boundaries.md, Water
// levels); the condition only says where the water stands, when.
struct StandingWater {
  double level = 0;          // elevation of the water's surface (y in 2D, z in 3D) [m]
  double unit_weight = 0;    // gamma_w [N/m^3]
  double from = -std::numeric_limits<double>::infinity();  // the stretch along x where it stands [m]
  double to = std::numeric_limits<double>::infinity();
};

// Factor of a load ramped linearly from zero at t = 0 to its full value at
// ramp_time, and held after it (ramp_time 0: full at once).
inline double ramp_factor(double time, double ramp_time) {
  return ramp_time > 0 ? std::min(1.0, time / ramp_time) : 1.0;
}

class BoundaryCondition {
 public:
  virtual ~BoundaryCondition() = default;

  // Resolve the node sets once, from the grid geometry.
  virtual void setup(const GridGeometry& grid) = 0;

  // Stage "apply_forces": add external nodal forces (tractions, loads).
  virtual void apply_forces(const GridGeometry& grid, NodeState& nodes, double time) const {
    (void)grid; (void)nodes; (void)time;
  }
  // Stage "constrain_velocity": impose nodal velocity components. Called after
  // every computation of nodal velocities (the grid update and the MUSL remap).
  virtual void constrain_velocity(const GridGeometry& grid, NodeState& nodes, double time) const {
    (void)grid; (void)nodes; (void)time;
  }
  // The water this condition stands on the bodies at `time`, if it is a
  // water level (default: none): a value at every time once at t = 0, on the
  // same stretch and of the same unit weight (its level may change). Asked
  // at the start and each time the loads are applied.
  virtual std::optional<StandingWater> standing_water(double time) const { (void)time; return std::nullopt; }
  // The faces this condition opens to the liquid (default: none).
  virtual std::vector<LiquidOpening> liquid_openings() const { return {}; }
  // Once, after the material points are created and before the first step.
  // The core never removes points, but may sort them again into the grid's
  // order (/sort_points_at_spread): a condition that keeps point numbers
  // then gets their new ones (follows_renumbering, renumber_loaded_points).
  virtual void setup_points(const GridGeometry& grid, const PointSet& points) { (void)grid; (void)points; }
  // Stage "apply_forces", right after apply_forces(grid, nodes, time): add
  // external nodal forces that act through the material points (a load that
  // moves with a body's surface), from the points at the start of the step.
  virtual void apply_point_forces(const GridGeometry& grid, const PointSet& points, NodeState& nodes,
                                  double time) const {
    (void)grid; (void)points; (void)nodes; (void)time;
  }
  // True for a condition that overrides setup_points or apply_point_forces.
  // On many processes (docs/parallel.md) setup_points sees every point, and
  // apply_point_forces the points it reads (gathered each step) on every
  // process: a condition that returns false is not called on many processes.
  virtual bool loads_points() const { return false; }
  // The points (numbers as setup_points saw them, or as renumbered since)
  // whose fields apply_point_forces reads; asked after setup_points and
  // after each renumbering. On many processes only these points' fields are
  // gathered each step (the others hold stale values); empty, the default:
  // every point's (such a condition must not keep point numbers).
  virtual std::vector<std::size_t> loaded_points() const { return {}; }
  // Whether the condition follows when the run sorts its points again into
  // the grid's order (/sort_points_at_spread, docs/parallel.md), which
  // changes their numbers. A scene that sorts refuses, before its first
  // step, a condition that loads points (loads_points()) and does not
  // follow. A condition that keeps point numbers must say loads_points().
  virtual bool follows_renumbering() const { return false; }
  // After a sort, and in a run restarted from a checkpoint written after
  // one: the numbers, now, of the points loaded_points() named when
  // setup_points ran, in that order (on every process).
  virtual void renumber_loaded_points(std::span<const std::size_t> new_numbers) { (void)new_numbers; }
};

}  // namespace suffuse
