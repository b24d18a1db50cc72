// One field of a frame's material points as numbers, and the box of each
// point: what the profiles and colour maps of suffuse plot draw.
#pragma once

#include <vtkPolyData.h>

#include <array>
#include <string>
#include <vector>

namespace suffuse::plot {

struct PointField {
  std::string name;   // as asked: porosity, velocity:y, stress:XY
  std::string label;  // for an axis or a colour bar, with the unit when the file has it: "velocity y [m/s]"
  std::vector<double> values;  // one per point
};

// The field SPEC of POINTS: an array name, or NAME:COMPONENT for an array of
// several components, where COMPONENT is x, y, z (vectors), a component name
// the file gives (XX, YY, ZZ, XY, YZ, XZ for stress and strain), a component
// index from 0, or magnitude (a vector's default; a tensor needs a component). Throws
// suffuse::Error naming the fields and components there are.
PointField point_field(vtkPolyData* points, const std::string& spec);

// Whether POINTS lie in a plane z = 0 (a 2D run).
bool is_planar(vtkPolyData* points);

// The edge lengths of each point's box: the `size` array when the file has
// it, else a cube (a square in 2D) of the point's volume. Throws
// suffuse::Error when the file has neither.
std::vector<std::array<double, 3>> point_sizes(vtkPolyData* points);

}  // namespace suffuse::plot
