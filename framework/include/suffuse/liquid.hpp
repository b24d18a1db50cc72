#pragma once
// Pore liquids and permeability laws, for saturated (two-phase) bodies.
#include <span>

namespace suffuse {

// The liquid that fills the pores of a saturated body.
class Liquid {
 public:
  virtual ~Liquid() = default;
  virtual double density() const = 0;        // rho_L [kg/m^3]
  virtual double bulk_modulus() const = 0;   // K_L [Pa]
  virtual double viscosity() const = 0;      // mu [Pa s]
};

// Standard gravity used in the definition of hydraulic conductivity,
// K = k rho_L g_ref / mu, whatever the scene's gravity.
inline constexpr double reference_gravity = 9.81;

// Bulk modulus of water [Pa]: the default liquid's, and the value below which
// a run reports a lowered (numerically softened) liquid.
inline constexpr double water_bulk_modulus = 2.2e9;

// Density of a pore liquid that carries a volume fraction c of suspended
// grains of density rho_s in water of density rho_w.
inline double suspension_density(double c, double rho_s, double rho_w) { return c * rho_s + (1 - c) * rho_w; }

// Hydraulic conductivity of a soil skeleton as a function of its porosity.
class PermeabilityLaw {
 public:
  virtual ~PermeabilityLaw() = default;
  // K [m/s] for each porosity n [-] of a batch (spans of equal length).
  virtual void conductivity(std::span<const double> porosity, std::span<double> conductivity) const = 0;
};

}  // namespace suffuse
