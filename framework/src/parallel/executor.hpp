#pragma once
// The two parallel patterns of the step, named once and reused by every part:
// a loop over contiguous chunks of a range, and a scatter from points into
// nodal (or cell) arrays. The scatter sums in an order fixed by the points
// alone, so results are bit for bit the same for any thread count (no
// atomics, no per-thread sums).
#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <exception>
#include <limits>
#include <string>
#include <vector>

#include "parallel/communicator.hpp"
#include "parallel/kernel_isa.hpp"
#include "suffuse/error.hpp"
#include "suffuse/grid.hpp"

namespace suffuse::detail {

// The entries [first, last) the points of one scatter chunk add to.
struct ScatterRange {
  std::size_t first = 0, last = 0;
};
// Those of every chunk of `points` points (Executor::chunk_ranges); in a
// run on many processes, `chunks` are this process's and `all` every
// process's, in the serial run's chunk order, and per process:
// - held: the entries its chunks touch (from its chunks' first to their
//   last; empty if it has no point);
// - owned: those of its held entries no lower process holds. Each entry a
//   point touches is owned by one process, which gives its value to sums
//   over entries and to outputs (Domain::node_sums).
struct ScatterRanges {
  std::size_t points = 0;
  std::vector<ScatterRange> chunks, all;
  std::vector<ScatterRange> held;
  std::vector<std::vector<ScatterRange>> owned;
};

// The arrays one scatter adds into, and which of their entries each point
// adds to: `per_point` indices per point in `index` (a point's cell, or its
// support's first node), each naming the entries [index, index + extent] of
// every array (an array holds size / entries values per entry: 1 for a mass,
// dim for a momentum). `ranges`, if given, are those of
// Executor::chunk_ranges for this index, computed once where the index is
// made (the shape functions' serve every nodal scatter of a step).
class ScatterTargets {
 public:
  static constexpr int capacity = 16;
  // `halo`: on many processes, entries on each side of the process's held
  // ones whose sums it needs complete too (what its nodal stages read
  // beyond them; ScatterRanges).
  ScatterTargets(const NodeId* index, int per_point, std::size_t entries,
                 const ScatterRanges* ranges = nullptr, std::int64_t extent = 0, std::size_t halo = 0)
      : index_(index), per_point_(per_point), entries_(entries), ranges_(ranges), extent_(extent), halo_(halo) {}
  void add(std::vector<double>& v) {
    if (count_ == capacity)
      throw Error("internal: a scatter into more than " + std::to_string(capacity) + " arrays");
    if (entries_ == 0 || v.size() % entries_ != 0)
      throw Error("internal: a scatter target of " + std::to_string(v.size()) + " values for " +
                  std::to_string(entries_) + " entries");
    array_[count_] = v.data();
    components_[count_++] = v.size() / entries_;
  }
  int count() const { return count_; }
  double* const* arrays() const { return array_.data(); }
  std::size_t components(int k) const { return components_[k]; }
  std::size_t components_total() const {
    std::size_t n = 0;
    for (int k = 0; k < count_; ++k) n += components_[k];
    return n;
  }
  const NodeId* index() const { return index_; }
  int per_point() const { return per_point_; }
  std::size_t entries() const { return entries_; }
  const ScatterRanges* ranges() const { return ranges_; }
  std::int64_t extent() const { return extent_; }
  std::size_t halo() const { return halo_; }

 private:
  const NodeId* index_;
  int per_point_;
  std::size_t entries_;
  const ScatterRanges* ranges_;
  std::int64_t extent_;
  std::size_t halo_;
  std::array<double*, capacity> array_{};
  std::array<std::size_t, capacity> components_{};
  int count_ = 0;
};

class Executor {
 public:
  // Points per scatter chunk: at least min_scatter_chunk, and at least the
  // points of two of the grid's layers (cells along its last axis), so that
  // a chunk of points that follow the grid's order spans about two layers of
  // cells: more than a linear support, so that the chunks two apart touch
  // no common node and the scatter needs no buffer (scatter). Otherwise a
  // chunk's buffer runs over the node numbers its points touch, at
  // least two node layers in 3D and two rows in 2D: with shorter chunks the
  // buffers together would hold many copies of the nodal arrays. Fixed by
  // the points and the grid, whatever the thread count, so the sums are too.
  static constexpr std::size_t min_scatter_chunk = 2048;
  std::size_t scatter_chunk(std::size_t points) const {
    if (comm_) points = total_points_;  // the serial run's chunks
    return std::max(min_scatter_chunk, 2 * ((points + layers_ - 1) / layers_));
  }

  static constexpr std::size_t default_layers = std::numeric_limits<std::size_t>::max() / 2;
  explicit Executor(int threads, std::size_t layers = default_layers, KernelIsa isa = KernelIsa::portable)
      : threads_(std::max(1, threads)), layers_(std::max<std::size_t>(1, layers)), isa_(isa), errors_(threads_) {}

  int threads() const { return threads_; }
  KernelIsa isa() const { return isa_; }
  // Values received from other processes by the scatters so far.
  std::size_t exchanged_values() const { return exchanged_; }

  // A run on many processes: this one holds the points [first, first +
  // local) of the serial run's `total`, whole scatter chunks of it (first is
  // a multiple of scatter_chunk(total)). Collective: every process calls it.
  void distribute(const Communicator& comm, std::size_t total, std::size_t first, std::size_t local) {
    comm_ = &comm;
    total_points_ = total;
    const std::size_t chunk = scatter_chunk(total);
    first_chunk_ = first / chunk;
    chunks_of_rank_ = comm.all_counts((local + chunk - 1) / chunk);
    first_chunk_of_rank_.assign(chunks_of_rank_.size() + 1, 0);
    for (std::size_t r = 0; r < chunks_of_rank_.size(); ++r)
      first_chunk_of_rank_[r + 1] = first_chunk_of_rank_[r] + chunks_of_rank_[r];
  }

  // The entries process `rank` needs complete after a scatter through
  // `ranges`: its held ones and `halo` on each side, within [0, entries).
  static ScatterRange needed(const ScatterRanges& ranges, std::size_t rank, std::size_t halo, std::size_t entries) {
    const ScatterRange& h = ranges.held[rank];
    if (h.first >= h.last) return {};
    return {h.first - std::min(h.first, halo), std::min(entries, h.last + halo)};
  }

  // kernel.template operator()<D, L>() for dimension `dim` on this run's
  // instruction set (kernel_isa.hpp): for the kernels written on Lanes<L>.
  template <class Kernel>
  void vector_kernel(int dim, const Kernel& kernel) const {
    run_vector_kernel(isa_, dim, kernel);
  }

  // A loop gives each thread at least this many points (or nodes): starting
  // and joining a parallel region costs microseconds, about a pass of a
  // thousand points, and the default column (640 points) ran half as fast
  // on two threads as on one when every pass was split.
  static constexpr std::size_t min_items_per_thread = 1024;

  // Calls body(thread, begin, end) on contiguous chunks of [0, n), one per
  // thread: threads() of them, or fewer where n * items_per_unit (the points
  // or nodes in all) gives a thread fewer than min_items_per_thread. Callers'
  // results do not depend on the chunks (the thread tests assert it), so
  // this changes no number. An exception in any chunk is rethrown here,
  // after every thread finished.
  template <class Body>
  void for_chunks(std::size_t n, Body&& body, std::size_t items_per_unit = 1) {
    const int threads = threads_for(n, items_per_unit);
    if (threads == 1) {
      body(0, std::size_t{0}, n);
      return;
    }
    std::fill(errors_.begin(), errors_.end(), nullptr);
#pragma omp parallel for num_threads(threads) schedule(static, 1)
    for (int t = 0; t < threads; ++t) {
      try {
        body(t, n * t / threads, n * (t + 1) / threads);
      } catch (...) {
        errors_[t] = std::current_exception();
      }
    }
    for (const auto& e : errors_)
      if (e) std::rethrow_exception(e);
  }

  // The threads a loop of n units of items_per_unit items each runs on.
  int threads_for(std::size_t n, std::size_t items_per_unit) const {
    if (threads_ == 1 || n <= 1) return 1;
    const std::size_t by_items = n * items_per_unit / min_items_per_thread;
    return static_cast<int>(std::max<std::size_t>(1, std::min({static_cast<std::size_t>(threads_), n, by_items})));
  }

  // Runs kernel(begin, end, arrays) on chunks of scatter_chunk(points) points;
  // `arrays` are the targets' data in the order they were added. Each chunk
  // touches a range of entries (the points of a chunk are neighbours when
  // they follow the grid's order, as bodies are made).
  // - Where the ranges of the even chunks are disjoint, and so are those of
  //   the odd ones (every chunk spans more than the support's width), the
  //   even chunks add straight into the targets, in parallel, then the odd
  //   ones: no buffer to zero and add.
  // - Otherwise the first chunk adds into the targets and every other one
  //   into a buffer over its range, zeroed first; the buffers are then added
  //   into the targets entry by entry in chunk order.
  // Either way the order of the sums is fixed by the points and the grid.
  template <class Kernel>
  void scatter(std::size_t points, const ScatterTargets& targets, Kernel&& kernel) {
    if (comm_) {
      scatter_across_processes(points, targets, kernel);
      return;
    }
    const std::size_t chunk = scatter_chunk(points), chunks = (points + chunk - 1) / chunk;
    if (chunks <= 1) {
      if (points > 0) kernel(std::size_t{0}, points, targets.arrays());
      return;
    }
    const bool cached = targets.ranges() && targets.ranges()->points == points;
    if (!cached) chunk_ranges(targets.index(), targets.per_point(), points, ranges_, targets.extent());
    const std::vector<ScatterRange>& ranges = cached ? targets.ranges()->chunks : ranges_.chunks;
    if (parities_are_disjoint(ranges)) {
      for (std::size_t parity : {0, 1})
        for_chunks((chunks + 1 - parity) / 2, [&](int, std::size_t kb, std::size_t ke) {
          for (std::size_t c = 2 * kb + parity; c < 2 * ke + parity && c < chunks; c += 2)
            kernel(c * chunk, std::min(points, (c + 1) * chunk), targets.arrays());
        }, chunk);
      return;
    }
    offsets_.resize(chunks);
    std::size_t total = 0;
    for (std::size_t c = 1; c < chunks; ++c) {
      offsets_[c] = total;
      total += (ranges[c].last - ranges[c].first) * targets.components_total();
    }
    if (buffer_.size() < total) buffer_.resize(total);
    for_chunks(chunks, [&](int, std::size_t cb, std::size_t ce) {
      for (std::size_t c = cb; c < ce; ++c) {
        const std::size_t begin = c * chunk, end = std::min(points, begin + chunk);
        if (c == 0) {
          kernel(begin, end, targets.arrays());
          continue;
        }
        // Each array's part of the buffer, shifted so that the kernel
        // indexes it by entry as it does the targets.
        std::array<double*, ScatterTargets::capacity> mine{};
        double* next = buffer_.data() + offsets_[c];
        const std::size_t width = ranges[c].last - ranges[c].first;
        for (int k = 0; k < targets.count(); ++k) {
          const std::size_t n = width * targets.components(k);
          std::fill(next, next + n, 0.0);
          mine[k] = next - ranges[c].first * targets.components(k);
          next += n;
        }
        kernel(begin, end, mine.data());
      }
    }, chunk);
    for_chunks(targets.entries(), [&](int, std::size_t eb, std::size_t ee) {
      for (std::size_t c = 1; c < chunks; ++c) {
        const std::size_t first = std::max(eb, ranges[c].first), last = std::min(ee, ranges[c].last);
        if (first >= last) continue;
        const double* part = buffer_.data() + offsets_[c];
        const std::size_t width = ranges[c].last - ranges[c].first;
        for (int k = 0; k < targets.count(); ++k) {
          const std::size_t m = targets.components(k);
          double* out = targets.arrays()[k];
          const double* from = part - ranges[c].first * m;
          for (std::size_t i = first * m; i < last * m; ++i) out[i] += from[i];
          part += width * m;
        }
      }
    });
  }

  // Totals of k sums over points (k <= max_totals; add(p, sums) adds point
  // p's terms): each scatter chunk sums its points in order, and the chunks'
  // sums are added in chunk order, on every process. The same totals for any
  // thread and process count (a mass ledger that a checkpoint keeps).
  static constexpr int max_totals = 8;
  template <class Add>
  std::array<double, max_totals> totals(std::size_t points, int k, Add&& add) {
    if (k < 0 || k > max_totals) throw Error("internal: " + std::to_string(k) + " totals at once");
    const std::size_t chunk = scatter_chunk(points), mine = (points + chunk - 1) / chunk;
    const auto m = static_cast<std::size_t>(k);
    partial_.assign(mine * m, 0.0);
    for_chunks(mine, [&](int, std::size_t cb, std::size_t ce) {
      for (std::size_t c = cb; c < ce; ++c)
        for (std::size_t p = c * chunk; p < std::min(points, (c + 1) * chunk); ++p) add(p, partial_.data() + c * m);
    }, chunk);
    const std::vector<double>* all = &partial_;
    if (comm_) {
      std::vector<std::size_t> counts(chunks_of_rank_.size());
      for (std::size_t r = 0; r < counts.size(); ++r) counts[r] = chunks_of_rank_[r] * m;
      comm_->all_gather(partial_, counts, received_);
      all = &received_;
    }
    std::array<double, max_totals> total{};
    for (std::size_t c = 0; m > 0 && c < all->size() / m; ++c)
      for (std::size_t i = 0; i < m; ++i) total[i] += (*all)[c * m + i];
    return total;
  }

  // True when each chunk's range ends before the range of the chunk two on
  // begins: no entry is touched by two even chunks or by two odd ones.
  static bool parities_are_disjoint(const std::vector<ScatterRange>& ranges) {
    for (std::size_t c = 2; c < ranges.size(); ++c)
      if (ranges[c - 2].last > ranges[c].first) return false;
    return true;
  }

  // The entries each scatter chunk of `points` touches through `index`
  // (each index reaching `extent` entries past itself).
  void chunk_ranges(const NodeId* index, int per_point, std::size_t points, ScatterRanges& out,
                    std::int64_t extent = 0) {
    const std::size_t chunk = scatter_chunk(points), chunks = (points + chunk - 1) / chunk;
    const std::size_t m = static_cast<std::size_t>(per_point);
    out.points = points;
    out.chunks.resize(chunks);
    if (chunks <= 1 && !comm_) return;  // one chunk adds into the targets: no range needed
    for_chunks(chunks, [&](int, std::size_t cb, std::size_t ce) {
      for (std::size_t c = cb; c < ce; ++c) {
        NodeId lo = std::numeric_limits<NodeId>::max(), hi = -1;
        const std::size_t end = std::min(points, (c + 1) * chunk) * m;
        for (std::size_t k = c * chunk * m; k < end; ++k) {
          lo = std::min(lo, index[k]);
          hi = std::max(hi, index[k]);
        }
        out.chunks[c] = hi < lo ? ScatterRange{}
                                : ScatterRange{static_cast<std::size_t>(lo),
                                               static_cast<std::size_t>(hi) + static_cast<std::size_t>(extent) + 1};
      }
    }, chunk);
    if (comm_) gather_ranges(out);
  }

 private:
  // Every process's chunk ranges, in chunk order (node numbers are exact in
  // doubles up to 2^53).
  void gather_ranges(ScatterRanges& out) {
    send_.clear();
    for (const ScatterRange& r : out.chunks) {
      send_.push_back(static_cast<double>(r.first));
      send_.push_back(static_cast<double>(r.last));
    }
    std::vector<std::size_t> counts(chunks_of_rank_.size());
    for (std::size_t r = 0; r < counts.size(); ++r) counts[r] = 2 * chunks_of_rank_[r];
    comm_->all_gather(send_, counts, received_);
    out.all.resize(received_.size() / 2);
    for (std::size_t c = 0; c < out.all.size(); ++c)
      out.all[c] = {static_cast<std::size_t>(received_[2 * c]), static_cast<std::size_t>(received_[2 * c + 1])};
    const std::size_t ranks = chunks_of_rank_.size();
    out.held.assign(ranks, ScatterRange{});
    out.owned.assign(ranks, {});
    for (std::size_t r = 0; r < ranks; ++r) {
      ScatterRange& h = out.held[r];
      h = {std::numeric_limits<std::size_t>::max(), 0};
      for (std::size_t c = first_chunk_of_rank_[r]; c < first_chunk_of_rank_[r + 1]; ++c)
        if (out.all[c].first < out.all[c].last)
          h.first = std::min(h.first, out.all[c].first), h.last = std::max(h.last, out.all[c].last);
      if (h.first >= h.last) {
        h = {};
        continue;
      }
      // Its held entries less every lower process's.
      std::vector<ScatterRange> left{h};
      for (std::size_t q = 0; q < r; ++q) {
        const ScatterRange& cut = out.held[q];
        std::vector<ScatterRange> next;
        for (const ScatterRange& piece : left) {
          if (cut.first >= cut.last || cut.last <= piece.first || cut.first >= piece.last) {
            next.push_back(piece);
            continue;
          }
          if (piece.first < cut.first) next.push_back({piece.first, cut.first});
          if (cut.last < piece.last) next.push_back({cut.last, piece.last});
        }
        left = std::move(next);
      }
      out.owned[r] = std::move(left);
    }
  }

  // The scatter of a run on many processes, each holding whole chunks of
  // the serial run's: each sum a process needs (its held entries and the
  // targets' halo, `needed`) is formed in the serial run's order. Each
  // process sends another only the part of its chunks' entries the other
  // needs: neighbours along the points' order exchange, the others not.
  // Entries a process does not need are left incomplete.
  // - Disjoint parities: the even chunks add into the targets and send
  //   their entries (no two even chunks share one); then the odd chunks,
  //   the same way.
  // - Otherwise: chunk 0 adds into the targets, every other chunk into a
  //   buffer of its own; then each process receives chunk 0's entries and
  //   the buffers it needs, and adds the buffers in chunk order, as the
  //   serial run does.
  template <class Kernel>
  void scatter_across_processes(std::size_t points, const ScatterTargets& targets, Kernel& kernel) {
    const std::size_t chunk = scatter_chunk(points), mine = (points + chunk - 1) / chunk;
    const bool cached = targets.ranges() && targets.ranges()->points == points && !targets.ranges()->all.empty();
    if (!cached) chunk_ranges(targets.index(), targets.per_point(), points, ranges_, targets.extent());
    const ScatterRanges& ranges = cached ? *targets.ranges() : ranges_;
    const std::vector<ScatterRange>& all = ranges.all;
    const std::size_t first = first_chunk_, chunks = all.size(), width = targets.components_total();
    const std::size_t ranks = chunks_of_rank_.size(), me = static_cast<std::size_t>(comm_->rank());
    need_.resize(ranks);
    for (std::size_t r = 0; r < ranks; ++r) need_[r] = needed(ranges, r, targets.halo(), targets.entries());
    // The entries of chunk c that process r needs.
    auto overlap = [&](std::size_t c, std::size_t r) {
      const std::size_t lo = std::max(all[c].first, need_[r].first), hi = std::min(all[c].last, need_[r].last);
      return lo < hi ? ScatterRange{lo, hi} : ScatterRange{};
    };
    auto run = [&](std::size_t c, double* const* arrays) {
      const std::size_t local = c - first;
      kernel(local * chunk, std::min(points, (local + 1) * chunk), arrays);
    };
    // The chosen chunks' values, from their owners to the processes that
    // need them: pack(c, part) appends the values of chunk c on entries
    // `part` (array by array), take(c, part, from) stores what arrived.
    auto share = [&](auto chosen, auto&& pack, auto&& take) {
      send_.clear();
      std::vector<std::size_t> send_counts(ranks, 0), recv_counts(ranks, 0);
      for (std::size_t r = 0; r < ranks; ++r) {
        if (r == me) continue;
        for (std::size_t c = first; c < first + mine; ++c) {
          const ScatterRange part = overlap(c, r);
          if (!chosen(c) || part.first >= part.last) continue;
          pack(c, part);
          send_counts[r] += (part.last - part.first) * width;
        }
        for (std::size_t c = first_chunk_of_rank_[r]; c < first_chunk_of_rank_[r + 1]; ++c)
          if (chosen(c)) recv_counts[r] += (overlap(c, me).last - overlap(c, me).first) * width;
      }
      comm_->all_to_all(send_, send_counts, recv_counts, received_);
      exchanged_ += received_.size();
      const double* from = received_.data();
      for (std::size_t r = 0; r < ranks; ++r) {
        if (r == me) continue;
        for (std::size_t c = first_chunk_of_rank_[r]; c < first_chunk_of_rank_[r + 1]; ++c) {
          const ScatterRange part = overlap(c, me);
          if (!chosen(c) || part.first >= part.last) continue;
          take(c, part, from);
          from += (part.last - part.first) * width;
        }
      }
    };
    auto pack_from = [&](double* const* arrays, const ScatterRange& part) {
      for (int k = 0; k < targets.count(); ++k) {
        const std::size_t m = targets.components(k);
        send_.insert(send_.end(), arrays[k] + part.first * m, arrays[k] + part.last * m);
      }
    };
    auto take_into = [&](double* const* arrays, const ScatterRange& part, const double* from) {
      for (int k = 0; k < targets.count(); ++k) {
        const std::size_t m = targets.components(k), n = (part.last - part.first) * m;
        std::copy(from, from + n, arrays[k] + part.first * m);
        from += n;
      }
    };
    if (parities_are_disjoint(all)) {
      for (std::size_t parity : {0, 1}) {
        const std::size_t begin = first + ((first % 2 == parity) ? 0 : 1);
        const std::size_t count = begin < first + mine ? (first + mine - begin + 1) / 2 : 0;
        for_chunks(count, [&](int, std::size_t kb, std::size_t ke) {
          for (std::size_t k = kb; k < ke; ++k) run(begin + 2 * k, targets.arrays());
        }, chunk);
        share([&](std::size_t c) { return c % 2 == parity; },
              [&](std::size_t, const ScatterRange& part) { pack_from(targets.arrays(), part); },
              [&](std::size_t, const ScatterRange& part, const double* from) {
                take_into(targets.arrays(), part, from);
              });
      }
      return;
    }
    // Buffers for this process's chunks and those whose entries it needs
    // only: their sum over all chunks would grow with the whole grid.
    offsets_.assign(chunks, 0);
    std::size_t held = 0;
    for (std::size_t c = 1; c < chunks; ++c) {
      const ScatterRange needed_here = overlap(c, me);
      if ((c < first || c >= first + mine) && needed_here.first >= needed_here.last) continue;
      offsets_[c] = held;
      held += (all[c].last - all[c].first) * width;
    }
    if (buffer_.size() < held) buffer_.resize(held);
    // Each such chunk's buffer: the arrays one after another, each indexed
    // by entry as the targets are (chunk 0: the targets).
    auto parts = [&](std::size_t c) {
      std::array<double*, ScatterTargets::capacity> part{};
      double* next = buffer_.data() + offsets_[c];
      for (int k = 0; k < targets.count(); ++k) {
        part[k] = c == 0 ? targets.arrays()[k] : next - all[c].first * targets.components(k);
        next += (all[c].last - all[c].first) * targets.components(k);
      }
      return part;
    };
    for_chunks(mine, [&](int, std::size_t kb, std::size_t ke) {
      for (std::size_t c = first + kb; c < first + ke; ++c) {
        if (c > 0) std::fill_n(buffer_.data() + offsets_[c], (all[c].last - all[c].first) * width, 0.0);
        run(c, parts(c).data());
      }
    }, chunk);
    share([](std::size_t) { return true; },
          [&](std::size_t c, const ScatterRange& part) { pack_from(parts(c).data(), part); },
          [&](std::size_t c, const ScatterRange& part, const double* from) {
            take_into(parts(c).data(), part, from);
          });
    const ScatterRange own = need_[me];
    for_chunks(own.last - own.first, [&](int, std::size_t eb, std::size_t ee) {
      for (std::size_t c = 1; c < chunks; ++c) {
        const std::size_t lo = std::max(own.first + eb, all[c].first), hi = std::min(own.first + ee, all[c].last);
        if (lo >= hi) continue;
        const auto part = parts(c);
        for (int k = 0; k < targets.count(); ++k) {
          const std::size_t m = targets.components(k);
          double* out = targets.arrays()[k];
          for (std::size_t i = lo * m; i < hi * m; ++i) out[i] += part[k][i];
        }
      }
    });
  }

  const Communicator* comm_ = nullptr;  // a run on many processes; null: one
  std::size_t total_points_ = 0, first_chunk_ = 0;
  std::vector<std::size_t> chunks_of_rank_, first_chunk_of_rank_;
  std::vector<ScatterRange> need_;       // per process: the entries it needs from a scatter
  std::vector<double> send_, received_;  // exchanges between processes
  std::vector<double> partial_;          // per chunk: its sums (totals)
  std::size_t exchanged_ = 0;
  int threads_;
  std::size_t layers_;
  KernelIsa isa_;
  std::vector<std::exception_ptr> errors_;  // per thread, for for_chunks
  ScatterRanges ranges_;                    // per scatter chunk: the entries it touches, when not given
  std::vector<std::size_t> offsets_;        // per scatter chunk: where its buffer starts
  std::vector<double> buffer_;              // the chunks' sums, grown on first use only
};

}  // namespace suffuse::detail
