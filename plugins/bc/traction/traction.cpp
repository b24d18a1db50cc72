// bc/traction: a distributed load (surcharge) on a line (2D) or plane (3D),
// optionally ramped linearly in time. The load is carried by the material
// points whose face lies on that surface at the start, and distributed to the
// nodes with the grid's basis at the edge of its box as it moves (f_I += N_I t A_p): it
// follows the body as it settles. A load on nodes fixed in space acts only
// through the points that still reach them: the top row of a settling column
// then carries t h / (h - settlement), twice the load at half a cell, until
// it is crushed. The load acts on the soil skeleton (the mixture in
// saturated bodies).
#include <algorithm>
#include <cmath>
#include <string>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>
#include <vector>

namespace {

class TractionBC final : public suffuse::BoundaryCondition {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.vector("box_min").with_unit("m").doc(
        "Lower corner of the loaded surface, one component equal to box_max's (the normal); the material points "
        "whose face lies on it at the start carry the load");
    s.vector("box_max").with_unit("m").doc("Upper corner of the loaded surface");
    s.vector("traction").with_unit("Pa").doc("Traction vector, e.g. [0, -10e3] for a 10 kPa surcharge on a top surface");
    s.number("ramp_time").with_unit("s").at_least(0).fallback(0.0).doc(
        "Time over which the load grows linearly from zero (0: applied at once)");
    s.time_series("factor").with_unit("-").fallback(1.0).doc(
        "The load in time: traction times this factor, a number or a table [[t, factor], ...] or a CSV file "
        "(docs/boundaries.md); with ramp_time, the ramp multiplies it");
    return s;
  }

  static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters& p, int dim) {
    const auto& lo = p.vector("box_min");
    const auto& hi = p.vector("box_max");
    int flat = 0;
    for (int a = 0; a < dim; ++a) {
      if (lo[a] > hi[a]) return {{"box_max", "empty box", "box_max >= box_min in every component", "box_max < box_min"}};
      flat += lo[a] == hi[a];
    }
    if (flat != 1)
      return {{"box_max", "not a surface", "box_min and box_max equal in exactly one component (the normal)",
               std::to_string(flat) + " equal components"}};
    return {};
  }

  explicit TractionBC(const suffuse::PluginArgs& args)
      : dim_(args.dim),
        where_(args.instance),
        lo_(args.params.vector("box_min")),
        hi_(args.params.vector("box_max")),
        traction_(args.params.vector("traction")),
        ramp_(args.params.number("ramp_time")),
        factor_(args.params.time_series("factor")) {
    for (int a = 0; a < dim_; ++a)
      if (lo_[a] == hi_[a]) normal_ = a;
  }

  void setup(const suffuse::GridGeometry&) override {}

  // The loaded points: those whose face lies on the box at the start. The
  // load is a dead load: each point carries traction times the part of its
  // face inside the box, for the whole run.
  void setup_points(const suffuse::GridGeometry& grid, const suffuse::PointSet& points) override {
    const double tol = 1e-6 * grid.min_cell_size();
    const double* x = points.data(points.core().position);
    const double* size = points.data(points.core().size);
    const double plane = lo_[normal_];
    int below = 0, above = 0;
    for (std::size_t p = 0; p < points.size(); ++p) {
      const double* xp = x + p * dim_;
      const double* sp = size + p * dim_;
      const double half = 0.5 * sp[normal_];
      const bool top = std::abs(xp[normal_] + half - plane) <= tol;
      const bool bottom = std::abs(xp[normal_] - half - plane) <= tol;
      if (!top && !bottom) continue;
      double area = 1;
      for (int a = 0; a < dim_; ++a) {
        if (a == normal_) continue;
        area *= std::max(0.0, std::min(hi_[a], xp[a] + 0.5 * sp[a]) - std::max(lo_[a], xp[a] - 0.5 * sp[a]));
      }
      if (!(area > 0)) continue;
      (top ? below : above) += 1;
      points_.push_back(p);
      areas_.push_back(area);
    }
    if (points_.empty())
      throw suffuse::Error(where_ + ": no material point has a face between box_min and box_max (declared by bc/traction)");
    if (below > 0 && above > 0)
      throw suffuse::Error(where_ + ": material points on both sides of the loaded surface (declared by bc/traction)");
    side_ = below > 0 ? 1.0 : -1.0;
  }

  // f_I += N_I t A_p, N_I the grid's linear basis integrated over the point's
  // piece of the loaded surface: along the normal at the edge of the point's
  // box as uGIMP sees it (centre + half its initial size, at most half a
  // cell), averaged over the face's extent across it (as uGIMP averages over
  // a point's box). A node then takes the load in the share it takes the
  // point's internal force: uniform stress equal to the load is in
  // equilibrium even at a node only the point's tail reaches. (The face
  // stretched by the strain reached such a node later than the internal
  // force did, and its equilibrium pulled the top points' stress to 0.78
  // and 1.21 of the load: TwoPhase.SaturatedColumnSettlingACellCarriesItsLoad.)
  // A node beyond the grid passes its weight to its neighbour inside.
  bool loads_points() const override { return true; }
  std::vector<std::size_t> loaded_points() const override { return points_; }
  // Each loaded point keeps its area; only its number changes.
  bool follows_renumbering() const override { return true; }
  void renumber_loaded_points(std::span<const std::size_t> new_numbers) override {
    points_.assign(new_numbers.begin(), new_numbers.end());
  }

  void apply_point_forces(const suffuse::GridGeometry& grid, const suffuse::PointSet& points, suffuse::NodeState& state,
                          double time) const override {
    const double factor = suffuse::ramp_factor(time, ramp_) * factor_(time);
    const auto& core = points.core();
    const double* x = points.data(core.position);
    const double* size = points.data(core.size);
    const auto& o = grid.origin();
    const auto& h = grid.cell_size();
    const auto& nn = grid.nodes_per_axis();
    for (std::size_t k = 0; k < points_.size(); ++k) {
      const std::size_t p = points_[k];
      int base[3] = {0, 0, 0};
      double w1[3][3] = {};
      for (int a = 0; a < dim_; ++a) {
        double c = x[p * dim_ + a], l = std::min(0.5 * size[p * dim_ + a], 0.5 * h[a]);
        if (a == normal_) {
          c += side_ * l;
          l = 0;
        }
        const double xi = (c - o[a]) / h[a];
        base[a] = static_cast<int>(std::lround(xi)) - 1;
        for (int j = 0; j < 3; ++j) w1[a][j] = hat_average(c - (o[a] + (base[a] + j) * h[a]), h[a], l);
        for (int j : {0, 2}) {
          const int node = base[a] + j;
          if (node >= 0 && node < nn[a]) continue;
          w1[a][1] += w1[a][j];
          w1[a][j] = 0;
        }
      }
      const int count = dim_ == 2 ? 9 : 27;
      for (int s = 0; s < count; ++s) {
        const int off[3] = {s % 3, (s / 3) % 3, s / 9};
        double w = factor * areas_[k];
        int ijk[3] = {0, 0, 0};
        for (int a = 0; a < dim_; ++a) {
          w *= w1[a][off[a]];
          ijk[a] = base[a] + off[a];
        }
        if (w == 0) continue;
        const std::int64_t I = grid.node_index(ijk[0], ijk[1], ijk[2]);
        for (int c = 0; c < dim_; ++c) state.force[I * dim_ + c] += w * traction_[c];
      }
    }
  }

 private:
  // The linear hat of a node at distance r, cell size h, averaged over [r - l, r + l] (l = 0: the hat itself).
  static double hat_average(double r, double h, double l) {
    const double a = std::abs(r);
    if (a < l) return 1 - (r * r + l * l) / (2 * h * l);
    if (a <= h - l) return 1 - a / h;
    if (a < h + l) {
      const double t = h + l - a;
      return t * t / (4 * h * l);
    }
    return 0;
  }

  int dim_;
  std::string where_;
  std::vector<double> lo_, hi_, traction_;
  double ramp_;
  suffuse::TimeFunction factor_;
  int normal_ = 0;
  double side_ = 1;
  std::vector<std::size_t> points_;
  std::vector<double> areas_;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::BoundaryCondition, TractionBC>(
      "bc/traction", "Distributed load on a body's surface (surcharge), carried by its material points, optionally ramped in time");
}
