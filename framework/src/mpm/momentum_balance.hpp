#pragma once
// The momentum balance of the step on the grid: the dry skeleton's
// (DryMomentum) or the saturated mixture's (SaturatedMixture, two-phase).
// The boundary conditions act between these stages (Simulation::step).
namespace suffuse::detail {

class MomentumBalance {
 public:
  virtual ~MomentumBalance() = default;
  // Nodal masses, momenta and forces (internal, gravity) from the points.
  virtual void points_to_grid() = 0;
  // Nodal velocities at the end of the step from the forces, before the
  // velocity constraints; `damping` is the step's local damping coefficient
  // (Scene::damping_at).
  virtual void integrate_grid(double dt, double damping) = 0;
  // Nodal accelerations of the step, after the constraints.
  virtual void accelerations(double dt) = 0;
  // Point velocities (FLIP) and positions from the grid.
  virtual void grid_to_points(double dt) = 0;
  // MUSL: nodal velocities again, from the updated point momenta (then the
  // constraints once more).
  virtual void remap() = 0;
};

}  // namespace suffuse::detail
