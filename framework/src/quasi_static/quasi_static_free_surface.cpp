// Free surfaces of a quasi-static step (quasi_static.hpp): nodes next to a
// cell inside the grid that holds no saturated point. Their pressure is
// zero where the body's surface is, not at the node: a surface rarely
// passes through nodes (a body swells or settles, a slope cuts cells, a
// crest ends inside one), and p = 0 at the node next to it bends the
// pressure over the last cell (docs/time-integration.md, The free surface
// between nodes).
#include <algorithm>
#include <array>
#include <cmath>
#include <limits>

#include "quasi_static/quasi_static.hpp"

namespace suffuse::detail {

namespace {
// The saturated points counted in cell c (cell_count, per cell), or -1 for
// a cell outside the grid (on a periodic axis the cells go on across the
// seam).
double saturated_points(const GridGeometry& grid, const PeriodicGrid& periodic, const std::vector<double>& cell_count,
                        std::array<int, 3> c) {
  std::int64_t cell = 0, stride = 1;
  for (int a = 0; a < grid.dim(); ++a) {
    c[a] = periodic.cell(a, c[a]);
    if (c[a] < 0 || c[a] >= grid.cells()[a]) return -1;
    cell += stride * c[a];
    stride *= grid.cells()[a];
  }
  return cell_count[static_cast<std::size_t>(cell)];
}
}  // namespace

// Per node, axis and side, how far the domains of the saturated points
// nearest the grid line through the node along that axis reach (within
// half a cell across it; the two nodes of each point's cell on that line).
void QuasiStatic::measure_surface_reach() {
  const int dim = d_.dim();
  const PointSet& pts = d_.points;
  const double* x = pts.data(pts.core().position);
  const double* size = pts.data(pts.core().size);
  const double* n = pts.data(mixture_->fields().porosity);
  const auto& cells = d_.grid.cells();
  line_reach_.assign(d_.grid.node_count() * static_cast<std::size_t>(dim) * 2, -std::numeric_limits<double>::infinity());
  for (std::size_t p = 0; p < pts.size(); ++p) {
    if (!(n[p] > 0)) continue;
    for (int a = 0; a < dim; ++a) {
      std::array<int, 3> lo{0, 0, 0}, hi{0, 0, 0};
      for (int b = 0; b < dim; ++b) {
        const double at = (x[p * dim + b] - d_.grid.origin()[b]) / d_.grid.cell_size()[b];
        if (b == a) {
          lo[b] = std::clamp(static_cast<int>(std::floor(at)), 0, cells[b] - 1);
          hi[b] = lo[b] + 1;
        } else {
          lo[b] = std::clamp(static_cast<int>(std::ceil(at - 0.5 - 1e-9)), 0, cells[b]);
          hi[b] = std::clamp(static_cast<int>(std::floor(at + 0.5 + 1e-9)), 0, cells[b]);
        }
      }
      for (int k = lo[2]; k <= hi[2]; ++k)
        for (int j = lo[1]; j <= hi[1]; ++j)
          for (int i = lo[0]; i <= hi[0]; ++i) {
            const auto N = static_cast<std::size_t>(d_.grid.node_index(i, j, k));
            for (int side = 0; side < 2; ++side) {  // +x + l/2, then -x + l/2
              double& reach = line_reach_[(N * dim + a) * 2 + side];
              reach = std::max(reach, (side ? -1 : 1) * x[p * dim + a] + size[p * dim + a] / 2);
            }
          }
    }
  }
  d_.comm.max(line_reach_);
}

// Marks the surface nodes among those with pore volume that no face fixes:
// none has an unknown of its own. Their pressure is zero, or follows the
// inner node extrapolation() finds.
void QuasiStatic::find_free_surfaces() {
  const int dim = d_.dim();
  const std::size_t nn = d_.grid.node_count();
  measure_surface_reach();
  std::vector<char>& surface = surface_node_;
  surface.assign(nn, 0);
  for (std::size_t I = 0; I < nn; ++I) {
    if (node_pore_[I] <= 0 || fixed_pressure_[I]) continue;
    const auto ijk = d_.grid.node_ijk(static_cast<std::int64_t>(I));
    for (int corner = 0; corner < (1 << dim) && !surface[I]; ++corner) {
      auto c = ijk;
      for (int a = 0; a < dim; ++a) c[a] -= (corner >> a) & 1;
      surface[I] = saturated_points(d_.grid, d_.periodic, cell_count_, c) == 0;
    }
  }
  extrapolated_.clear();
  if (phreatic_) seepage_node_.assign(nn, 0);
  for (std::size_t I = 0; I < nn; ++I)
    if (surface[I]) {
      // Drained (zero), or below a water level the water's pressure.
      const double at_node = water_ ? water_pressure(d_.grid.node_position(static_cast<std::int64_t>(I))) : 0.0;
      double at_surface = at_node;
      auto e = extrapolation(I);
      if (e && water_) {
        // Where the surface crosses the line from the inner node M through
        // I: M + (I - M) / (1 - factor) (the factor puts p = 0 there).
        const auto xI = d_.grid.node_position(static_cast<std::int64_t>(I));
        const auto xM = d_.grid.node_position(static_cast<std::int64_t>(e->from));
        std::array<double, 3> at{};
        for (int a = 0; a < dim; ++a) at[a] = xM[a] + (xI[a] - xM[a]) / (1 - e->factor);
        at_surface = water_pressure(at);
        e->offset = (1 - e->factor) * at_surface;
      }
      // Above the water levels, where pores drain, the surface is a seepage
      // face: drained where water leaves, closed where it would enter
      // (settle_seepage_faces). A closed node has an unknown of its own and
      // no flux. A step starts with the nodes closed whose potential,
      // projected from the points, is below zero (the water would be drawn
      // in): a function of the points' state, so that a halved step and a
      // restarted run start alike, and the faces settle in few rounds.
      if (phreatic_ && at_surface == 0 && drains_[I] > 0) {
        seepage_node_[I] = 1;
        if (seepage_rounds_ == 1) seepage_closed_[I] = p_[I] < 0;
        if (seepage_closed_[I]) continue;
      }
      fixed_pressure_[I] = 1;
      p_[I] = at_node;
      if (e) extrapolated_.push_back(*e);
    }
  if (phreatic_)
    for (std::size_t I = 0; I < nn; ++I) seepage_closed_[I] = seepage_closed_[I] && seepage_node_[I];
}

double QuasiStatic::water_pressure(const std::array<double, 3>& x) const {
  const WaterProfile& water = water_->current();  // the loads' level, at the step's end
  return water.unit_weight() * std::max(0.0, water.level(x[0]).first - x[d_.dim() - 1]);
}

// A free-surface node's pressure, extrapolated linearly from the nearest
// node inside along a grid axis (at most two cells in) to zero where the
// body's surface crosses that line: the farthest reach of the domains of
// the points nearest the line, not the node (a body that swelled 0.25 mm
// above its top node in upward_seepage.json had its top cell's flux 0.58%
// low with p = 0 at the node; one ending half a cell below a node, 48%).
// Only outward where the cells beyond the node hold no saturated point:
// not towards a wall beside it or another body beyond a gap. None where no
// such direction has a node inside (a corner, a body one cell thick): the
// node is then drained.
std::optional<QuasiStatic::Extrapolated> QuasiStatic::extrapolation(std::size_t I) const {
  const int dim = d_.dim();
  const auto& cells = d_.grid.cells();
  const auto ijk = d_.grid.node_ijk(static_cast<std::int64_t>(I));
  // Whether the cells beyond I outward (-in), those touching its line,
  // hold no saturated point (the grid's edge is no surface).
  const auto open_beyond = [&](int a, int in) {
    const int along = d_.periodic.cell(a, in < 0 ? ijk[a] : ijk[a] - 1);
    if (along < 0 || along >= cells[a]) return false;
    for (int beside = 0; beside < (1 << (dim - 1)); ++beside) {
      auto c = ijk;
      for (int b = 0, bit = 0; b < dim; ++b) c[b] = b == a ? along : ijk[b] - ((beside >> bit++) & 1);
      if (saturated_points(d_.grid, d_.periodic, cell_count_, c) > 0) return false;
    }
    return true;
  };
  std::optional<Extrapolated> best;
  int best_steps = 3;
  double best_volume = 0;
  for (int a = 0; a < dim; ++a)
    for (const int in : {-1, 1}) {
      if (!open_beyond(a, in)) continue;
      for (int k = 1; k <= 2; ++k) {
        auto m = ijk;
        m[a] += in * k;
        if (m[a] < 0 || m[a] > cells[a]) break;
        const auto M = static_cast<std::size_t>(d_.grid.node_index(m[0], m[1], m[2]));
        if (surface_node_[M]) continue;
        if (fixed_pressure_[M] || node_pore_[M] <= 0) break;
        if (k > best_steps || (k == best_steps && node_volume_[M] <= best_volume)) break;
        // The points on the line from M to I (the cells next to its nodes):
        // the farthest reach outward (-in) of their domains.
        const int side = in > 0 ? 1 : 0;
        double reach = -std::numeric_limits<double>::infinity();
        for (int step = 0; step <= k; ++step) {
          auto node = m;
          node[a] -= in * step;
          if (node[a] < 0 || node[a] > cells[a]) continue;
          const auto N = static_cast<std::size_t>(d_.grid.node_index(node[0], node[1], node[2]));
          reach = std::max(reach, line_reach_[(N * dim + a) * 2 + side]);
        }
        if (!std::isfinite(reach)) break;
        const double h = d_.grid.cell_size()[a];
        const double x_M = d_.grid.origin()[a] + m[a] * h;
        // From M to the surface, outward; at least half a cell, which bounds the factor.
        const double to_surface = std::max(reach + in * x_M, h / 2);
        best = Extrapolated{I, M, (to_surface - k * h) / to_surface};
        best_steps = k;
        best_volume = node_volume_[M];
        break;
      }
    }
  return best;
}

// Once the unknowns are numbered: a surface node's pressure is its inner
// node's times the factor that puts p = 0 at the surface (its unknown that
// node's, p_weight_ the factor), plus, below a water level, the offset that
// puts the water's pressure there instead; its equation joins the inner
// node's. Newton's increments keep the relation (they scale by the factor).
void QuasiStatic::follow_inner_nodes() {
  p_weight_.assign(d_.grid.node_count(), 1.0);
  for (const Extrapolated& e : extrapolated_) {
    p_dof_[e.node] = p_dof_[e.from];
    p_weight_[e.node] = e.factor;
    p_[e.node] = water_ ? e.factor * p_[e.from] + e.offset : e.factor * p_[e.from];
  }
}

}  // namespace suffuse::detail
