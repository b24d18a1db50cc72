#pragma once
// Boundary conditions act on sets of grid nodes at named stages of the step.
#include "suffuse/grid.hpp"

namespace suffuse {

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
};

}  // namespace suffuse
