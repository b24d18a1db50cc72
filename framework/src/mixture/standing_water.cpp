#include "mixture/standing_water.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <string>
#include <utility>

#include "mpm/point_supports.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

WaterProfile::WaterProfile(std::vector<StandingWater> stretches) : stretches_(std::move(stretches)) {
  std::sort(stretches_.begin(), stretches_.end(),
            [](const StandingWater& a, const StandingWater& b) { return a.from < b.from; });
}

std::pair<double, double> WaterProfile::level(double x) const {
  // Before the first stretch, its level; after the last, the last's; in a
  // gap, the line between the levels at its ends.
  if (x <= stretches_.front().to) return {stretches_.front().level, 0.0};
  for (std::size_t k = 1; k < stretches_.size(); ++k) {
    const StandingWater &a = stretches_[k - 1], &b = stretches_[k];
    if (x < b.from) {
      const double slope = (b.level - a.level) / (b.from - a.to);
      return {a.level + slope * (x - a.to), slope};
    }
    if (x <= b.to) return {b.level, 0.0};
  }
  return {stretches_.back().level, 0.0};
}

namespace {
std::string text(double v) {
  std::ostringstream o;
  o << v;
  return o.str();
}
}  // namespace

StandingWaterLoad::StandingWaterLoad(const std::vector<const BoundaryCondition*>& conditions,
                                     const std::vector<std::string>& names) {
  for (std::size_t k = 0; k < conditions.size(); ++k)
    if (conditions[k]->standing_water(0.0)) conditions_.push_back(conditions[k]), names_.push_back(names[k]);
  for (std::size_t a = 0; a < conditions_.size(); ++a)
    for (std::size_t b = a + 1; b < conditions_.size(); ++b) {
      const StandingWater wa = *conditions_[a]->standing_water(0.0), wb = *conditions_[b]->standing_water(0.0);
      if (wa.from < wb.to && wb.from < wa.to)
        throw Error(names_[b] + ": its stretch of x [" + text(wb.from) + ", " + text(wb.to) +
                    "] overlaps that of " + names_[a] + " [" + text(wa.from) + ", " +
                    text(wa.to) + "]; expected water levels on separate stretches (from, to), "
                    "the level interpolated between them");
      if (wa.unit_weight != wb.unit_weight)
        throw Error(names_[b] + ": unit_weight " + text(wb.unit_weight) + " N/m^3 differs from that of " +
                    names_[a] + " (" + text(wa.unit_weight) + "); expected one water");
    }
}

WaterProfile StandingWaterLoad::profile(double time) const {
  std::vector<StandingWater> stretches;
  for (const BoundaryCondition* c : conditions_) stretches.push_back(*c->standing_water(time));
  return WaterProfile(std::move(stretches));
}

namespace {

// -V (grad N p_w + N grad p_w) of each point to its nodes: the mixture's
// force (every point), then the liquid's (saturated points), 2 D per node.
template <int D>
void scatter_water_forces(std::size_t begin, std::size_t end, const PointSupports& s, const WaterProfile& water,
                          const double* x, const double* volume, const double* porosity, double* block) {
  const double gamma = water.unit_weight();
  for (std::size_t p = begin; p < end; ++p) {
    const double* xp = x + p * D;
    const auto [level, slope] = water.level(xp[0]);
    const double depth = level - xp[D - 1];
    if (!(depth > 0)) continue;  // above the water
    const double V = volume[p], pw = gamma * depth;
    double grad_pw[D] = {};
    grad_pw[0] = gamma * slope;
    grad_pw[D - 1] += -gamma;
    const bool saturated = porosity[p] > 0;
    for_each_node<D>(s, p, [&](std::size_t node, double N, const double* grad) {
      double* o = block + node * 2 * D;
      for (int i = 0; i < D; ++i) {
        const double f = -V * (grad[i] * pw + N * grad_pw[i]);
        o[i] += f;
        if (saturated) o[D + i] += f;
      }
    });
  }
}

}  // namespace

void StandingWaterLoad::add_forces(Domain& d, const MixtureFields& f, NodeState& n, double time) {
  current_ = profile(time);
  const WaterProfile& water = *current_;
  const int dim = d.dim();
  d.clear_nodal(block_, 2 * static_cast<std::size_t>(dim));
  const PointSet& pts = d.points;
  const auto& c = pts.core();
  ScatterTargets targets = d.shape.targets(d.grid.node_count());
  targets.add(block_);
  d.exec.scatter(pts.size(), targets, [&](std::size_t b, std::size_t e, double* const* out) {
    auto scatter = dim == 2 ? &scatter_water_forces<2> : &scatter_water_forces<3>;
    scatter(b, e, d.shape.view(), water, pts.data(c.position), pts.data(c.volume), pts.data(f.porosity), out[0]);
  });
  d.for_nodes([&](int, std::size_t b, std::size_t e) {
    for (std::size_t I = b; I < e; ++I)
      for (int i = 0; i < dim; ++i) {
        n.force[I * dim + i] += block_[I * 2 * dim + i];
        n.liquid_force[I * dim + i] += block_[I * 2 * dim + dim + i];
      }
  });
}

}  // namespace suffuse::detail
