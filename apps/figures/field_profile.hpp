// A field of the material points along a line: the points near the line,
// projected on it and sorted, for the profiles of suffuse plot.
#pragma once

#include <vtkPolyData.h>

#include <array>
#include <vector>

namespace suffuse::plot {

struct ProfileLine {
  std::array<double, 3> from{}, to{};  // the ends [m]; z = 0 in 2D
  double band = 0;                     // > 0: points at most this far from the line [m]; 0: points whose box it crosses
};

struct ProfileSample {
  double s = 0;      // distance along the line from `from` [m]
  double value = 0;  // the field at the point
};

// The points of POINTS near LINE (between its ends), with VALUES (one per
// point), by increasing s. Without a band a point is taken when the line
// passes through its box (SIZES, one per point) made a tenth larger: for even
// points a band about half a point wide on each side, and a line along the
// edge between two rows of points takes both.
// Throws suffuse::Error when the ends coincide; empty when no point is near.
std::vector<ProfileSample> extract_profile(vtkPolyData* points, const std::vector<double>& values,
                                           const std::vector<std::array<double, 3>>& sizes, const ProfileLine& line);

}  // namespace suffuse::plot
