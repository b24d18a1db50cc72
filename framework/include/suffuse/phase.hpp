#pragma once
// A phase: the constitutive behaviour of one material (soil skeleton, pore liquid...).
#include <cstddef>

#include "suffuse/points.hpp"

namespace suffuse {

// A contiguous range of points made of one material.
struct PointRange {
  std::size_t begin = 0;
  std::size_t end = 0;
  std::size_t size() const { return end - begin; }
};

class Phase {
 public:
  virtual ~Phase() = default;

  // Mass density of the material [kg/m^3], used to give points their mass.
  virtual double density() const = 0;
  // Constrained (P-wave) modulus [Pa]; sqrt(M/rho) is the wave speed that
  // bounds the explicit time step.
  virtual double p_wave_modulus() const = 0;

  // Register per-point state fields and keep their ids. Called once at set-up.
  virtual void add_fields(PointSet& points) { (void)points; }
  // Set the initial state of this material's points (after geometry and mass).
  virtual void initialise(PointSet& points, PointRange range) const { (void)points; (void)range; }

  // Advance the stress of a batch of points over dt. The core has filled the
  // core "velocity_gradient" field (dim*dim, row-major L_ij = dv_i/dx_j).
  // Must be safe to call concurrently on disjoint ranges.
  virtual void update_stress(PointSet& points, PointRange range, double dt) const = 0;
};

}  // namespace suffuse
