#pragma once
// Quasi-static integration of a step (docs/time-integration.md): the mixture
// in equilibrium at the end of the step, with the pore liquid's mass balance
// over the step (backward Euler), solved on the grid for the nodal
// displacement increments du and pore pressures p (the u-p formulation of
// consolidation, equal-order shape functions, integrated at the points):
//
//   [ K   -Q ] [du]   [ f_ext + f_gravity - f_int(sigma') + Q p ]
//   [ -Q' -C ] [dp] = [ -(b - Q' du - C p)                       ]
//
// K = sum V B' D B (the phases' tangents), Q = sum V grad N N (the pressure's
// force and the skeleton's volume change), C = S + dt H (storage n / K_L and
// Darcy flow K / gamma_w), b the old pressures' storage, gravity's flow and
// the inflow. The matrix is symmetric quasi-definite, so a sparse LDL'
// factorisation exists for any ordering (Vanderbei 1995): Eigen's
// SimplicialLDLT with AMD ordering; where a phase's tangent is not symmetric
// (Mohr-Coulomb with psi < phi), SparseLU with COLAMD ordering; a step's
// later iterations solve by GMRES with its last factors as preconditioner
// (quasi_static_linear.hpp, /time/reuse_factors). The stresses
// come from the phases' own updates, from the state at the start of the
// step, in every iteration: the tangent only steers the iterations (Newton's
// method with each phase's consistent tangent where it gives one, a
// backtracking line search), the equilibrium is that of the true stresses.
//
// Where the skeleton carries no stress (a cohesionless layer lifted by
// seepage above the critical gradient), there is no equilibrium at a fixed
// permeability. The nodes of points without stiffness get a small one,
// /time/creep times the skeleton's (V M |grad N|^2, M its P-wave modulus),
// holding them to their place at the start of the step: such a layer creeps
// from step to step, while its dilation raises its permeability, until
// equilibrium returns (as explicit runs show). Nowhere else.
//
// A node the body barely reaches (the points' sum N V below 1e-4 of the
// nodal volume: a point's support crossing into its cell by a sliver) has
// almost no stiffness; solved for, its increment is ill-determined and
// swings by metres, straining the points it touches. Such nodes have no
// unknowns: they follow the points they touch (follow_tail_nodes).
//
// With /time/inertia the mixture's inertia joins the balance of each node's
// displacement (backward Euler, the u-p approximation: the liquid moves
// with the skeleton): M (du - dt v0) / dt^2 in the residual, M / dt^2 on the
// diagonal, M and v0 the mixture's nodal mass and velocity at the step's
// start. Implicit dynamics: unconditionally stable, first order, damping
// each mode by 1 / sqrt(1 + omega^2 dt^2) per step; negligible in steps
// much longer than the soil's periods, and where the skeleton loses its
// equilibrium (a collapse) it lets the soil accelerate instead. The points'
// velocities then change as FLIP's do in explicit runs (update_points).
//
// Boundary conditions are read from the plugins' own effects on the nodes:
// a velocity constraint fixes du = v dt; a face a condition opens to the
// liquid fixes p there (bc/pore_pressure, the pressure read from its force
// -p n A) or brings the flux it constrains (bc/inflow_flux); grid faces
// closed to the liquid are impermeable; a free surface (a node next to a
// cell without saturated points) is drained where the surface is, not at
// the node (quasi_static_free_surface.cpp).
//
// On many processes (docs/parallel.md) each process adds its own points'
// terms; the nodal sums (masses, loads, forces, residuals) are then summed
// over the processes (the points' reach at free surfaces: its largest), so
// every process holds every node's and takes the same
// decisions (the unknowns, the line search, convergence). The matrix is
// PETSc's (DistributedSystem), each process adding its points' blocks.
#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "mpm/domain.hpp"
#include "mpm/materials.hpp"
#include "mixture/drainage.hpp"
#include "mixture/saturated_mixture.hpp"
#include "mixture/standing_water.hpp"
#include "suffuse/boundary_condition.hpp"

namespace suffuse::detail {

class QuasiStatic {
 public:
  // `apply_loads` adds the conditions' forces at a time to nodes (the
  // simulation's: on many processes the points a condition loads are read
  // in the serial numbering).
  using ApplyLoads = std::function<void(NodeState&, double)>;
  QuasiStatic(const Scene& scene, Domain& domain, const Materials& materials, SaturatedMixture* mixture,
              const std::vector<std::unique_ptr<BoundaryCondition>>& bcs, ApplyLoads apply_loads);
  ~QuasiStatic();

  // Stage "solve": the equilibrium at time + dt. Returns the iterations it
  // took, or nothing if it did not converge within the scene's
  // max_iterations; the stresses and the phases' state are then as at the
  // start of the step.
  std::optional<int> solve(double time, double dt);
  // Stage "g2p", after a converged solve: points move by the solved
  // increments; strain, volume, porosity, pore pressure and Darcy flux
  // follow (the nodal Darcy flux too, for the transport).
  void update_points(double dt);
  // A strength reduction (run/factor_of_safety.hpp): while a factor F is
  // set, solve() finds the equilibrium with every phase's strength divided
  // by F, the pore pressures held at the points' (no pressure unknowns),
  // without inertia and without the phases' eigenstrain (the caller zeroes
  // the step's), a solve failing after `max_iterations`. nullopt: the run's
  // own steps.
  void reduce_strength(std::optional<double> factor, int max_iterations = 0) {
    reduction_ = factor;
    reduction_iterations_ = max_iterations;
  }
  // The last equilibrium's nodal pressures (NaN where a node had none), for
  // checkpoints: a restart starts its first step as the run would have.
  const std::vector<double>& equilibrium_pressures() const { return accepted_p_; }
  void restore_equilibrium_pressures(std::vector<double> p) { equilibrium_p_ = accepted_p_ = std::move(p); }
  // The run takes the equilibrium solve() found: the next step starts from
  // its pressures. An attempt the run rejects (halved, or moving a cell or
  // more under /failure) leaves the next attempt to start where it did.
  void accept_step() { accepted_p_ = equilibrium_p_; }
  // What boundary condition `b` (one whose reaction the scene records) does
  // at the last converged equilibrium: the force its velocity constraints
  // exert on the soil, f_int - f_ext summed over the components it holds
  // (the total force in saturated runs), and the mass-weighted mean
  // displacement increment it imposed there.
  struct Held {
    std::array<double, 3> force{}, displacement{};
  };
  Held held_by(std::size_t b) const;
  // Where the last solve that did not converge stood, for the error that
  // stops the run: the node with the largest out-of-balance force, and the
  // points without stiffness at the last iteration (empty after a
  // converged solve).
  const std::string& failure() const { return failure_; }
  // The iterations of the last solve that did not converge.
  int attempted_iterations() const { return attempted_iterations_; }
  // Water levels (bc/water_level): below them a free surface holds the
  // water's pressure instead of zero. Their load on the skeleton comes
  // through apply_loads.
  void set_standing_water(const StandingWaterLoad* water) { water_ = water; }
  // The largest sum over the axes of |q_i| / (n h_i) at the points [1/s]:
  // a transport substep of Courant number C lasts C over it.
  double transport_rate() const;
  // Linear solves so far on one process: factorisations, and GMRES
  // iterations with the factors of an earlier matrix (quasi_static_linear.hpp).
  std::size_t factorisations() const { return factorisations_; }
  std::size_t gmres_iterations() const { return gmres_iterations_; }
  // Points the last assembly held with the creep term (/time/creep): without
  // stiffness, or separated across a plane (coupling::separated_directions),
  // summed over the processes. Where they form a layer (a heave, a
  // fluidised bed) its deformation is the creep term's, not a prediction
  // (docs/time-integration.md, Fluidisation).
  std::size_t creep_held_points() const { return creep_held_points_; }
  // The largest displacement of a node with mass over the last solve's
  // equilibrium (every process's) [m].
  double largest_increment() const;
  // A converged attempt not taken (under /failure, a mechanism's): the
  // points go back to the step's start, as after one that did not converge.
  void reject_attempt();
  // The last attempt's out-of-balance force relative to the forces, before
  // its first solve and after each iteration (how fast Newton converged).
  const std::vector<double>& residuals() const { return residuals_; }

 private:
  struct Linear;  // the sparse system and its factorisation
  void prepare(double time, double dt);  // degrees of freedom, constraints, loads of the step
  void save_state(std::vector<std::vector<double>>& into) const;
  void restore_state(const std::vector<std::vector<double>>& from);
  double evaluate(double dt);  // stresses from du, p; the residual; returns the norm of the forces'
  // Newton iterations from the current du, p, with a backtracking line
  // search; counts them; true if they converged (the state is then that of
  // the solution), else the state is restored.
  bool newton(double dt, int& iterations);
  void prepare_blocks();  // the node pairs the matrix couples, after prepare
  void assemble(double dt);  // the matrix, from the tangents at the iterate
  // False (a strength reduction's singular system) or throws.
  bool factorise_or_throw();
  void describe_failure();  // failure_, from the last iterate
  // Phreatic scenes: after a converged solve, closes the seepage-face nodes
  // water would enter through and opens the closed ones whose pressure rose
  // above zero; true if any changed (the step is then solved again).
  bool settle_seepage_faces();
  // A later seepage round's first iterate: the last round's equilibrium
  // (warm_du_, warm_p_, kept by solve), not the step's start.
  void warm_start();
  std::vector<double> warm_du_, warm_p_;
  // The nodal pressures of the last equilibrium a step found (NaN where a
  // node had none): the next step's Newton starts from them (prepare), and a
  // strength reduction holds them, not the points' projection of them, so
  // that its solve at full strength starts in that equilibrium.
  // accepted_p_: those of the last step the run took (accept_step), where
  // each solve() starts; equilibrium_p_ also holds its seepage rounds'.
  std::vector<double> equilibrium_p_, accepted_p_;
  void keep_equilibrium_pressures();
  // evaluate's terms of a point whose pores drain: its internal force with
  // the pressure max(psi, 0), its water balance with S(psi) and k_r; keeps
  // the matrix's factors of the point (coupling_, capacity_, relative_).
  void add_drained_point_terms(const Drainage& drains, std::size_t p, double psi, const double* grad_psi,
                               double div_u, double dt, std::vector<double>& f_int, std::vector<double>& r_p,
                               std::vector<double>& water_terms);
  // du of the tail nodes: the mean, weighted by N m, of the increments the
  // other nodes give the points they reach (a translation or rotation of
  // the body carries them along, a sliver of a point adds no strain).
  void follow_tail_nodes();

  const Scene& scene_;
  Domain& d_;
  const Materials& materials_;
  SaturatedMixture* mixture_;  // null in dry runs
  const std::vector<std::unique_ptr<BoundaryCondition>>& bcs_;
  ApplyLoads apply_loads_;
  std::unique_ptr<Linear> linear_;
  // Nodal sums of the points' terms over the processes (one process: nothing).
  void sum_over_processes(std::vector<double>& v) const { d_.comm.sum(v); }

  std::vector<std::vector<double>> saved_;  // the stress state an iteration starts from
  // The stress state at the start of the step, where the step's eigenstrain
  // was imposed before the iterations (restored if they fail).
  std::vector<std::vector<double>> step_start_;
  std::vector<double> tangent_;             // 36 per point
  NodeState probe_;                         // what the boundary conditions do to the nodes
  std::vector<std::int64_t> u_dof_, p_dof_;  // per node component / node: equation, or -1 (none or fixed)
  std::vector<double> du_, p_;               // the step's nodal unknowns, fixed values included
  std::vector<double> du_previous_, p_previous_;  // the last iterate, for the line search
  std::vector<double> f_ext_, b_p_;          // loads: mixture forces; pressure equations' right-hand side
  std::vector<double> node_mass_, node_pore_, node_volume_;
  // Nodes a body barely reaches (sum N V below min_cover of the nodal
  // volume: a point's support crossing a node's edge by a sliver). Their
  // stiffness is nearly nil, and solved for they swing by metres, straining
  // the points they touch; they have no unknowns and follow the points.
  std::vector<double> node_cover_;             // per node: sum N V over every point
  std::vector<std::int64_t> tail_nodes_;       // the nodes left without unknowns
  std::vector<std::size_t> tail_points_;       // the points that reach one
  std::vector<char> tail_mark_;                // per node: one of tail_nodes_
  std::vector<double> tail_sum_, tail_weight_;  // per node: work arrays of follow_tail_nodes
  std::vector<double> residual_;             // per equation
  std::vector<double> creep_;                // per node component: the regularising stiffness
  std::size_t creep_held_points_ = 0;        // the points that gave it (every process's)
  // With /time/inertia, per node component: M / dt^2, and dt v0 (empty without).
  std::vector<double> inertia_, inertia_target_;
  std::vector<double> f_int_, r_p_;          // per node: internal forces of the total stress; pressure equations' residual
  std::vector<double> point_pressure_;       // p interpolated at the points (saturated ones)
  std::vector<double> cell_count_;           // saturated points per cell
  std::vector<char> fixed_pressure_;         // per node: no unknown of its own (a face prescribes it; a free surface)
  // Free surfaces: per node, axis and side (+, -), the farthest reach of the
  // domains (x + l/2, -x + l/2) of the saturated points nearest the grid
  // line through the node along that axis, in its two cells; the surface nodes; and
  // those whose pressure follows a node inside (extrapolation()): their
  // p_dof_ is that node's, p_weight_ the factor (1 for every other node).
  std::vector<double> line_reach_;
  std::vector<char> surface_node_;
  struct Extrapolated {
    std::size_t node, from;
    double factor;
    double offset = 0;  // a submerged surface: (1 - factor) times the water's pressure where the surface is
  };
  const StandingWaterLoad* water_ = nullptr;
  // Pores that drain above a phreatic surface (mixture/drainage.hpp): per
  // material, none where its pores stay saturated.
  std::vector<std::optional<Drainage>> drainage_;
  bool phreatic_ = false;
  // Per point, at the step's start: the water potential psi (the pressure
  // where the pores are full); at the iterate: the factors of the matrix
  // (BlockTerms in quasi_static_assembly.cpp), one per point but drift_'s 3.
  std::vector<double> potential_, coupling_, saturation_, capacity_, relative_, drift_;
  // Per node: a free-surface node above the water levels, a seepage face,
  // drained where water leaves; 1 where it is closed (water would enter).
  std::vector<char> seepage_node_, seepage_closed_, seepage_switched_;  // switched: within this step
  std::vector<double> drains_;  // per node: sum N of the wet points whose pores drain
  int seepage_rounds_ = 0;
  std::vector<double> water_terms_;          // per node, evaluate's work array
  double water_norm_ = 0, water_scale_ = 0;  // the pressure equations' residual, and the size of their terms
  // The still water's pressure at x (zero without water levels, or above them).
  double water_pressure(const std::array<double, 3>& x) const;
  std::vector<Extrapolated> extrapolated_;
  std::vector<double> p_weight_;
  void measure_surface_reach();
  void find_free_surfaces();
  std::optional<Extrapolated> extrapolation(std::size_t node) const;
  void follow_inner_nodes();
  // Nodes whose pressure one face open to the liquid prescribes: the flux
  // through that face, from their pressure equation's residual.
  struct FaceFlux {
    std::int64_t node;
    int axis;
    double outward, area;
  };
  std::vector<FaceFlux> face_flux_;
  // Per condition whose reaction is recorded: the node components it constrains.
  std::vector<std::vector<std::size_t>> held_;
  std::vector<double> velocity_before_;  // the probe before such a condition constrains it
  // The matrix in blocks (prepare_blocks): per node with an unknown and per
  // slot of the stencil around it, (dim + 1)^2 values.
  std::vector<int> point_nodes_ijk_;         // 3 per point and support node
  std::vector<std::int64_t> block_node_;      // per node: its index among block_nodes_, or -1
  std::vector<std::int64_t> block_nodes_;     // the nodes with an unknown
  std::vector<double> blocks_;
  std::vector<char> block_used_;             // per node and slot: a point couples the pair
  int stencil_radius_ = 0, stencil_width_ = 1;
  std::size_t stencil_slots_ = 1;
  std::vector<double> modulus_;              // per material: the P-wave modulus, for the creep term
  double force_scale_ = 0;
  std::vector<double> residuals_;  // residuals()
  std::size_t equations_ = 0, displacement_equations_ = 0;  // the displacements' come first
  std::string failure_;
  std::size_t factorisations_ = 0, gmres_iterations_ = 0;
  std::optional<double> reduction_;  // reduce_strength()
  // Scenes with /failure: a singular system fails the attempt (a mechanism
  // without stiffness at the limit load) rather than the run.
  bool singular_fails_attempt_ = false;
  bool singular_ = false;  // the last attempt's system was singular
  int reduction_iterations_ = 0;
  int attempted_iterations_ = 0;
};

}  // namespace suffuse::detail
