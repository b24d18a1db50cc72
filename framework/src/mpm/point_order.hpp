#pragma once
// The points kept in the grid's order (issues 17 and 18). The scatters cut
// the points, in their numbering, into chunks (Executor::scatter_chunk); a
// chunk whose points stay together touches few nodes, chunks two apart touch
// none (no buffers), and on many processes each process's points reach a
// narrow slab of nodes. Points that mix (a collapse, a flow along a slope)
// spread every chunk over more nodes: the scatters then need buffers and the
// processes' slabs overlap and exchange more. When the chunks' spread grows
// past a factor of what it was after the last sort, each body's points are
// sorted by cell again, on one process or many (points then move to the
// process that holds their new numbers). The spread, the decision and the
// new order depend on the points alone, not on the process or thread count,
// so the results stay the serial run's bit for bit (docs/parallel.md).
#include <cstddef>
#include <optional>
#include <vector>

#include "suffuse/points.hpp"

namespace suffuse::detail {

class Domain;

class PointOrder {
 public:
  // threshold: sort when the spread reaches this factor of the reference
  // (the spread after the last sort, or at the first step); 0: never.
  explicit PointOrder(double threshold) : threshold_(threshold) {}

  // Field "id": each point's number when the run started, which it keeps
  // through the sorts (for matching points between frames). Once the bodies
  // are made, before the points are split between processes; added when the
  // scene may sort (a threshold above 0).
  void number_points(PointSet& points);
  static FieldInfo id_field_info();
  const std::optional<FieldId>& id_field() const { return id_; }

  // The sum over the scatter chunks of the nodes each reaches (from the
  // first its points' supports touch to the last), from the step's shape
  // functions (Domain::locate_points): the same on any process count.
  double spread(const Domain& d) const;

  // At the start of a step, once the shape functions are evaluated: sorts
  // when the spread reached the threshold (collective); the shape functions
  // must then be evaluated again, and take_reference called. Returns whether it sorted; then new_numbers() holds the
  // new serial number of each of this process's points as they were
  // numbered before.
  bool sort_if_spread(Domain& d);
  // After a sort, once the shape functions were evaluated again: the spread
  // the next sorts are measured against.
  void take_reference(const Domain& d) { reference_ = spread(d); }
  // Each body's points by cell (stable: points of one cell keep their
  // order), whatever the spread (collective).
  void sort(Domain& d);
  const std::vector<std::size_t>& new_numbers() const { return new_number_; }

  // What a checkpoint keeps, so that a restarted run sorts when the run it
  // continues would have.
  double reference() const { return reference_; }
  void restore_reference(double reference) { reference_ = reference; }
  std::size_t sorts() const { return sorts_; }

 private:
  void compute_cells(const Domain& d);
  void sort_points(Domain& d);  // sort's work, in the buffers below
  double threshold_;
  std::optional<FieldId> id_;
  double reference_ = 0;
  std::size_t sorts_ = 0;
  std::vector<std::size_t> new_number_;
  // Work buffers of a sort, freed after it (sorts are rare; a field's copy
  // is up to 48 bytes per point, the counts 8 per cell and body).
  std::vector<std::size_t> cell_;
  std::vector<double> counts_, below_, send_, received_;
};

}  // namespace suffuse::detail
