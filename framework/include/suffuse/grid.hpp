#pragma once
// Structured regular background grid: geometry (immutable) and nodal state.
// Nodes are numbered i + nx*(j + ny*k) with nx, ny, nz nodes per axis.
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace suffuse {

// The index of a node in a point's support. 32 bits: the interpolation holds
// one per point and node, and every stage of a step reads them, so half the
// bytes are half the traffic; scenes are limited to 2^31 - 1 nodes (/grid).
using NodeId = std::int32_t;

class GridGeometry {
 public:
  GridGeometry(int dim, std::array<double, 3> origin, std::array<double, 3> cell_size,
               std::array<int, 3> cells);

  int dim() const { return dim_; }
  const std::array<double, 3>& origin() const { return origin_; }
  const std::array<double, 3>& cell_size() const { return h_; }
  const std::array<int, 3>& cells() const { return cells_; }
  const std::array<int, 3>& nodes_per_axis() const { return nodes_; }
  std::size_t node_count() const { return node_count_; }
  double min_cell_size() const;
  double upper(int axis) const { return origin_[axis] + h_[axis] * cells_[axis]; }

  std::int64_t node_index(int i, int j, int k) const {
    return i + static_cast<std::int64_t>(nodes_[0]) * (j + static_cast<std::int64_t>(nodes_[1]) * k);
  }
  std::array<int, 3> node_ijk(std::int64_t index) const;
  std::array<double, 3> node_position(std::int64_t index) const;
  // True when x (dim components) lies in the closed grid box.
  bool contains(const double* x) const;

 private:
  int dim_;
  std::array<double, 3> origin_, h_;
  std::array<int, 3> cells_, nodes_;
  std::size_t node_count_;
};

// Area (a length in 2D) of the face normal to `axis` of the dual cell of node
// ijk: a cell size along each other axis, halved where the node is at the end
// of that axis. The one formula for tributary areas of boundary nodes and the
// faces of the transport's dual cells.
inline double dual_face_area(const std::array<int, 3>& nodes_per_axis, const std::array<double, 3>& cell_size,
                             const std::array<int, 3>& ijk, int axis, int dim) {
  double area = 1;
  for (int b = 0; b < dim; ++b)
    if (b != axis) area *= cell_size[b] * ((ijk[b] == 0 || ijk[b] == nodes_per_axis[b] - 1) ? 0.5 : 1.0);
  return area;
}

// A face of the grid box: left/right (x = min/max), bottom/top (y), front/back (z).
struct GridFace {
  int axis = 0;        // 0, 1 or 2
  bool upper = false;  // the max side of the axis
  double outward() const { return upper ? 1.0 : -1.0; }  // sign of the outward normal
};

// Nodal state of one time step (structure-of-arrays, vectors interleaved by dim).
struct NodeState {
  std::vector<double> mass;      // [kg]
  std::vector<double> momentum;  // [kg m/s]
  std::vector<double> force;     // [N] internal + external
  std::vector<double> velocity;  // [m/s] of the grid update, then of the MUSL remap
  std::vector<double> acceleration;  // [m/s^2] of the grid update, after constraints

  // Pore liquid, in saturated runs only (empty otherwise).
  std::vector<double> liquid_mass;          // sum N n rho_L V [kg]
  std::vector<double> liquid_inertia;       // sum N rho_L V [kg]; liquid_mass / liquid_inertia is the nodal porosity
  std::vector<double> liquid_momentum;      // [kg m/s]
  std::vector<double> liquid_force;         // [N] pressure gradient and gravity on the liquid
  std::vector<double> liquid_velocity;      // [m/s]
  std::vector<double> liquid_acceleration;  // [m/s^2]

  void resize(std::size_t nodes, int dim, bool with_liquid = false);
  bool has_liquid() const { return !liquid_mass.empty(); }
};

}  // namespace suffuse
