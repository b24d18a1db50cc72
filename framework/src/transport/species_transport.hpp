#pragma once
// The species of a saturated run (docs/erosion.md): erosion moves fines from
// the skeleton to the pore liquid at the points; the liquid and its suspended
// fines then cross the grid with the Darcy flux, by a conservative finite-
// volume scheme on the dual cells; what crosses the open faces of the grid is
// booked per face, so the mass ledger closes to round-off.
#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mpm/domain.hpp"
#include "mixture/saturated_mixture.hpp"
#include "mixture/standing_water.hpp"
#include "suffuse/boundary_condition.hpp"
#include "suffuse/erosion_law.hpp"
#include "suffuse/mass_ledger.hpp"

namespace suffuse::detail {

class InitialValues;

class DistributedSystem;

// How the transport steps in time. Explicit steps use one forward-Euler
// stage (their step is far below the transport's limit). Quasi-static
// substeps at Courant numbers near it use Heun's method (SSP: a mean of two
// Euler stages, so it stays positive and conservative; second order in
// time). Backward Euler (first-order upwind, unconditionally stable,
// positive and conservative) takes what is left of a quasi-static step once
// the transport is steady: one sparse solve instead of thousands of substeps.
enum class TransportScheme { forward_euler, heun, backward_euler };

// Ids of the fines' point fields (runs that track fines).
struct FinesFields {
  FieldId skeleton_fines, suspended_fines, eroded_mass, fines_content, fines_content_increment, ultimate_fines_content,
      concentration, eroded_fraction, eroded_fraction_increment, erosion_rate, hydraulic_gradient, carrying_liquid;
};

class SpeciesTransport {
 public:
  // Node layers around a node whose inputs one explicit (forward Euler)
  // transport step reads (Transport: a face's flow reads the node upstream
  // of its upwind node, and a node's change the faces below it), so that a
  // process's nodes match the serial run's where its points read them
  // (Domain::set_halo_layers). Heun's second stage reads twice as far (the
  // quasi-static substeps: their halo is doubled); the backward-Euler step
  // gathers every node (species_transport_implicit.cpp).
  static constexpr int halo_layers = 2;
  // Fines are tracked when a body holds some, a material erodes, or an inlet brings them.
  static bool tracks_fines(const Scene& scene, const std::vector<LiquidOpening>& openings);
  // The point fields it registers when it tracks fines.
  static std::vector<FieldDeclaration<FinesFields>> fines_fields_declared();

  SpeciesTransport(const Scene& scene, const Registry& registry, Domain& domain, const SaturatedMixture& mixture,
                   const std::vector<std::unique_ptr<BoundaryCondition>>& bcs);
  ~SpeciesTransport();

  // Fines of a body's points (after the mixture's initialise).
  void initialise(const BodySpec& body, const BodyPoints& points, const InitialValues& initial);
  // The initial totals of the ledger, once every body is initialised.
  void start_ledger();

  // Stage "erosion": each material's erosion law, applied at the points.
  // Returns whether any point eroded or deposited. The laws see the points'
  // Darcy flux, or in a quasi-static step that kept its start's, the mean
  // of the step's start and end (start_step).
  bool erode(double dt);
  // Water levels (bc/water_level): their clean water enters the bodies
  // through free surfaces below the level, at the level of the step's
  // loads (StandingWaterLoad::add_forces). Explicit transport steps only.
  void set_standing_water(const StandingWaterLoad* water);
  // Stage "transport": liquid and suspended fines across the grid.
  void transport(double dt, TransportScheme scheme = TransportScheme::forward_euler);
  // Largest change over the last transport of a node's composition (over
  // every process): its
  // fines' share of the liquid (relative to the largest share on the grid),
  // and its carrying liquid's share; 0 in runs without fines. Not the liquid
  // per pore volume: that is the suspension's density wherever the nodal
  // fluxes balance, and what the points read (c, the liquid's density)
  // depends on the shares alone.
  double composition_change() const;

  // Quasi-static steps run erosion and transport in substeps: the fines
  // content and eroded fraction increments then span the whole step.
  void start_step();
  void finish_step();
  // Before a quasi-static step's equilibrium replaces the points' Darcy
  // flux: the step's substeps then erode with the mean of the flux at its
  // start and at its end, not the end's alone (the highest of the step while
  // a river rises), so that the erosion is second order in the step. One
  // flux for every substep: a substep that erodes nothing tells that the
  // rest erode nothing (the steady shortcut of Simulation::step_quasi_static).
  void keep_flux_at_start();
  // The largest |increment of the eroded fraction| of a point over the last
  // step, over every process.
  double largest_eroded_fraction_increment() const;

  MassLedger mass_ledger(double time) const;
  // One CSV row of the ledger (with the header first if asked).
  // A row of the ledger CSV (after its header if `header`); `l` from mass_ledger.
  void write_ledger_row(std::ostream& out, const MassLedger& l, bool header) const;

  // What a checkpoint keeps besides the point fields: the initial totals and
  // what crossed each boundary (with its summation carry).
  std::vector<double> saved_state() const;
  void restore_state(const std::vector<double>& state);  // throws if the size differs

 private:
  struct OpeningNode {
    std::int64_t node;
    double area;
  };
  struct Opening {  // what enters per volume is in inflow_liquid_ / inflow_fines_
    GridFace face;
    std::vector<OpeningNode> nodes;
    std::vector<std::int64_t> ids;                 // the nodes' numbers
    std::vector<std::array<double, 4>> crossed;    // per node, this stage: out, in of liquid; out, in of fines
  };
  void setup_openings(const Scene& scene, const SaturatedMixture& mixture,
                      const std::vector<std::unique_ptr<BoundaryCondition>>& bcs);
  void add_to_totals(const std::vector<std::array<double, 4>>& step);
  // One explicit stage from the given nodal amounts: changes in node_d*,
  // what crossed each account in `step`.
  void explicit_stage(double dt, const double* liquid, const double* fines, const double* carrying,
                      std::vector<std::array<double, 4>>& step);
  // A share of node I's liquid (and its fines and carrying liquid, given
  // per node) leaves the grid, booked to `account` (out of liquid, of fines).
  void discharge(std::size_t I, double share, const double* liquid, const double* fines, const double* carrying,
                 std::array<double, 4>& account);
  // The backward-Euler step (species_transport_implicit.cpp), same outputs.
  void implicit_stage(double dt);
  // The pore volume the liquid fills, per unit volume, per point: n, or
  // n S where pores drain above the phreatic surface (docs/phreatic.md),
  // so that the liquid moves with the Darcy flux through the water-filled
  // pores and a drained point's liquid weighs what its pores hold.
  const double* water_filled_porosity();

  Domain& d_;
  const MixtureFields& m_;
  const std::vector<double>& node_darcy_;
  std::vector<std::string> erosion_names_;  // "erosion law erosion/x of material 'm' (...)", for messages
  std::vector<std::unique_ptr<ErosionLaw>> erosion_;  // per material, may be null
  std::optional<FinesFields> fines_;                  // runs that track fines
  // Scratch of the erosion stage, per thread, for a block of erosion_block
  // points at a time (40 bytes per point were held for every point): |q|;
  // the carrying liquid's share of the pores, its concentration, and 0 (the
  // clean water's); the rate in the clean water.
  static constexpr std::size_t erosion_block = 1024;
  struct ErosionScratch {
    std::vector<double> flux_magnitude, carrier_share, carrier_concentration, clean_concentration, clean_rate;
  };
  std::vector<ErosionScratch> erosion_scratch_;
  std::vector<char> eroded_in_chunk_;  // per thread's chunk: some point eroded
  std::vector<double> step_fines_content_, step_eroded_fraction_;  // at the start of a quasi-static step
  std::vector<double> step_mean_flux_;  // a quasi-static step's: its start's Darcy flux, then the mean (start_step)

  std::vector<Opening> openings_;
  // Per node and axis: what enters per volume, NaN: no inlet.
  std::vector<double> inflow_liquid_, inflow_fines_, inflow_carrying_;
  std::vector<BoundaryDischarge> discharge_;          // per opening, then the free surfaces; cumulative
  std::vector<std::array<double, 4>> discharge_step_, discharge_carry_;  // this step's share; summation carry
  double initial_solid_ = 0, initial_liquid_ = 0, initial_fines_ = 0;
  std::vector<double> node_face_;  // dim per node: face volumes of the transport
  std::vector<double> node_pore_, node_liquid_, node_fines_, node_carrying_, node_out_, node_dliquid_, node_dfines_,
      node_dcarrying_, node_free_liquid_, node_free_fines_, node_free_carrying_;
  // Heun's first stage: its changes, and the nodal amounts after it.
  std::vector<double> stage_dliquid_, stage_dfines_, stage_dcarrying_, stage_liquid_, stage_fines_, stage_carrying_;
  std::vector<std::array<double, 4>> stage_discharge_;
  // What the exchange reads per node and per face (NodeShares).
  std::vector<double> node_per_pore_, node_fines_ratio_, node_carrying_ratio_, node_send_, face_flow_;
  // Per node, the scatter's sums (species_block) and the change shared per
  // amount held and per pore volume (share_block, g2p_share).
  std::vector<double> species_block_, share_block_;
  std::vector<double> water_filled_;  // n S per point, where pores drain (water_filled_porosity)
  std::unique_ptr<DistributedSystem> implicit_system_;  // the backward-Euler step's, on many processes
  // Still water on the bodies (set_standing_water): per node, whether it
  // stands above it this step, and the clean water each node took in
  // through its free-surface faces; the density of that water.
  const StandingWaterLoad* water_ = nullptr;
  std::vector<char> node_submerged_;
  std::vector<double> node_free_water_in_;
  double clean_water_density_ = 0;
};

}  // namespace suffuse::detail
