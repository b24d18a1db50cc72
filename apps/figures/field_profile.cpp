// A field of the material points along a line (see field_profile.hpp).
#include "field_profile.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <suffuse/error.hpp>

namespace suffuse::plot {

namespace {

// Whether the infinite line through A along the unit vector D passes through
// the box of edge lengths SIZE centred at P (slab test); touching counts.
bool crosses_box(const std::array<double, 3>& a, const std::array<double, 3>& d, const double* p,
                 const std::array<double, 3>& size) {
  double t0 = -std::numeric_limits<double>::max(), t1 = std::numeric_limits<double>::max();
  for (int k = 0; k < 3; ++k) {
    // Boxes a tenth larger: a line along the edge between two rows of points
    // (the axis of a body two points wide) takes both rows, also where the
    // boxes, which the file gives as squares of the points' volumes, shrank.
    const double half = 0.55 * size[k] + 1e-12;
    if (std::abs(d[k]) < 1e-14) {
      if (std::abs(a[k] - p[k]) > half) return false;
      continue;
    }
    const double u = (p[k] - half - a[k]) / d[k], v = (p[k] + half - a[k]) / d[k];
    t0 = std::max(t0, std::min(u, v));
    t1 = std::min(t1, std::max(u, v));
  }
  return t0 <= t1;
}

}  // namespace

std::vector<ProfileSample> extract_profile(vtkPolyData* points, const std::vector<double>& values,
                                           const std::vector<std::array<double, 3>>& sizes, const ProfileLine& line) {
  std::array<double, 3> d{};
  double length = 0;
  for (int k = 0; k < 3; ++k) d[k] = line.to[k] - line.from[k], length += d[k] * d[k];
  length = std::sqrt(length);
  if (!(length > 0)) throw Error("the profile line has no length: its two ends are the same point");
  for (double& c : d) c /= length;

  std::vector<ProfileSample> samples;
  const double slack = 1e-9 * length;
  for (vtkIdType i = 0; i < points->GetNumberOfPoints(); ++i) {
    const auto p = static_cast<std::size_t>(i);
    double x[3];
    points->GetPoint(i, x);
    double s = 0, distance = 0;
    for (int k = 0; k < 3; ++k) s += (x[k] - line.from[k]) * d[k];
    if (s < -slack || s > length + slack) continue;
    for (int k = 0; k < 3; ++k) {
      const double r = x[k] - line.from[k] - s * d[k];
      distance += r * r;
    }
    const bool near = line.band > 0 ? std::sqrt(distance) <= line.band : crosses_box(line.from, d, x, sizes[p]);
    if (near) samples.push_back({std::clamp(s, 0.0, length), values[p]});
  }
  std::stable_sort(samples.begin(), samples.end(),
                   [](const ProfileSample& a, const ProfileSample& b) { return a.s < b.s; });
  return samples;
}

}  // namespace suffuse::plot
