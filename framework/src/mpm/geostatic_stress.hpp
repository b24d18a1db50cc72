#pragma once

#include <cstddef>
#include <functional>
#include <span>

#include "suffuse/points.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

// The initial effective stress of a body with k0 (docs/two-phase.md): the
// total weight of the soil, its pore liquid and any water ponded above each
// point, minus the point's hydrostatic pore pressure; k0 times that
// horizontally. The soil above a point is its own body and every body
// stacked on it: a body whose bottom is the top of the one below, over the
// point's horizontal position (a levee on its foundation).
//
// weight(b, lo, hi): the total weight of body b's soil and pore liquid
// between the heights lo and hi, per unit area [Pa] (rho g (hi - lo) dry,
// ((1 - n) rho_s + n S rho_L) g integrated saturated, S below 1 where its
// pores drain above its water table); liquid_density: the pore liquid's
// density of body `body` (0 if dry); g: gravity's magnitude along the
// vertical (last) axis, downward.
using WeightBetween = std::function<double(std::size_t body, double lo, double hi)>;
void add_geostatic_stress(const Scene& scene, const WeightBetween& weight, std::size_t body, double liquid_density,
                          double g, PointSet& points, PointRange range);

}  // namespace suffuse::detail
