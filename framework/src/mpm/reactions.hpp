#pragma once
// Reactions of boundary conditions: the force a condition's velocity
// constraints exert on the skeleton, and how far they moved it, for the
// conditions a scene names ("reaction"): a footing's load-settlement curve, the
// force on a retaining wall, the base shear of a column.
//
// The force is measured at the grid update, at the nodes whose velocity the
// condition changed, so it needs nothing from the plugin but its
// constrain_velocity(): R = sum_I m_I (v_I - p_I/m_I) / dt - F_I, the
// momentum the node gains over the step less its unbalanced force F_I
// (internal and external; the local damping, a numerical force, is not
// counted: with damping 0.1 it would add 10% to a footing's load). m_I is
// the nodal mass of the update (mass scaling included). The constraint
// after the MUSL remap re-imposes the same velocities on a projection and is
// not counted.
// The displacement along an axis is the time integral of the mass-weighted
// mean velocity of the nodes whose velocity the condition changed along it.
// Two conditions that hold the same component of a node both count its
// reaction there. Quasi-static steps give the force of their end-of-step
// equilibrium, R = f_int - f_ext at the components the condition holds
// (QuasiStatic::held_by), held over the step: a row is then the mean over
// the steps since the previous row, weighted by their lengths. In saturated runs the skeleton's nodal force is the
// mixture's (effective stress and pore pressure): the reaction is the total
// force on the soil.
#include <array>
#include <iosfwd>
#include <string>
#include <vector>

#include "mpm/domain.hpp"
#include "suffuse/boundary_condition.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

class Reactions {
 public:
  Reactions(const std::vector<ReactionSpec>& specs, int dim);

  bool empty() const { return records_.empty(); }
  // Before the step's first constraint: the free velocities of the grid
  // update, and the step's local damping (taken out of the reactions).
  void start_constraints(const Domain& domain, double damping);
  // Condition `b` constrains the nodes' velocities; if its reaction is
  // recorded, what it changed over the step `dt` is measured.
  void constrain(std::size_t b, const BoundaryCondition& bc, Domain& domain,
                 double time, double dt);

  // Quasi-static steps: record r's condition held the soil with `force` at
  // the step's equilibrium and moved it by `displacement` over the step.
  std::size_t size() const { return records_.size(); }
  std::size_t condition(std::size_t r) const { return records_[r].condition; }
  void add_equilibrium(std::size_t r, const std::array<double, 3>& force, const std::array<double, 3>& displacement,
                       double dt);

  // CSV: "time [s]", then per recorded condition its force components (the
  // mean over the steps since the previous row) and its displacement now.
  void write_header(std::ostream& out) const;
  void write_row(std::ostream& out, double time);

  // What a checkpoint keeps: each record's impulse, elapsed time and displacement.
  std::vector<double> saved_state() const;
  void restore_state(const std::vector<double>& state);  // throws if the size differs

 private:
  struct Record {
    std::size_t condition;
    std::string name;
    std::array<double, 3> impulse{}, displacement{};  // impulse since the last row [N s]
    double elapsed = 0;                               // time since the last row [s]
  };
  int dim_;
  double damping_ = 0;  // the step's local damping, taken out of the reactions
  std::vector<Record> records_;
  std::vector<double> free_;    // nodal velocities of the grid update, before any constraint
  std::vector<double> before_;  // nodal velocities before this condition's constraint
};

}  // namespace suffuse::detail
