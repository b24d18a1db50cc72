#pragma once
// What a scene would take in memory, estimated from its grid and bodies
// before anything is allocated, so that a grid or point count that would
// exhaust the machine is refused with the estimate instead of failing (or
// being killed) midway.
#include <cstddef>

#include "suffuse/scene.hpp"

namespace suffuse::detail {

struct MemoryEstimate {
  double points = 0, nodes = 0, bytes = 0;
};

MemoryEstimate estimate_memory(const Scene& scene);
// Throws suffuse::Error when the estimate exceeds the memory available
// (MemAvailable of /proc/meminfo; no check where it cannot be read).
void check_memory(const Scene& scene);

}  // namespace suffuse::detail
