#pragma once
// Erosion laws: the rate at which a seepage flow detaches erodible fines from
// the soil skeleton and carries them off as suspended fines in the pore liquid
// (mass exchange skeleton -> liquid, Vardoulakis et al. 1996).
//
// The core calls rate() once per batch of points of a material, with every
// span of the same length. The law only computes n_e; the core applies it:
// it moves the eroded solid mass rho_s n_e V dt from the skeleton to the
// liquid, raises the porosity by the eroded volume, and limits the step so
// that the fines content never drops below the body's ultimate fines content
// (a negative rate deposits suspended fines, at most those the point holds).
#include <span>

namespace suffuse {

struct ErosionBatch {
  std::span<const double> porosity;                 // n [-]
  std::span<const double> fines_content;            // f_c: erodible fines / solid volume [-]
  std::span<const double> ultimate_fines_content;   // f_c_inf: fines that can never be eroded [-]
  std::span<const double> concentration;            // c: suspended fines volume / pore liquid volume [-]
  std::span<const double> darcy_flux;               // |q| = n |v_L - v_s| [m/s]
  std::span<const double> hydraulic_gradient;       // |i| = |q| / K [-]
  std::span<double> rate;                           // out: n_e, eroded solid volume / volume / time [1/s]
};

class ErosionLaw {
 public:
  virtual ~ErosionLaw() = default;
  // Called from several threads at once, on disjoint batches: write only the
  // batch's `rate`, keep no mutable state. A rate that is not finite stops
  // the run with an error naming the point.
  virtual void rate(const ErosionBatch& batch) const = 0;
};

// Onset threshold shared by the bundled laws: no erosion where the hydraulic
// gradient is below i_cr (Uzuoka et al. 2012; Fujisawa et al. 2010).
inline void switch_off_below_gradient(const ErosionBatch& batch, double critical_gradient) {
  if (critical_gradient <= 0) return;
  for (std::size_t p = 0; p < batch.rate.size(); ++p)
    if (batch.hydraulic_gradient[p] < critical_gradient) batch.rate[p] = 0;
}

}  // namespace suffuse
