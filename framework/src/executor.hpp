#pragma once
// The two parallel patterns of the step, named once and reused by every part:
// a loop over contiguous chunks of a range, and a scatter from points into
// nodal arrays with per-thread buffers. Results depend on the thread count
// only through the order of floating-point sums, and are the same for the
// same thread count (no atomics).
#include <algorithm>
#include <array>
#include <cstddef>
#include <exception>
#include <string>
#include <vector>

#include "suffuse/error.hpp"

namespace suffuse::detail {

// The nodal arrays one scatter adds into.
class ScatterTargets {
 public:
  static constexpr int capacity = 16;
  void add(std::vector<double>& v) {
    if (count_ == capacity)
      throw Error("internal: a scatter into more than " + std::to_string(capacity) + " nodal arrays");
    array_[count_] = v.data();
    size_[count_++] = v.size();
  }
  int count() const { return count_; }
  double* const* arrays() const { return array_.data(); }
  std::size_t size(int k) const { return size_[k]; }
  std::size_t total_size() const {
    std::size_t n = 0;
    for (int k = 0; k < count_; ++k) n += size_[k];
    return n;
  }

 private:
  std::array<double*, capacity> array_{};
  std::array<std::size_t, capacity> size_{};
  int count_ = 0;
};

class Executor {
 public:
  explicit Executor(int threads) : threads_(std::max(1, threads)), buffers_(threads_ - 1), errors_(threads_) {}

  int threads() const { return threads_; }

  // Calls body(thread, begin, end) on threads() contiguous chunks of [0, n).
  // An exception in any chunk is rethrown here, after every thread finished.
  template <class Body>
  void for_chunks(std::size_t n, Body&& body) {
    if (threads_ == 1) {
      body(0, std::size_t{0}, n);
      return;
    }
    std::fill(errors_.begin(), errors_.end(), nullptr);
#pragma omp parallel for num_threads(threads_) schedule(static, 1)
    for (int t = 0; t < threads_; ++t) {
      try {
        body(t, n * t / threads_, n * (t + 1) / threads_);
      } catch (...) {
        errors_[t] = std::current_exception();
      }
    }
    for (const auto& e : errors_)
      if (e) std::rethrow_exception(e);
  }

  // Runs kernel(begin, end, arrays) on chunks of [0, points); `arrays` are the
  // targets' data in the order they were added. Threads other than the first
  // add into private buffers, sized from the targets (grown on first use
  // only), summed into the targets in thread order afterwards.
  template <class Kernel>
  void scatter(std::size_t points, const ScatterTargets& targets, Kernel&& kernel) {
    const std::size_t total = targets.total_size();
    for_chunks(points, [&](int t, std::size_t b, std::size_t e) {
      if (t == 0) {
        kernel(b, e, targets.arrays());
        return;
      }
      std::vector<double>& buffer = buffers_[t - 1];
      if (buffer.size() < total) buffer.resize(total);
      std::array<double*, ScatterTargets::capacity> mine{};
      double* next = buffer.data();
      for (int k = 0; k < targets.count(); ++k) {
        mine[k] = next;
        std::fill(next, next + targets.size(k), 0.0);
        next += targets.size(k);
      }
      kernel(b, e, mine.data());
    });
    if (buffers_.empty()) return;
    std::size_t offset = 0;
    for (int k = 0; k < targets.count(); ++k) {
      double* out = targets.arrays()[k];
      for_chunks(targets.size(k), [&](int, std::size_t b, std::size_t e) {
        for (const std::vector<double>& buffer : buffers_)
          for (std::size_t i = b; i < e; ++i) out[i] += buffer[offset + i];
      });
      offset += targets.size(k);
    }
  }

 private:
  int threads_;
  std::vector<std::vector<double>> buffers_;  // per extra thread
  std::vector<std::exception_ptr> errors_;    // per thread, for for_chunks
};

// Global reductions. Every total over the whole domain (the mass ledger, the
// total mass and momentum, the stable time step) goes through one of these:
// in a later MPI partition they become the sums and minima across processes.
// (The run summary's point count will need one too.)
inline double global_sum(double local) { return local; }
inline double global_min(double local) { return local; }

}  // namespace suffuse::detail
