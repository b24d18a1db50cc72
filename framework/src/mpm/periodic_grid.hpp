#pragma once
// A grid that wraps along some axes (/grid/periodic; docs/boundaries.md,
// Periodic grids): along such an axis the nodes of the upper face are the
// nodes of the lower face. The upper face's nodes stay in the grid as
// images: sums over a point's nodes go to the node they are (node(), or
// fold() after a scatter), and what a kernel reads of them is copied from
// it (copy_to_images()). Points leaving one face come in at the other
// (wrap()).
#include <array>
#include <cstdint>
#include <utility>
#include <vector>

#include "suffuse/grid.hpp"

namespace suffuse::detail {

class PeriodicGrid {
 public:
  PeriodicGrid(const GridGeometry& grid, const std::array<bool, 3>& axes);

  bool any() const { return axes_[0] || axes_[1] || axes_[2]; }
  bool along(int axis) const { return axes_[static_cast<std::size_t>(axis)]; }
  // The node a node is: the lower face's for an image, itself otherwise.
  std::int64_t node(std::int64_t node) const;
  // Adds each image's values (`components` per node) to the node it is,
  // and zeroes the image's.
  void fold(std::vector<double>& nodal, int components) const;
  // Each image's values, those of the node it is.
  void copy_to_images(std::vector<double>& nodal, int components) const;
  // Positions (dim per point) outside the period put back into it.
  void wrap(double* positions, std::size_t points) const;
  // A face node's area (face_node_area) on the seam: an end node of a
  // wrapped axis along the face has the whole width, its image none.
  double face_area(const GridGeometry& grid, GridFace face, std::int64_t node) const;
  // A cell's index along `axis` wrapped into the grid where the grid wraps
  // along it (-1 is the last cell); unchanged along other axes.
  int cell(int axis, int index) const;

 private:
  std::array<bool, 3> axes_{};
  int dim_;
  std::array<int, 3> nodes_;
  std::array<double, 3> lower_{}, upper_{};
  std::vector<std::pair<std::int64_t, std::int64_t>> images_;  // (image, the node it is)
};

}  // namespace suffuse::detail
