#include "mpm/domain.hpp"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "geometry/body_shape.hpp"
#include "mpm/initial_values.hpp"
#include "mpm/solid_kernels.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

Domain::Domain(const Scene& scene, const Registry& registry, int threads)
    : grid(scene.dim, scene.grid_origin, scene.grid_cell_size, scene.grid_cells),
      periodic(grid, scene.grid_periodic),
      points(scene.dim),
      exec(threads, static_cast<std::size_t>(scene.grid_cells[scene.dim - 1]), kernel_isa_for_this_machine()),
      shape_function_(registry.create<ShapeFunction>(
          scene.shape_function.type, {scene.shape_function.params, scene.dim, scene.shape_function.pointer})),
      average_volumetric_rate_(scene.volumetric_strain == VolumetricStrain::cell_average) {
  for (int a = 0; a < scene.dim; ++a) {
    shape.nodes[a] = shape_function_->support(grid.nodes_per_axis()[a]);
    if (shape.nodes[a] < 1 || shape.nodes[a] > grid.nodes_per_axis()[a])
      throw Error("/shape_function: " + scene.shape_function.type + " spans " + std::to_string(shape.nodes[a]) +
                  " nodes along axis " + std::to_string(a) + ", which has " +
                  std::to_string(grid.nodes_per_axis()[a]));
    shape.per_point += shape.nodes[a];
  }
  shape.stride = {1, grid.node_index(0, 1, 0), scene.dim == 3 ? grid.node_index(0, 0, 1) : 0};
  if (average_volumetric_rate_) {
    std::size_t cells = 1;
    for (int a = 0; a < scene.dim; ++a) cells *= static_cast<std::size_t>(scene.grid_cells[a]);
    cell_volume_.resize(cells);
    cell_rate_.resize(cells);
  }
  nodes.resize(grid.node_count(), scene.dim, scene.saturated());
  all_nodes_ = {ScatterRange{0, grid.node_count()}};
}

void Domain::set_halo_layers(int layers) {
  shape.halo = static_cast<std::size_t>(std::max(0, layers)) * static_cast<std::size_t>(shape.stride[dim() - 1]);
}

ScatterRange Domain::node_range() const {
  const auto ranks = static_cast<std::size_t>(comm.size());
  // Before the first step's shape functions: every node.
  if (!comm.parallel() || shape.chunks.held.size() != ranks) return all_nodes_.front();
  return Executor::needed(shape.chunks, static_cast<std::size_t>(comm.rank()), shape.halo, grid.node_count());
}

const std::vector<ScatterRange>& Domain::owned_nodes(const Interpolation& s) const {
  if (!comm.parallel()) return all_nodes_;
  if (!owners_known(s))
    throw Error("internal: the nodes' owners are asked for before the shape functions were evaluated");
  return s.chunks.owned[static_cast<std::size_t>(comm.rank())];
}

void Domain::start_node_terms(int k) {
  if (k < 1 || k > max_node_terms) throw Error("internal: " + std::to_string(k) + " sums over nodes at once");
  node_term_count_ = k;
  node_terms_.clear();
}

Domain::NodeTerms Domain::sum_node_terms() {
  const auto width = static_cast<std::size_t>(node_term_count_) + 1;  // the node, its terms
  const std::vector<double>* records = &node_terms_;
  if (comm.parallel()) {
    comm.all_gather(node_terms_, comm.all_counts(node_terms_.size()), all_node_terms_);
    records = &all_node_terms_;
  }
  const std::size_t n = records->size() / width;
  NodeTerms sum{};
  auto add = [&](std::size_t i) {
    for (std::size_t k = 1; k < width; ++k) sum[k - 1] += (*records)[i * width + k];
  };
  if (!comm.parallel()) {  // one process's records ascend
    for (std::size_t i = 0; i < n; ++i) add(i);
    return sum;
  }
  // Each process's records ascend, but the nodes processes own may
  // interleave (ScatterRanges::owned): into node order.
  node_order_.resize(n);
  for (std::size_t i = 0; i < n; ++i) node_order_[i] = i;
  std::sort(node_order_.begin(), node_order_.end(),
            [&](std::size_t a, std::size_t b) { return (*records)[a * width] < (*records)[b * width]; });
  for (const std::size_t i : node_order_) add(i);
  return sum;
}

void Domain::gather_nodal_to_root(const Interpolation& s, std::vector<double>& values, int components) {
  gather_nodal(s, values, components, false);
}

void Domain::gather_nodal_to_all(const Interpolation& s, std::vector<double>& values, int components) {
  gather_nodal(s, values, components, true);
}

void Domain::gather_nodal(const Interpolation& s, std::vector<double>& values, int components, bool everywhere) {
  if (!comm.parallel()) return;
  const auto m = static_cast<std::size_t>(components);
  std::vector<double> mine;
  for (const ScatterRange& r : owned_nodes(s)) mine.insert(mine.end(), values.begin() + r.first * m, values.begin() + r.last * m);
  if (everywhere)
    comm.all_gather(mine, comm.all_counts(mine.size()), exchanged_);
  else
    comm.gather_to_root(mine, comm.all_counts(mine.size()), exchanged_);
  if (!everywhere && !comm.root()) return;
  std::fill(values.begin(), values.end(), 0.0);
  const double* from = exchanged_.data();
  for (const std::vector<ScatterRange>& owned : s.chunks.owned)
    for (const ScatterRange& r : owned) {
      std::copy(from, from + (r.last - r.first) * m, values.begin() + r.first * m);
      from += (r.last - r.first) * m;
    }
}

BodyPoints Domain::create_body(const BodySpec& body, double solid_density, std::span<const BodySpec> earlier,
                               std::vector<std::size_t>& file_rows) {
  const int D = dim();
  // The lattice: a box's own (count points per axis filling it evenly); a
  // polygon's the grid's (points_per_cell per cell), from the cell that
  // holds its lower corner to the one that holds its upper.
  std::array<std::size_t, 3> count{1, 1, 1};
  std::array<double, 3> spacing{1, 1, 1}, start{};
  for (int a = 0; a < D; ++a) {
    if (body.polygon) {
      const double h = grid.cell_size()[a], o = grid.origin()[a];
      spacing[a] = h / body.points_per_cell;
      const double first = std::floor((body.min[a] - o) / h) * body.points_per_cell;
      const double last = std::ceil((body.max[a] - o) / h) * body.points_per_cell;
      start[a] = o + (first + 0.5) * spacing[a];
      count[a] = static_cast<std::size_t>(std::max(0.0, last - first));
      continue;
    }
    const double extent = body.max[a] - body.min[a];
    count[a] = std::max<std::size_t>(
        1, static_cast<std::size_t>(std::llround(extent / grid.cell_size()[a] * body.points_per_cell)));
    spacing[a] = extent / static_cast<double>(count[a]);
    start[a] = body.min[a] + 0.5 * spacing[a];
  }
  double volume = 1;
  for (int a = 0; a < D; ++a) volume *= spacing[a];  // per unit thickness in 2D
  // The lattice's points in the shape, but where an earlier body is: a later
  // body fills only what earlier ones left (docs/geometry.md). Two passes
  // over the lattice, counting and then filling: no copy of the positions.
  ShapeTest own(body, D);
  auto for_each_point = [&](auto&& use) {
    if (!body.points.empty()) {  // from a file: each row a point
      for (std::size_t r = 0; r + D < body.points.size(); r += D + 1) {
        std::array<double, 3> xp{};
        for (int a = 0; a < D; ++a) xp[a] = body.points[r + a];
        bool taken = false;
        for (const BodySpec& other : earlier)
          taken = taken || (near_bounds(other, xp.data(), D) && shape_contains(other, xp.data(), D));
        if (!taken) use(xp, body.points[r + D], r / (D + 1));
      }
      return;
    }
    for (std::size_t k = 0; k < count[2]; ++k)
      for (std::size_t j = 0; j < count[1]; ++j)
        for (std::size_t i = 0; i < count[0]; ++i) {
          const std::size_t idx[3] = {i, j, k};
          std::array<double, 3> xp{};
          for (int a = 0; a < D; ++a)
            xp[a] = body.polygon ? start[a] + static_cast<double>(idx[a]) * spacing[a]
                                 : body.min[a] + (static_cast<double>(idx[a]) + 0.5) * spacing[a];
          if (body.polygon && !own.contains(xp.data())) continue;
          bool taken = false;
          for (const BodySpec& other : earlier)
            taken = taken || (near_bounds(other, xp.data(), D) && shape_contains(other, xp.data(), D));
          if (!taken) use(xp, volume, std::size_t{0});
        }
  };
  std::size_t total = 0;
  for_each_point([&](const std::array<double, 3>&, double, std::size_t) { ++total; });
  const std::size_t first = points.append(total);
  const auto& f = points.core();
  double* x = points.data(f.position);
  double* v = points.data(f.velocity);
  double* m = points.data(f.mass);
  double* V = points.data(f.volume);
  double* id = points.data(f.material_id);
  double* size = points.data(f.size);
  double* stress = points.data(f.stress);
  file_rows.clear();
  if (!body.points.empty()) {
    file_rows.reserve(total);
    for_each_point([&](const std::array<double, 3>&, double, std::size_t row) { file_rows.push_back(row); });
  }
  const BodyPoints made{body.name, body.material, {first, first + total}, body.liquid.has_value()};
  const InitialValues initial(body, made, file_rows, D);
  std::size_t p = first;
  for_each_point([&](const std::array<double, 3>& xp, double point_volume, std::size_t) {
    // A point from a file: a cube (a square in 2D) of its volume.
    const double side = body.points.empty() ? 0.0 : std::pow(point_volume, 1.0 / D);
    for (int a = 0; a < D; ++a) {
      x[p * D + a] = xp[a];
      v[p * D + a] = initial.velocity(p, a);
      size[p * D + a] = body.points.empty() ? spacing[a] : side;
    }
    for (int c = 0; c < 6; ++c) stress[p * 6 + c] = initial.stress(p, c);
    V[p] = point_volume;
    m[p] = point_volume * solid_density * (body.liquid ? 1 - initial.porosity(p) : 1.0);
    id[p] = static_cast<double>(body.material);
    ++p;
  });
  bodies.push_back(made);
  return bodies.back();
}

std::string Domain::point_name(std::size_t p) const {
  std::string name = "material point " + std::to_string(first_point_ + p);
  if (const auto id = points.find("id"); id && p < points.size())
    name += " (id " + std::to_string(static_cast<std::size_t>(points.data(*id)[p])) + ")";
  return name;
}

void Domain::locate_points(std::size_t step, double time) {
  const int D = dim();
  const std::size_t n = points.size();
  const double* x = points.data(points.core().position);
  // A pass that counts without a call per point; the point is searched for
  // only when one left.
  double lower[3], upper[3];
  for (int a = 0; a < D; ++a) lower[a] = grid.origin()[a], upper[a] = grid.upper(a);
  auto count_outside = [&]<int Dim>() {
    std::size_t count = 0;
    for (std::size_t p = 0; p < n; ++p)
      for (int a = 0; a < Dim; ++a) count += !(x[p * Dim + a] >= lower[a] && x[p * Dim + a] <= upper[a]);  // NaN too
    return count;
  };
  const std::size_t outside = D == 2 ? count_outside.template operator()<2>() : count_outside.template operator()<3>();
  for (std::size_t p = 0; outside && p < n; ++p) {
    if (grid.contains(x + p * D)) continue;
    std::string body;
    for (const BodyPoints& b : bodies)
      if (p >= b.range.begin && p < b.range.end) body = b.name;
    std::ostringstream pos;
    for (int a = 0; a < D; ++a) pos << (a ? ", " : "") << x[p * D + a];
    throw Error(point_name(p) + " of body '" + body + "' left the grid at step " +
                std::to_string(step) + " (t = " + std::to_string(time) + " s): position (" + pos.str() +
                "); enlarge /grid or check the boundary conditions and the time step");
  }
  if (average_volumetric_rate_) locate_cells();
  evaluate_shape(shape);
}

void Domain::distribute_points() {
  if (!comm.parallel()) return;
  const std::size_t total = points.size(), chunk = exec.scatter_chunk(total), chunks = (total + chunk - 1) / chunk;
  const auto rank = static_cast<std::size_t>(comm.rank()), size = static_cast<std::size_t>(comm.size());
  const std::size_t begin = std::min(total, chunks * rank / size * chunk),
                    end = std::min(total, chunks * (rank + 1) / size * chunk);
  points.keep(begin, end);
  for (BodyPoints& b : bodies) {
    const std::size_t lo = std::clamp(b.range.begin, begin, end), hi = std::clamp(b.range.end, begin, end);
    b.range = {lo - begin, hi - begin};
  }
  total_points_ = total;
  first_point_ = begin;
  exec.distribute(comm, total, begin, end - begin);
}

// A copy of every point's fields, in the serial numbering (made on first
// use): on the first process only, or on every process.
void Domain::make_copy(std::unique_ptr<PointSet>& into, bool everywhere) {
  if (into) return;
  into = std::make_unique<PointSet>(dim());
  for (FieldId f = 0; f < points.field_count(); ++f) into->add_field(points.info(f));
  if (everywhere || comm.root()) into->append(total_points_);
}

// Every process's points into that copy.
void Domain::collect_points(std::unique_ptr<PointSet>& into, bool everywhere) {
  make_copy(into, everywhere);
  const std::vector<std::size_t> counts = comm.all_counts(points.size());
  std::vector<std::size_t> values(counts.size());
  for (FieldId f = 0; f < points.field_count(); ++f) {
    const auto m = static_cast<std::size_t>(points.components(f));
    for (std::size_t r = 0; r < counts.size(); ++r) values[r] = counts[r] * m;
    if (everywhere) {
      comm.all_gather(points.values(f), values, exchanged_);
    } else {
      comm.gather_to_root(points.values(f), values, exchanged_);
      if (!comm.root()) continue;
    }
    std::copy(exchanged_.begin(), exchanged_.end(), into->data(f));
  }
}

const PointSet& Domain::gathered_points() {
  if (!comm.parallel()) return points;
  collect_points(gathered_, false);
  return *gathered_;
}

const PointSet& Domain::every_point() {
  if (!comm.parallel()) return points;
  collect_points(every_, true);
  return *every_;
}

const PointSet& Domain::points_at(std::span<const std::size_t> wanted) {
  if (!comm.parallel()) return points;
  make_copy(every_, true);
  const std::vector<std::size_t> counts = comm.all_counts(points.size());
  std::vector<std::size_t> first(counts.size() + 1, 0);
  for (std::size_t r = 0; r < counts.size(); ++r) first[r + 1] = first[r] + counts[r];
  // Each process's wanted points: a contiguous part of `wanted`.
  auto part = [&](std::size_t r) {
    const auto lo = std::lower_bound(wanted.begin(), wanted.end(), first[r]);
    return std::make_pair(lo, std::lower_bound(lo, wanted.end(), first[r + 1]));
  };
  std::size_t row = 0;  // values per point, every field
  for (FieldId f = 0; f < points.field_count(); ++f) row += static_cast<std::size_t>(points.components(f));
  std::vector<double> mine;
  const auto [lo, hi] = part(static_cast<std::size_t>(comm.rank()));
  for (FieldId f = 0; f < points.field_count(); ++f) {
    const auto m = static_cast<std::size_t>(points.components(f));
    const double* v = points.data(f);
    for (auto p = lo; p != hi; ++p) mine.insert(mine.end(), v + (*p - first_point_) * m, v + (*p - first_point_ + 1) * m);
  }
  std::vector<std::size_t> values(counts.size());
  for (std::size_t r = 0; r < counts.size(); ++r) {
    const auto [b, e] = part(r);
    values[r] = static_cast<std::size_t>(e - b) * row;
  }
  comm.all_gather(mine, values, exchanged_);
  const double* from = exchanged_.data();
  for (std::size_t r = 0; r < counts.size(); ++r) {
    const auto [b, e] = part(r);
    for (FieldId f = 0; f < points.field_count(); ++f) {
      const auto m = static_cast<std::size_t>(points.components(f));
      double* into = every_->data(f);
      for (auto p = b; p != e; ++p, from += m) std::copy(from, from + m, into + *p * m);
    }
  }
  return *every_;
}

void Domain::evaluate_shape(Interpolation& out) {
  const int D = dim();
  const std::size_t n = points.size(), F = static_cast<std::size_t>(shape.per_point);
  if (&out == &shape) expanded_current_ = false;
  out.per_point = shape.per_point, out.nodes = shape.nodes, out.stride = shape.stride;
  out.first.resize(n);
  out.weights.resize(n * F);
  out.derivatives.resize(n * F);
  const auto xs = points.values(points.core().position);
  const auto sizes = points.values(points.core().size);
  exec.for_chunks(n, [&](int, std::size_t b, std::size_t e) {
    shape_function_->evaluate(grid, xs.subspan(b * D, (e - b) * D), sizes.subspan(b * D, (e - b) * D),
                              std::span(out.first).subspan(b, e - b), std::span(out.weights).subspan(b * F, (e - b) * F),
                              std::span(out.derivatives).subspan(b * F, (e - b) * F));
  });
  exec.chunk_ranges(out.first.data(), 1, n, out.chunks, out.view().extent());
}

const ExpandedSupports& Domain::expanded_shape() {
  if (!expanded_current_) {
    expand_supports(shape.view(), dim(), points.size(), expanded_);
    if (periodic.any())  // a sum over a point's nodes goes to the node an image is
      for (NodeId& id : expanded_.ids) id = static_cast<NodeId>(periodic.node(id));
  }
  expanded_current_ = true;
  return expanded_;
}

void expand_supports(const PointSupports& s, int dim, std::size_t points, ExpandedSupports& out) {
  const int npp = s.nodes_per_point();
  out.npp = npp;
  out.ids.resize(points * npp);
  out.weights.resize(points * npp);
  out.gradients.resize(points * npp * dim);
  for (std::size_t p = 0; p < points; ++p) {
    std::size_t q = p * npp;
    auto put = [&](std::size_t node, double N, const double* grad) {
      out.ids[q] = static_cast<NodeId>(node);
      out.weights[q] = N;
      for (int i = 0; i < dim; ++i) out.gradients[q * dim + i] = grad[i];
      ++q;
    };
    if (dim == 2)
      for_each_node<2>(s, p, put);
    else
      for_each_node<3>(s, p, put);
  }
}

void Domain::locate_cells() {
  const int D = dim();
  const std::size_t n = points.size();
  const double* x = points.data(points.core().position);
  point_cell_.resize(n);
  exec.for_chunks(n, [&](int, std::size_t b, std::size_t e) {
    for (std::size_t p = b; p < e; ++p) {
      std::int64_t cell = 0, stride = 1;
      for (int a = 0; a < D; ++a) {
        const int i = static_cast<int>(std::floor((x[p * D + a] - grid.origin()[a]) / grid.cell_size()[a]));
        cell += stride * std::clamp(i, 0, grid.cells()[a] - 1);
        stride *= grid.cells()[a];
      }
      point_cell_[p] = cell;
    }
  });
  exec.chunk_ranges(point_cell_.data(), 1, n, point_cell_chunks_);
}

void Domain::update_kinematics(double dt) {
  const auto& f = points.core();
  if (!average_volumetric_rate_) {  // one pass: L, strain and volume
    exec.for_chunks(points.size(), [&](int, std::size_t b, std::size_t e) {
      exec.vector_kernel(dim(), [&]<int D, int L>() {
        velocity_gradient_kernel<D, true, L>(b, e, dt, shape.view(), nodes.velocity.data(), points.data(f.velocity_gradient),
                                             points.data(f.strain), points.data(f.volume));
      });
    });
    return;
  }
  update_velocity_gradient(dt);
  auto integrate = dim() == 2 ? &strain_volume_kernel<2> : &strain_volume_kernel<3>;
  exec.for_chunks(points.size(), [&](int, std::size_t b, std::size_t e) {
    integrate(b, e, dt, points.data(f.velocity_gradient), points.data(f.strain), points.data(f.volume));
  });
}

void Domain::update_velocity_gradient(double dt) {
  const auto& f = points.core();
  double* gradient = points.data(f.velocity_gradient);
  exec.for_chunks(points.size(), [&](int, std::size_t b, std::size_t e) {
    exec.vector_kernel(dim(), [&]<int D, int L>() {
      velocity_gradient_kernel<D, false, L>(b, e, dt, shape.view(), nodes.velocity.data(), gradient, nullptr,
                                            nullptr);
    });
  });
  if (!average_volumetric_rate_) return;
  std::fill(cell_volume_.begin(), cell_volume_.end(), 0.0);
  std::fill(cell_rate_.begin(), cell_rate_.end(), 0.0);
  ScatterTargets targets(point_cell_.data(), 1, cell_volume_.size(), &point_cell_chunks_);
  targets.add(cell_volume_);
  targets.add(cell_rate_);
  auto sum = dim() == 2 ? &cell_volumetric_rate_kernel<2> : &cell_volumetric_rate_kernel<3>;
  exec.scatter(points.size(), targets, [&](std::size_t b, std::size_t e, double* const* out) {
    sum(b, e, point_cell_.data(), gradient, points.data(f.volume), out[0], out[1]);
  });
  auto replace = dim() == 2 ? &replace_volumetric_rate_kernel<2> : &replace_volumetric_rate_kernel<3>;
  exec.for_chunks(points.size(), [&](int, std::size_t b, std::size_t e) {
    replace(b, e, point_cell_.data(), cell_volume_.data(), cell_rate_.data(), gradient);
  });
}

}  // namespace suffuse::detail
