#pragma once

#include <cstddef>
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
// unit_weights[b]: body b's total unit weight [N/m^3] (rho g dry,
// ((1 - n) rho_s + n rho_L) g saturated); liquid_density: the pore liquid's
// density of body `body` (0 if dry); g: gravity's magnitude along the
// vertical (last) axis, downward.
void add_geostatic_stress(const Scene& scene, std::span<const double> unit_weights, std::size_t body,
                          double liquid_density, double g, PointSet& points, PointRange range);

}  // namespace suffuse::detail
