#pragma once
// The mass balance of every species of a saturated run.
#include <string>
#include <vector>

namespace suffuse {

// What crossed one open face of the grid (a LiquidOpening), or left through
// the free surfaces of the bodies ("free_surface"), cumulative [kg].
struct BoundaryDischarge {
  std::string face;  // the account's name: its grid face's, a part's own, or "free_surface"
  double liquid_out = 0, liquid_in = 0;  // pore liquid, suspended fines included
  double fines_out = 0, fines_in = 0;    // suspended fines
  std::string grid_face;  // the grid face it is on (a part's too); empty for the free surfaces
};

// Mass of every species, in kg (per metre of thickness in 2D). Each balance
// is: what there was + what came in = what is there + what left.
struct MassLedger {
  double time = 0;
  double initial_solid = 0, initial_liquid = 0, initial_fines = 0;
  double solid = 0;            // skeleton, its fines included
  double skeleton_fines = 0;   // erodible fines still in the skeleton
  double suspended_fines = 0;  // fines carried by the pore liquid
  double liquid = 0;           // pore liquid, suspended fines included
  double eroded = 0;           // solid moved from skeleton to liquid, net of deposition
  std::vector<BoundaryDischarge> boundaries;

  double fines_discharged() const;
  // Relative imbalances: |in - there - out| / in (0 when nothing came in).
  double solid_imbalance() const;
  double liquid_imbalance() const;
  double fines_imbalance() const;
};

}  // namespace suffuse
