#pragma once
// The grid fields of an output frame: what the points carry, projected on the
// nodes with the shape functions at the points' current positions (the same
// projection the next step's P2G makes). Computed only at frames of writers
// that ask for them, so the time loop pays nothing for it.
#include <vector>

#include "mpm/domain.hpp"
#include "suffuse/writer.hpp"

namespace suffuse::detail {

struct MixtureFields;

class GridProjection {
 public:
  // `mixture`: the saturated mixture's point fields, or null in dry runs;
  // `nodal_darcy`: its nodal Darcy flux (D per node).
  GridProjection(const MixtureFields* mixture, const std::vector<double>* nodal_darcy)
      : mixture_(mixture), nodal_darcy_(nodal_darcy) {}
  // mass, velocity (mass-weighted); saturated runs also liquid_velocity
  // (liquid-mass-weighted), pore_pressure (volume-weighted) and darcy_flux:
  // the nodal flux the transport moves the liquid with, so that a face's
  // flow rate is the one the mass ledger books.
  const std::vector<GridField>& project(Domain& domain);

 private:
  const MixtureFields* mixture_;
  const std::vector<double>* nodal_darcy_;
  Interpolation shape_;
  std::vector<GridField> fields_;
  std::vector<double> weight_;
};

}  // namespace suffuse::detail
