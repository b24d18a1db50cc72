#pragma once
// The two parallel patterns of the step, shared by the stage files: chunks of
// a range, and scatters into nodal arrays with per-thread buffers.
#include <algorithm>
#include <exception>

#include "suffuse/simulation.hpp"

namespace suffuse {

template <class Body>
void Simulation::for_chunks(std::size_t n, Body&& body) {
  if (threads_ == 1) {
    body(0, std::size_t{0}, n);
    return;
  }
  // One contiguous chunk per thread; an exception in any chunk is rethrown
  // here, after every thread has finished.
  std::vector<std::exception_ptr>& errors = chunk_errors_;
  std::fill(errors.begin(), errors.end(), nullptr);
#pragma omp parallel for num_threads(threads_) schedule(static, 1)
  for (int t = 0; t < threads_; ++t) {
    try {
      body(t, n * t / threads_, n * (t + 1) / threads_);
    } catch (...) {
      errors[t] = std::current_exception();
    }
  }
  for (const auto& e : errors)
    if (e) std::rethrow_exception(e);
}

template <class Kernel>
void Simulation::scatter(const ScatterTargets& targets, Kernel&& kernel) {
  for_chunks(points_.size(), [&](int t, std::size_t b, std::size_t e) {
    if (t == 0) {
      kernel(b, e, targets.array.data());
      return;
    }
    std::array<double*, 8> mine{};
    double* next = scatter_[t - 1].data();
    for (int k = 0; k < targets.count; ++k) {
      mine[k] = next;
      std::fill(next, next + targets.size[k], 0.0);
      next += targets.size[k];
    }
    kernel(b, e, mine.data());
  });
  if (scatter_.empty()) return;
  // Sum the private buffers into the node arrays, in thread order.
  for (int k = 0; k < targets.count; ++k) {
    std::size_t offset = 0;
    for (int j = 0; j < k; ++j) offset += targets.size[j];
    for_chunks(targets.size[k], [&](int, std::size_t b, std::size_t e) {
      for (const std::vector<double>& buffer : scatter_)
        for (std::size_t i = b; i < e; ++i) targets.array[k][i] += buffer[offset + i];
    });
  }
}

}  // namespace suffuse
