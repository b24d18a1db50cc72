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
    if (const auto w = conditions[k]->standing_water(0.0))
      conditions_.push_back(conditions[k]), names_.push_back(names[k]), first_.push_back(*w);
  for (std::size_t a = 0; a < conditions_.size(); ++a)
    for (std::size_t b = a + 1; b < conditions_.size(); ++b) {
      const StandingWater &wa = first_[a], &wb = first_[b];
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
  for (std::size_t k = 0; k < conditions_.size(); ++k) {
    const std::optional<StandingWater> w = conditions_[k]->standing_water(time);
    // A condition keeps its stretch and water for the run (checked at the start).
    if (!w || w->from != first_[k].from || w->to != first_[k].to || w->unit_weight != first_[k].unit_weight)
      throw Error(names_[k] + ": its water changed at t = " + text(time) + " s; expected a level at every time on "
                  "the stretch and of the unit weight it had at the start");
    stretches.push_back(*w);
  }
  return WaterProfile(std::move(stretches));
}

namespace {

// -V (grad N p_w + N grad p_w) of each point to its nodes: the mixture's
// force (every point), then the liquid's (saturated points), 2 D per node.
// That is the water's pressure on the whole boundary of the bodies, the
// faces they share with the grid's boundary included; there the grid face's
// own conditions act (a fixed base, rollers, a prescribed head), so a point
// whose domain's edge lies on such a face gives its part of that face back:
// p_w n A_p at its edge, on the nodes as the edge's position weighs them
// (the face's node and the next one in along the normal, the point's own
// weights along the face). An edge counts as on the face within a quarter
// of the point's (uGIMP) size: a body held on a face moves off it by its
// strain.
// (A give-back only while the edge lay on the face to 1e-6 of a cell
// stopped after a quasi-static run's first step; its face nodes then took
// the water's pressure twice, and a head prescribed there read 2 p.)
template <int D>
void scatter_water_forces(std::size_t begin, std::size_t end, const PointSupports& s, const GridGeometry& grid,
                          const PeriodicGrid& periodic, const WaterProfile& water, const double* x, const double* size, const double* volume,
                          const double* porosity, double* block) {
  const double gamma = water.unit_weight();
  const auto& cells = grid.cells();
  for (std::size_t p = begin; p < end; ++p) {
    const double* xp = x + p * D;
    const auto [level, slope] = water.level(xp[0]);
    const double depth = level - xp[D - 1];
    const bool saturated = porosity[p] > 0;
    if (depth > 0) {
      const double V = volume[p], pw = gamma * depth;
      double grad_pw[D] = {};
      grad_pw[0] = gamma * slope;
      grad_pw[D - 1] += -gamma;
      for_each_node<D>(s, p, [&](std::size_t node, double N, const double* grad) {
        double* o = block + node * 2 * D;
        for (int i = 0; i < D; ++i) {
          const double f = -V * (grad[i] * pw + N * grad_pw[i]);
          o[i] += f;
          if (saturated) o[D + i] += f;
        }
      });
    }
    // The faces of the grid this point's domain reaches.
    const double* lp = size + p * D;
    for (int a = 0; a < D; ++a)
      for (const bool upper : {false, true}) {
        if (periodic.along(a)) break;  // the seam is no face: the body goes on across it
        const double plane = grid.origin()[a] + (upper ? cells[a] * grid.cell_size()[a] : 0.0);
        // The edge as uGIMP sees it (half the size, at most half a cell),
        // and how far inside the face (an edge pushed past it is on it).
        const double h = grid.cell_size()[a], half = std::min(0.5 * lp[a], 0.5 * h);
        const double edge = xp[a] + (upper ? half : -half);
        const double gap = std::max(0.0, upper ? plane - edge : edge - plane);
        if (!(gap <= 0.5 * half)) continue;  // the body's own edge, not a point behind it
        double on_face[3] = {xp[0], xp[1], D == 3 ? xp[2] : 0.0};
        on_face[a] = upper ? plane - gap : plane + gap;
        const auto [face_level, face_slope] = water.level(on_face[0]);
        const double face_depth = face_level - on_face[D - 1];
        if (!(face_depth > 0)) continue;
        double area = 1;
        for (int b = 0; b < D; ++b)
          if (b != a) area *= lp[b];
        const double back = gamma * face_depth * area * (upper ? 1.0 : -1.0);  // + p_w n A_p, n outward
        const int face_index = upper ? cells[a] : 0, inner_index = upper ? cells[a] - 1 : 1;
        const auto first = grid.node_ijk(static_cast<std::int64_t>(s.first[p]));
        const std::size_t at = p * static_cast<std::size_t>(s.per_point);
        const double* w[3] = {s.weights + at, s.weights + at + s.nodes[0],
                              s.weights + at + s.nodes[0] + s.nodes[1]};
        const int mz = D == 3 ? s.nodes[2] : 1;
        for (int k = 0; k < mz; ++k)
          for (int j = 0; j < s.nodes[1]; ++j)
            for (int i = 0; i < s.nodes[0]; ++i) {
              const int offset[3] = {i, j, k};
              const int along = first[a] + offset[a];
              if (along != face_index && along != inner_index) continue;
              double weight = along == face_index ? 1 - gap / h : gap / h;
              for (int b = 0; b < D; ++b)
                if (b != a) weight *= w[b][offset[b]];
              const std::size_t node =
                  static_cast<std::size_t>(s.first[p] + i * s.stride[0] + j * s.stride[1] + k * s.stride[2]);
              block[node * 2 * D + a] += weight * back;
              if (saturated) block[node * 2 * D + D + a] += weight * back;
            }
      }
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
    scatter(b, e, d.shape.view(), d.grid, d.periodic, water, pts.data(c.position), pts.data(c.size), pts.data(c.volume),
            pts.data(f.porosity), out[0]);
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
