#pragma once
// Erosion laws: rate of mass exchange from the soil skeleton to the pore liquid.
// Declared here so the SDK is stable; the two-phase and erosion solvers call it.
#include <span>

namespace suffuse {

// Inputs and output of one batch of points, all spans of the same length.
struct ErosionBatch {
  std::span<const double> porosity;            // n [-]
  std::span<const double> fines_content;       // f_c, erodible fines / solid volume [-]
  std::span<const double> concentration;       // c, fines volume / liquid volume [-]
  std::span<const double> darcy_flux;          // |q| [m/s]
  std::span<const double> hydraulic_gradient;  // |i| [-]
  std::span<double> rate;                      // n_e, eroded solid volume / volume / time [1/s]
};

class ErosionLaw {
 public:
  virtual ~ErosionLaw() = default;
  virtual void rate(const ErosionBatch& batch) const = 0;
};

}  // namespace suffuse
