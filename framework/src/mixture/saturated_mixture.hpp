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
#include "suffuse/liquid.hpp"

namespace suffuse::detail {

class InitialValues;

// Ids of the mixture's point fields.
struct MixtureFields {
  FieldId porosity, porosity_increment, pressure, pressure_rate, liquid_velocity, conductivity, darcy_flux,
      liquid_density, liquid_mass, moving_liquid_mass, bulk_modulus, grain_density, water_density;
  std::optional<FieldId> saturation;  // in scenes whose pores drain above a phreatic surface (Scene::phreatic)
};

class SaturatedMixture final : public MomentumBalance {
 public:
  // The point fields it registers, for validation and for the constructor.
  static std::vector<FieldDeclaration<MixtureFields>> fields_declared();
  // The degree of saturation, registered in scenes with a phreatic surface.
  static FieldInfo saturation_field();

  SaturatedMixture(const Scene& scene, const Registry& registry, Domain& domain,
                   const std::vector<const Phase*>& phases);

  // Saturated state of a body's points: porosity, pore pressure (uniform,
  // plus hydrostatic below a water table), liquid and its density (with the
  // suspended fines of `concentration`), conductivity.
  void initialise(const BodySpec& body, const BodyPoints& points, const InitialValues& initial);
  // The time-step limit of a saturated body (its undrained wave).
  double stable_time_step(const BodySpec& body, const Phase& phase, double h) const;

  void points_to_grid() override;
  void integrate_grid(double dt) override;
  void accelerations(double dt) override;
  void grid_to_points(double dt) override;
  void remap() override;

  // Stage "pore_pressure": nodal Darcy flux, porosity, Darcy flux at the
  // points, and the smoothed pore-pressure rate.
  void update_pore_pressure(double dt, std::size_t step, double time);
  // Stage "permeability": K follows the porosity.
  void update_permeability();

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

  Domain& d_;
  std::array<double, 3> gravity_;
  std::vector<std::optional<DrainageSpec>> drainage_;  // per material
  double damping_, mass_scaling_;
  std::vector<const Phase*> phases_;  // per material
  std::vector<std::unique_ptr<Liquid>> liquids_;
  std::vector<std::unique_ptr<PermeabilityLaw>> permeability_;  // per material, may be null
  std::vector<std::string> permeability_names_;                 // for messages, as phases are named
  MixtureFields f_{};
  std::vector<double> node_drag_, node_pressure_rate_, node_darcy_;
  std::vector<double> block_;  // a scatter's per-node sums (saturated_block, the remap's, the pressure rate's)
};

}  // namespace suffuse::detail
