#pragma once
// Boundary conditions act on sets of grid nodes at named stages of the step.
#include <algorithm>
#include <vector>

#include "suffuse/grid.hpp"

namespace suffuse {

// A grid face the pore liquid may cross (a drained face, a seepage inlet or
// outlet). Every other boundary is impermeable to the transport of the liquid
// and its suspended fines. Liquid entering carries `concentration` of fines.
struct LiquidOpening {
  GridFace face;
  double concentration = 0;  // volume of fines / volume of liquid entering [-]
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
  // The faces this condition opens to the liquid (default: none).
  virtual std::vector<LiquidOpening> liquid_openings() const { return {}; }
};

}  // namespace suffuse
