#include "run/memory_estimate.hpp"

#include <cmath>
#include <fstream>
#include <sstream>
#include <string>

#include "geometry/polygon.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

MemoryEstimate estimate_memory(const Scene& scene) {
  MemoryEstimate e;
  const int D = scene.dim;
  // Points: as Domain::create_body makes them.
  for (const BodySpec& b : scene.bodies) {
    double count = 1;
    for (int a = 0; a < D; ++a)
      count *= std::max(1.0, std::round((b.max[a] - b.min[a]) / scene.grid_cell_size[a] * b.points_per_cell));
    if (!b.points.empty()) count = static_cast<double>(b.points.size() / static_cast<std::size_t>(D + 1));
    if (b.polygon) {  // the share of its bounding box the polygon fills
      const std::array<double, 4> box = polygon_bounds(*b.polygon);
      count *= polygon_area(*b.polygon) / ((box[2] - box[0]) * (box[3] - box[1]));
    }
    e.points += count;
  }
  e.nodes = 1;
  for (int a = 0; a < D; ++a) e.nodes *= scene.grid_cells[a] + 1.0;
  // Per point: the fields (about 60 values in a saturated run with fines,
  // 35 dry) and the shape functions of the step (a first node and up to 3
  // weights and 3 derivatives per axis). Per node: the nodal arrays of both
  // phases and the transport (about 17 dim + 26 values), and the scatter's
  // chunk sums over the largest scatter's arrays (the saturated one, 4 + 4
  // dim values), counted as when a chunk spanned a layer of cells: its
  // buffer two to three layers of nodes, so 1.7 to 3.9 times over when the
  // points follow the grid's order, as bodies are made (counted for 2D and 3D
  // boxes, linear and GIMP). Since chunks span two layers, most scenes
  // scatter without buffers (Executor::scatter): an upper bound. Measured on
  // the bench columns within 30%.
  double per_point = (scene.saturated() ? 60.0 : 35.0) + 0.5 + 6.0 * D;
  // The quasi-static assembly reads the supports written out node by node
  // (an id, a weight and dim gradients each).
  if (scene.integration == TimeIntegration::quasi_static) per_point += std::pow(3.0, D) * (1.5 + D);
  const double per_node = 17.0 * D + 26.0 + 4.0 * (4.0 + 4.0 * D);
  e.bytes = 8.0 * (e.points * per_point + e.nodes * per_node);
  return e;
}

void check_memory(const Scene& scene) {
  std::ifstream meminfo("/proc/meminfo");
  std::string key;
  double kib = -1;
  while (meminfo >> key) {
    if (key == "MemAvailable:") {
      meminfo >> kib;
      break;
    }
    meminfo.ignore(256, '\n');
  }
  if (kib <= 0) return;
  const MemoryEstimate e = estimate_memory(scene);
  const double available = kib * 1024.0;
  if (e.bytes <= available) return;
  std::ostringstream msg;
  msg.precision(3);
  msg << "this scene needs about " << e.bytes / (1 << 30) << " GiB (" << e.points << " material points, " << e.nodes
      << " grid nodes), more than the " << available / (1 << 30)
      << " GiB this machine has available: use fewer /grid/cells or /bodies/*/points_per_cell";
  throw Error(msg.str());
}

}  // namespace suffuse::detail
