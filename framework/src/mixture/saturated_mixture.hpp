#pragma once
// The saturated mixture of a two-phase run (single-point MPM, Jassim, Stolle
// & Vermeer 2013; docs/two-phase.md): the pore liquid's momentum, the drag
// between liquid and skeleton, the pore pressure and the permeability. Owns
// the liquid's point fields and nodal arrays, the liquids and the
// permeability laws.
#include <array>
#include <memory>
#include <optional>
#include <vector>

#include "mpm/domain.hpp"
#include "mpm/momentum_balance.hpp"
#include "mpm/point_fields.hpp"
#include "mixture/drainage.hpp"
#include "suffuse/boundary_condition.hpp"
#include "suffuse/liquid.hpp"

namespace suffuse::detail {

class InitialValues;
class StandingWaterLoad;

// Ids of the mixture's point fields.
struct MixtureFields {
  FieldId porosity, porosity_increment, pressure, pressure_rate, liquid_velocity, conductivity, darcy_flux,
      liquid_density, liquid_mass, moving_liquid_mass, bulk_modulus, grain_density, water_density;
  // In scenes whose pores drain above a phreatic surface (Scene::phreatic):
  // the degree of saturation S and the water potential psi (drainage.hpp).
  std::optional<FieldId> saturation, potential;
};

class SaturatedMixture final : public MomentumBalance {
 public:
  // The point fields it registers, for validation and for the constructor.
  static std::vector<FieldDeclaration<MixtureFields>> fields_declared();
  // The degree of saturation and the water potential, registered in scenes
  // with a phreatic surface.
  static FieldInfo saturation_field();
  static FieldInfo potential_field();

  SaturatedMixture(const Scene& scene, const Registry& registry, Domain& domain,
                   const std::vector<const Phase*>& phases,
                   const std::vector<std::unique_ptr<BoundaryCondition>>& conditions);

  // Saturated state of a body's points: porosity, pore pressure (uniform,
  // plus hydrostatic below a water table), liquid and its density (with the
  // suspended fines of `concentration`), conductivity.
  void initialise(const BodySpec& body, const BodyPoints& points, const InitialValues& initial);
  // The time-step limit of a saturated body (its undrained wave).
  double stable_time_step(const BodySpec& body, const Phase& phase, double h) const;

  void points_to_grid() override;
  void integrate_grid(double dt, double damping) override;
  void accelerations(double dt) override;
  void grid_to_points(double dt) override;
  void remap() override;

  // Stage "pore_pressure": nodal Darcy flux, porosity, Darcy flux at the
  // points, and the smoothed pore-pressure rate.
  void update_pore_pressure(double dt, std::size_t step, double time);
  // Still water standing on the bodies (bc/water_level), if any: where
  // pores drain, water enters a free surface only below it.
  void set_standing_water(const StandingWaterLoad* water) { water_ = water; }
  // Stage "permeability": K follows the porosity.
  void update_permeability();
  // A quasi-static run's grid faces are impermeable but where a condition
  // opens them; an explicit run's drain wherever nothing holds the liquid
  // (the pressure's natural condition, docs/boundaries.md). The collapse
  // after a quasi-static failure keeps the quasi-static faces: on every
  // grid-face node no condition opens, the liquid's normal velocity is held
  // to the skeleton's. Called after the conditions' constraints.
  void hold_liquid_on_closed_faces(NodeState& nodes) const;
  // Where a condition held the skeleton but left the liquid free, and the
  // drag is semi-implicit: the liquid's velocity again, dragged by the
  // skeleton's held velocity instead of the free one integrate_grid
  // predicted (two_phase_kernels.hpp, drag_against_held_solid). Called after
  // the conditions' constraints, before hold_liquid_on_closed_faces.
  void drag_against_held_solid(NodeState& nodes, double dt) const;

  const MixtureFields& fields() const { return f_; }
  // Nodal Darcy flux n_I (v_L - v_s)_I of this step (dim per node), shared
  // by the pressure rate and the transport.
  const std::vector<double>& nodal_darcy_flux() const { return node_darcy_; }
  std::vector<double>& nodal_darcy_flux() { return node_darcy_; }  // written by quasi-static steps
  const Liquid& liquid(std::size_t index) const { return *liquids_[index]; }
  double grain_density(std::size_t material) const { return phases_[material]->density(); }
  const std::vector<std::unique_ptr<Liquid>>& liquids() const { return liquids_; }

 private:
  void update_conductivity(const BodyPoints& b);
  // The grid-face nodes no condition opens (hold_liquid_on_closed_faces).
  void close_grid_faces(const std::vector<std::unique_ptr<BoundaryCondition>>& conditions);
  // Where pores drain (drained_pores.cpp): the water's share of the pores,
  // n S, and its conductivity, K k_r, per point, and the suction's force on
  // the liquid, for the points-to-grid scatter.
  void prepare_drained_pores();
  // The suction's pull through the faces open to the liquid (a drain, a
  // water table at the grid's face), which hold it at zero: added to the
  // nodal liquid forces.
  void add_suction_on_openings(double* liquid_force) const;
  // No water enters a node from a neighbour without pores (outside the
  // bodies), but where still water stands, and none leaves to it where the
  // node's pores drained (a seepage face is saturated): such components of
  // the node's Darcy flux are taken as zero in the water's balance and in
  // the transport.
  void close_free_surfaces();
  // The potential from the water the pores gained (drained_pores.hpp).
  void update_potential(double dt);

  Domain& d_;
  std::array<double, 3> gravity_;
  std::vector<std::optional<Drainage>> drains_;  // per material: its pores drain above the phreatic surface
  std::vector<double> free_velocity_, free_liquid_velocity_;  // integrate_grid's, before the constraints
  double mass_scaling_;
  std::vector<const Phase*> phases_;  // per material
  std::vector<std::unique_ptr<Liquid>> liquids_;
  std::vector<std::unique_ptr<PermeabilityLaw>> permeability_;  // per material, may be null
  std::vector<std::string> permeability_names_;                 // for messages, as phases are named
  MixtureFields f_{};
  std::vector<double> node_drag_, node_pressure_rate_, node_darcy_;
  // update_potential: the porosity of the points whose pores are full (else
  // 0) and of those that drain (else 0), and the latter's nodal rate.
  std::vector<double> full_porosity_, draining_porosity_, node_draining_rate_;
  std::vector<double> block_;  // a scatter's per-node sums (saturated_block, the remap's, the pressure rate's)
  std::vector<double> wet_porosity_, wet_conductivity_, suction_force_, node_suction_;  // prepare_drained_pores
  struct OpenNode {  // a node of a face open to the liquid: its number, axis, outward sign times area
    std::size_t node;
    int axis;
    double outward_area;
  };
  std::vector<OpenNode> open_nodes_;  // in scenes with a phreatic surface
  struct ClosedNode {  // a grid-face node no condition opens to the liquid, and the face's axis
    std::size_t node;
    int axis;
  };
  std::vector<ClosedNode> closed_nodes_;  // in quasi-static scenes whose failure is followed by a collapse
  const StandingWaterLoad* water_ = nullptr;
};

}  // namespace suffuse::detail
