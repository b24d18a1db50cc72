#include "mpm/point_order.hpp"

#include <algorithm>

#include "mpm/domain.hpp"

namespace suffuse::detail {

namespace {

// The cell a position is in, numbered as the grid numbers its cells (the
// first axis fastest); positions outside the grid (or NaN) take the nearest
// cell: locate_points names such a point right after.
template <int D>
void cells_of(const GridGeometry& grid, const double* x, std::size_t n, std::size_t* cell) {
  const auto& o = grid.origin();
  const auto& h = grid.cell_size();
  const auto& c = grid.cells();
  double inverse[3];
  for (int a = 0; a < D; ++a) inverse[a] = 1 / h[a];
  for (std::size_t p = 0; p < n; ++p) {
    std::size_t key = 0, stride = 1;
    for (int a = 0; a < D; ++a) {
      const double xi = (x[p * D + a] - o[a]) * inverse[a];
      const std::size_t i = xi >= 0 ? (xi < c[a] ? static_cast<std::size_t>(xi) : static_cast<std::size_t>(c[a] - 1)) : 0;
      key += i * stride;
      stride *= static_cast<std::size_t>(c[a]);
    }
    cell[p] = key;
  }
}

}  // namespace

void PointOrder::compute_cells(const Domain& d) {
  const std::size_t n = d.points.size();
  cell_.resize(n);
  const double* x = d.points.data(d.points.core().position);
  if (d.dim() == 2)
    cells_of<2>(d.grid, x, n, cell_.data());
  else
    cells_of<3>(d.grid, x, n, cell_.data());
}

void PointOrder::number_points(PointSet& points) {
  if (threshold_ <= 0) return;  // never sorted
  id_ = points.add_field(id_field_info());
  double* id = points.data(*id_);
  for (std::size_t p = 0; p < points.size(); ++p) id[p] = static_cast<double>(p);
}

FieldInfo PointOrder::id_field_info() {
  return {"id", FieldKind::Scalar, "-",
          "the point's number when the run started, kept when the points are sorted again (/sort_points_at_spread)",
          true};
}

double PointOrder::spread(const Domain& d) const {
  // The step's chunk ranges (Executor::chunk_ranges), every process's on
  // each: the same sum on any number of processes.
  const ScatterRanges& ranges = d.shape.chunks;
  double sum = 0;
  for (const ScatterRange& r : d.comm.parallel() ? ranges.all : ranges.chunks)
    sum += static_cast<double>(r.last - r.first);
  return sum;
}

bool PointOrder::sort_if_spread(Domain& d) {
  // One chunk: its spread is that of every point, whatever their order.
  if (threshold_ <= 0 || d.total_points() <= d.exec.scatter_chunk(d.points.size())) return false;
  const double now = spread(d);
  if (reference_ <= 0) reference_ = now;  // the first step
  if (now < threshold_ * reference_) return false;
  sort(d);
  return true;
}

void PointOrder::sort(Domain& d) {
  sort_points(d);
  std::vector<std::size_t>().swap(cell_);
  for (auto* buffer : {&counts_, &below_, &send_, &received_}) std::vector<double>().swap(*buffer);
}

void PointOrder::sort_points(Domain& d) {
  compute_cells(d);
  const std::size_t n = cell_.size(), cells = d.grid.cells()[0] * static_cast<std::size_t>(d.grid.cells()[1]) *
                                                  (d.dim() == 3 ? static_cast<std::size_t>(d.grid.cells()[2]) : 1);
  // Key: body, then cell. A body's points keep its range of numbers (the
  // materials update bodies' ranges), sorted by cell within it.
  for (std::size_t b = 0; b < d.bodies.size(); ++b)
    for (std::size_t p = d.bodies[b].range.begin; p < d.bodies[b].range.end; ++p) cell_[p] += b * cells;
  // Counting sort over every process: the points of a key on lower
  // processes come first (they come first in the serial numbering).
  counts_.assign(d.bodies.size() * cells, 0.0);
  for (std::size_t p = 0; p < n; ++p) counts_[cell_[p]] += 1;
  below_ = counts_;
  d.comm.sum_below(below_);
  d.comm.sum(counts_);
  double next = 0;
  for (std::size_t k = 0; k < counts_.size(); ++k) {
    const double here = counts_[k];
    counts_[k] = next + below_[k];
    next += here;
  }
  new_number_.resize(n);
  for (std::size_t p = 0; p < n; ++p) new_number_[p] = static_cast<std::size_t>(counts_[cell_[p]]++);
  ++sorts_;

  PointSet& pts = d.points;
  const std::size_t first = d.first_point();
  if (!d.comm.parallel()) {
    for (FieldId f = 0; f < pts.field_count(); ++f) {
      const auto m = static_cast<std::size_t>(pts.components(f));
      double* v = pts.data(f);
      received_.resize(n * m);
      for (std::size_t p = 0; p < n; ++p) std::copy(v + p * m, v + (p + 1) * m, received_.data() + new_number_[p] * m);
      std::copy(received_.begin(), received_.end(), v);
    }
    return;
  }
  // Each point goes to the process that holds its new number: process r
  // holds as many points after the sort as before (a body keeps its range).
  const std::vector<std::size_t> held = d.comm.all_counts(n);
  const std::size_t ranks = held.size();
  std::vector<std::size_t> begins(ranks + 1, 0);
  for (std::size_t r = 0; r < ranks; ++r) begins[r + 1] = begins[r] + held[r];
  auto owner = [&](std::size_t number) {
    return static_cast<std::size_t>(std::upper_bound(begins.begin(), begins.end(), number) - begins.begin()) - 1;
  };
  std::vector<std::size_t> send_points(ranks, 0), order(n), at(ranks + 1, 0);
  for (std::size_t p = 0; p < n; ++p) ++send_points[owner(new_number_[p])];
  for (std::size_t r = 0; r < ranks; ++r) at[r + 1] = at[r] + send_points[r];
  for (std::size_t p = 0; p < n; ++p) order[at[owner(new_number_[p])]++] = p;
  // How many each process receives from each: every process's counts.
  std::vector<double> mine(send_points.begin(), send_points.end()), matrix;
  d.comm.all_gather(mine, std::vector<std::size_t>(ranks, ranks), matrix);
  const auto me = static_cast<std::size_t>(d.comm.rank());
  std::vector<std::size_t> recv_points(ranks);
  for (std::size_t r = 0; r < ranks; ++r) recv_points[r] = static_cast<std::size_t>(matrix[r * ranks + me]);

  send_.resize(n);
  for (std::size_t i = 0; i < n; ++i) send_[i] = static_cast<double>(new_number_[order[i]]);
  d.comm.all_to_all(send_, send_points, recv_points, received_);
  std::vector<std::size_t> place(received_.size());
  for (std::size_t i = 0; i < place.size(); ++i) place[i] = static_cast<std::size_t>(received_[i]) - first;
  std::vector<std::size_t> send_values(ranks), recv_values(ranks);
  for (FieldId f = 0; f < pts.field_count(); ++f) {
    const auto m = static_cast<std::size_t>(pts.components(f));
    double* v = pts.data(f);
    send_.resize(n * m);
    for (std::size_t i = 0; i < n; ++i) std::copy(v + order[i] * m, v + (order[i] + 1) * m, send_.data() + i * m);
    for (std::size_t r = 0; r < ranks; ++r) send_values[r] = send_points[r] * m, recv_values[r] = recv_points[r] * m;
    d.comm.all_to_all(send_, send_values, recv_values, received_);
    for (std::size_t i = 0; i < place.size(); ++i)
      std::copy(received_.data() + i * m, received_.data() + (i + 1) * m, v + place[i] * m);
  }
}

}  // namespace suffuse::detail
