#pragma once
// Named faces of the background grid, for boundary-condition plugins:
// left/right (x = min/max), bottom/top (y), front/back (z, 3D only).
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "suffuse/grid.hpp"
#include "suffuse/plugin.hpp"

namespace suffuse {

// The six names, in schema order, for a ParameterSchema::choice.
std::vector<std::string> grid_face_names();
// The face of a name from grid_face_names(); nothing for another name.
std::optional<GridFace> grid_face(const std::string& name);
// For a plugin's check(): front and back do not exist in 2D.
std::optional<ParameterIssue> grid_face_issue(const std::string& key, const std::string& name, int dim);
// Indices of the grid nodes on a face, in increasing order.
std::vector<std::int64_t> face_nodes(const GridGeometry& grid, GridFace face);
// A part of a face: its nodes within the box from box_min to box_max (the
// components along the face's normal are not read), in increasing order.
std::vector<std::int64_t> face_nodes(const GridGeometry& grid, GridFace face, std::span<const double> box_min,
                                     std::span<const double> box_max);
// For a plugin's check(): the optional keys box_min and box_max of a part of
// a face, both or neither, the box not empty.
std::vector<ParameterIssue> face_part_issues(const Parameters& p, int dim);

// The part of its face a condition opens to the pore liquid (bc/pore_pressure,
// bc/inflow_flux): the optional keys box_min, box_max and name, declared,
// read and resolved the same way for each (docs/boundaries.md, Parts of a face).
class FacePart {
 public:
  // Declares box_min, box_max and name; `acts` says what the condition does
  // there ("the pressure acts").
  static void declare(ParameterSchema& s, const std::string& acts);
  FacePart(const Parameters& p, GridFace face, std::string where, std::string plugin);
  // The face's nodes it holds, in increasing order; throws, naming the
  // condition, where it holds none.
  const std::vector<std::int64_t>& setup(const GridGeometry& grid);
  // The opening: the whole face, or these nodes, booked under its name.
  LiquidOpening opening(double concentration) const;
  const std::vector<std::int64_t>& nodes() const { return nodes_; }

 private:
  GridFace face_;
  std::vector<double> box_min_, box_max_;  // empty: the whole face
  std::string name_, where_, plugin_;
  std::vector<std::int64_t> nodes_;
};

// Tributary length (2D) or area (3D) of a node of the face: a cell size per
// axis along the face, half of it where the node is at the end of that axis.
// The areas of a face's nodes sum to the face's length or area.
double face_node_area(const GridGeometry& grid, GridFace face, std::int64_t node);

}  // namespace suffuse
