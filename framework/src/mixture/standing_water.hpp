#pragma once
// Still water outside the bodies (bc/water_level: a river on a levee's
// slope, a ditch at its toe, a flood over the ground) pressing on their
// surface. The pressure p_w = gamma_w (L - z) below the level L acts on the
// surface as the traction -p_w n, on the skeleton and on the pore liquid.
// Rather than finding the surface and its normals, the load is integrated
// over the bodies by the divergence theorem:
//
//   -integral over the surface of N_I p_w n = -integral over the bodies of (grad N_I p_w + N_I grad p_w),
//
// with the points as quadrature, the same as the pore pressure's own term
// (integral of grad N_I p). A body in still water (p = p_w at its points)
// is then in equilibrium to round-off whatever its shape: the liquid's
// forces cancel point by point, and the skeleton carries its buoyant
// weight. Only the values of p_w on the surface matter, so between the
// stretches of two conditions (a river and a ditch) the level is
// interpolated linearly along x: where that stretch meets the surface (a
// crest above both levels) p_w is zero either way; beyond the outermost
// stretches the nearest level holds, so that the level is continuous
// through the bodies (a cut in it would load them inside).
#include <optional>
#include <vector>

#include "mixture/saturated_mixture.hpp"
#include "mpm/domain.hpp"
#include "suffuse/boundary_condition.hpp"

namespace suffuse::detail {

// The level along x, from the stretches of the conditions at one time.
class WaterProfile {
 public:
  // Stretches that do not overlap (checked by StandingWaterLoad).
  explicit WaterProfile(std::vector<StandingWater> stretches);
  // The level at x and its slope along x (zero within a stretch).
  std::pair<double, double> level(double x) const;
  double unit_weight() const { return stretches_.front().unit_weight; }

 private:
  std::vector<StandingWater> stretches_;  // by `from`
};

class StandingWaterLoad {
 public:
  // The conditions among `conditions` that stand water; throws, naming
  // their JSON paths, where two stretches overlap or their unit weights
  // differ.
  StandingWaterLoad(const std::vector<const BoundaryCondition*>& conditions, const std::vector<std::string>& names);
  bool any() const { return !conditions_.empty(); }
  // The profile at `time`.
  WaterProfile profile(double time) const;
  // Adds the water's pressure on the bodies' surface to the mixture's and
  // the liquid's forces of `nodes` at `time`.
  void add_forces(Domain& d, const MixtureFields& f, NodeState& nodes, double time);
  // The profile add_forces last used: the level of this step's loads (the
  // transport lets water in below it).
  const WaterProfile& current() const { return *current_; }

 private:
  std::vector<const BoundaryCondition*> conditions_;
  std::vector<std::string> names_;
  std::vector<StandingWater> first_;  // each condition's water at the start
  std::vector<double> block_;  // per node, the mixture's then the liquid's force, D components each
  std::optional<WaterProfile> current_;
};

}  // namespace suffuse::detail
