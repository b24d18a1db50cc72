#pragma once
// The factor of safety of the current state by shear strength reduction
// (Zienkiewicz et al. 1975; Griffiths and Lane 1999; docs/slope-stability.md):
// the largest factor F by which the phases' strengths can be divided (c / F,
// tan(phi) / F) with an equilibrium still found.
//
// From the current state (an equilibrium at F = 1), F is raised in steps,
// each a quasi-static solve from the equilibrium of the last F that held,
// with the loads, the pore pressures and the points' positions as they are
// (small strains on the current configuration, no inertia, no erosion). A
// solve that does not converge within max_iterations brackets the factor;
// the bracket is then halved from its lower end until it is narrower than
// the tolerance. The state is put back as it was afterwards: the run goes
// on from its own equilibrium, and only the mechanism is kept (the shear
// strain the reduction added, on the way to the largest F that held).
#include <limits>
#include <vector>

#include "mpm/domain.hpp"
#include "mpm/materials.hpp"
#include "quasi_static/quasi_static.hpp"
#include "suffuse/scene.hpp"
#include "suffuse/simulation.hpp"

namespace suffuse::detail {

class StrengthReduction {
 public:
  // `mechanism`: the point field that receives the shear strain of the
  // reduction (none: not kept).
  StrengthReduction(const FactorOfSafetySpec& controls, Domain& domain, const Materials& materials,
                    QuasiStatic& solver, std::optional<FieldId> mechanism);
  // The factor of safety of the state at `time`, under that time's loads;
  // `dt` is the step the solves take (it scales nothing in them but the
  // nodal velocities they leave).
  SafetyFactor evaluate(double time, double dt);

 private:
  // Tries F from the state of the last F that held; true if it held (the
  // state is then its equilibrium, its strain added to the mechanism).
  bool holds(double F, double time, double dt, SafetyFactor& result);
  void save_points();
  void restore_points();

  FactorOfSafetySpec controls_;
  Domain& d_;
  const Materials& materials_;
  QuasiStatic& solver_;
  std::optional<FieldId> mechanism_;
  std::vector<std::vector<double>> saved_;  // every point field, as the evaluation found it
  std::vector<double> strain_;              // per point, 6: the strain the reduction added
};

}  // namespace suffuse::detail
