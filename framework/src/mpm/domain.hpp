#pragma once
// The grid and the material points of a run, and the interpolation between
// them (shape functions at the points' positions). On many processes each
// holds its share of the points and updates the nodes they reach and a halo
// (docs/parallel.md); the stages of the other parts reach grid and points
// only through a Domain.
#include <algorithm>
#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include "mpm/periodic_grid.hpp"
#include "mpm/point_supports.hpp"
#include "parallel/communicator.hpp"
#include "parallel/executor.hpp"
#include "suffuse/grid.hpp"
#include "suffuse/phase.hpp"
#include "suffuse/plugin.hpp"
#include "suffuse/points.hpp"
#include "suffuse/scene.hpp"

namespace suffuse::detail {

// The points of one body of the scene.
struct BodyPoints {
  std::string name;
  std::size_t material;
  PointRange range;
  bool saturated;
};

// The shape functions of every point for the current step: per point its
// support's first node, 1D weights and derivatives (point_supports.hpp).
struct Interpolation {
  std::vector<NodeId> first;
  std::vector<double> weights, derivatives;
  int per_point = 0;
  std::array<int, 3> nodes{1, 1, 1};
  std::array<std::int64_t, 3> stride{};
  ScatterRanges chunks;  // the nodes each scatter chunk touches, for every nodal scatter of the step
  // On many processes: nodes on each side of a process's held ones whose
  // sums it needs complete (Domain::set_halo_layers).
  std::size_t halo = 0;
  PointSupports view() const {
    return {first.data(), weights.data(), derivatives.data(), per_point, nodes, stride};
  }
  // A scatter into nodal arrays of `entries` nodes through these supports.
  ScatterTargets targets(std::size_t entries) const {
    return ScatterTargets(first.data(), 1, entries, &chunks, view().extent(), halo);
  }
};

class Domain {
 public:
  Domain(const Scene& scene, const Registry& registry, int threads);

  int dim() const { return grid.dim(); }

  // Fills a body's shape with points (position, size, velocity, volume,
  // solid mass, initial stress, material id), but where the earlier bodies
  // are; returns their range.
  // `file_rows`: set to the file's row of each point of a body of points
  // (InitialValues), cleared for a body of a shape.
  BodyPoints create_body(const BodySpec& body, double solid_density, std::span<const BodySpec> earlier,
                         std::vector<std::size_t>& file_rows);

  // A run on many processes: keeps this process's share of the points,
  // whole scatter chunks of the serial run's numbering (docs/parallel.md),
  // and each body's range within it. Call once the bodies are made.
  void distribute_points();
  // Points over every process, and the serial run's number of this
  // process's first point.
  std::size_t total_points() const { return total_points_ ? total_points_ : points.size(); }
  std::size_t first_point() const { return first_point_; }
  // Every process's points, in the serial run's order, on the first process
  // (collective; the others get an empty set): what writers and checkpoints
  // read. One process: `points` itself.
  const PointSet& gathered_points();
  // Every process's points on every process (collective): what conditions
  // that load points read on many processes (docs/parallel.md, Limits).
  const PointSet& every_point();
  // The same set with only the points `wanted` (serial numbers, ascending)
  // brought up to date (collective): what a condition that names the points
  // it loads reads (BoundaryCondition::loaded_points).
  const PointSet& points_at(std::span<const std::size_t> wanted);

  // "material point N" for this process's point p, N its number in the run
  // (the order of the outputs), with " (id K)" once points may be sorted
  // again (PointOrder): for messages.
  std::string point_name(std::size_t p) const;
  // Stage "shape": shape functions at the points' positions. Throws, naming
  // the point and its body, if a point left the grid.
  void locate_points(std::size_t step, double time);
  // Shape functions at the points' current positions, into `out` (the
  // step's own are in `shape`; outputs project with their own copy).
  void evaluate_shape(Interpolation& out);
  // The step's shape functions written out node by node (the quasi-static
  // solve's assembly reads them many times), made once per step on demand.
  const ExpandedSupports& expanded_shape();

  // Stage "strain": velocity gradient L from the remapped nodal velocities
  // (its trace averaged over each cell's points where the scene asks for
  // it), strain += sym(L) dt, volume *= det(I + L dt).
  void update_kinematics(double dt);
  // Its first half: the velocity gradient only (quasi-static iterations
  // try increments before one is accepted).
  void update_velocity_gradient(double dt);

  // The nodes this process updates: on one process every node; on many,
  // those its points reach (their supports, in the step's shape functions)
  // and a halo of `layers` node layers (along the grid's last axis) on each
  // side, as wide as the farthest neighbour a nodal stage reads, through
  // the stages of a step, so that the nodes the points read are the serial
  // run's (docs/parallel.md). Set once, before the first step.
  void set_halo_layers(int layers);
  ScatterRange node_range() const;
  // body(thread, begin, end) on threads' chunks of node_range().
  template <class Body>
  void for_nodes(Body&& body) {
    const ScatterRange r = node_range();
    exec.for_chunks(r.last - r.first,
                    [&](int t, std::size_t b, std::size_t e) { body(t, r.first + b, r.first + e); });
  }

  // `v` sized for `per_node` values per node, zero on node_range() (a
  // scatter's targets: it adds on no other node).
  void clear_nodal(std::vector<double>& v, std::size_t per_node) const {
    const ScatterRange r = node_range();
    v.resize(grid.node_count() * per_node);
    std::fill(v.begin() + static_cast<std::ptrdiff_t>(r.first * per_node),
              v.begin() + static_cast<std::ptrdiff_t>(r.last * per_node), 0.0);
  }

  // Sums over nodes, in node order, of the k <= 9 terms terms(I, t) writes
  // for node I (returning false when it adds nothing), each node's terms
  // from the process that owns it (ScatterRanges::owned): the serial run's
  // sums, bit for bit, on every process (collective). Over every node, or
  // over `candidates` (ascending node numbers).
  static constexpr int max_node_terms = 9;
  using NodeTerms = std::array<double, max_node_terms>;
  template <class Terms>
  NodeTerms node_sums(int k, Terms&& terms) {
    start_node_terms(k);
    for (const ScatterRange& r : owned_nodes(shape))
      for (std::size_t I = r.first; I < r.last; ++I) add_node_terms(I, terms);
    return sum_node_terms();
  }
  // (Here terms(i, t) are those of node candidates[i].)
  template <class Terms>
  NodeTerms node_sums(int k, std::span<const std::int64_t> candidates, Terms&& terms) {
    start_node_terms(k);
    const std::vector<ScatterRange>& owned = owned_nodes(shape);
    for (std::size_t i = 0; i < candidates.size(); ++i) {
      const auto I = static_cast<std::size_t>(candidates[i]);
      for (const ScatterRange& r : owned)
        if (I >= r.first && I < r.last) {
          auto of_candidate = [&](std::size_t, double* t) { return terms(i, t); };
          add_node_terms(I, of_candidate);
        }
    }
    return sum_node_terms();
  }
  // The nodes this process owns among those `s` reaches (one process: all),
  // once `s` was evaluated (owners_known).
  const std::vector<ScatterRange>& owned_nodes(const Interpolation& s) const;
  bool owners_known(const Interpolation& s) const {
    return !comm.parallel() || s.chunks.owned.size() == static_cast<std::size_t>(comm.size());
  }
  // On many processes, nodal values (`components` per node) made on every
  // process through `s`, on the first process: each owned node's from its
  // owner, zero at nodes no point reaches (as in the serial run).
  void gather_nodal_to_root(const Interpolation& s, std::vector<double>& values, int components);
  // The same on every process (collective): every node's value everywhere.
  void gather_nodal_to_all(const Interpolation& s, std::vector<double>& values, int components);

  Communicator comm;
  GridGeometry grid;
  PeriodicGrid periodic;  // the axes along which the grid wraps (mpm/periodic_grid.hpp)
  NodeState nodes;
  PointSet points;
  Executor exec;
  Interpolation shape;
  std::vector<BodyPoints> bodies;

 private:
  void locate_cells();  // the cell of every point, at the start of the step
  void collect_points(std::unique_ptr<PointSet>& into, bool everywhere);
  void gather_nodal(const Interpolation& s, std::vector<double>& values, int components, bool everywhere);
  void make_copy(std::unique_ptr<PointSet>& into, bool everywhere);

  std::unique_ptr<ShapeFunction> shape_function_;
  std::size_t total_points_ = 0, first_point_ = 0;
  std::unique_ptr<PointSet> gathered_;  // the first process's copy of every point, for outputs
  std::unique_ptr<PointSet> every_;     // every process's copy of every point, for point loads
  std::vector<double> exchanged_;
  // /volumetric_strain "cell_average": each point's volumetric strain rate is
  // the volume-weighted mean of its cell's (B-bar-like; removes the locking
  // of isochoric plastic flow on low-order shape functions).
  bool average_volumetric_rate_;
  ExpandedSupports expanded_;
  bool expanded_current_ = false;

  void start_node_terms(int k);
  template <class Terms>
  void add_node_terms(std::size_t I, Terms& terms) {
    double t[max_node_terms] = {};
    if (!terms(I, t)) return;
    node_terms_.push_back(static_cast<double>(I));
    node_terms_.insert(node_terms_.end(), t, t + node_term_count_);
  }
  NodeTerms sum_node_terms();
  int node_term_count_ = 0;
  std::vector<double> node_terms_, all_node_terms_;
  std::vector<std::size_t> node_order_;  // kept: sums over nodes run every step
  std::vector<ScatterRange> all_nodes_;  // one process: every node
  std::vector<NodeId> point_cell_;
  ScatterRanges point_cell_chunks_;
  std::vector<double> cell_volume_, cell_rate_;
};

}  // namespace suffuse::detail
