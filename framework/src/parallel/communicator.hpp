#pragma once
// The processes of a run and what they exchange (issue 18, docs/parallel.md).
// A run started by mpirun has one process per rank of MPI_COMM_WORLD; any
// other run, and any build without MPI, has one process, and every call
// below is then a copy or nothing.
//
// Each process holds a contiguous run of the points' scatter chunks (as the
// serial run numbers them). Every nodal sum is completed in the serial order
// (Executor::scatter) on the nodes the process's points reach and a halo
// around them, so those nodes, and then the points, are bit for bit those of
// the serial run, for any process count.
#include <cstddef>
#include <span>
#include <vector>

namespace suffuse::detail {

class Communicator {
 public:
  // MPI_COMM_WORLD if MPI is initialised (ParallelRun), else one process.
  Communicator();

  int rank() const { return rank_; }
  int size() const { return size_; }
  bool root() const { return rank_ == 0; }
  bool parallel() const { return size_ > 1; }

  // Over every process, the same on each. (Sums over points: Executor::totals.)
  double min(double local) const;
  double max(double local) const;
  bool any(bool local) const;
  // Each value summed over the lower-ranked processes (zero on the first):
  // where a process's share starts in an order by rank (collective).
  void sum_below(std::span<double> values) const;
  // Element-wise sums of every process's `values`, in place, the same bits
  // on every process (summed on the first, then broadcast: an all-reduce may
  // round differently on different processes, and their decisions must agree).
  void sum(std::span<double> values) const;
  // Every process gets the largest of each value over the processes (exact: no order).
  void max(std::span<double> values) const;

  // Every process's `mine` (counts[r] values from rank r), concatenated in
  // rank order into `all` (resized to the total), on every process.
  void all_gather(std::span<const double> mine, const std::vector<std::size_t>& counts, std::vector<double>& all) const;
  // The same into rank 0's `all` only (others' `all` is left alone).
  void gather_to_root(std::span<const double> mine, const std::vector<std::size_t>& counts,
                      std::vector<double>& all) const;
  // Point to point: send_counts[r] values of `send` (in rank order) to rank
  // r; recv_counts[r] values from rank r into `received` (resized), in rank
  // order. Both sides know the counts (no exchange of counts).
  void all_to_all(std::span<const double> send, const std::vector<std::size_t>& send_counts,
                  const std::vector<std::size_t>& recv_counts, std::vector<double>& received) const;
  // Each process's one count, as a vector of size() counts on every process.
  std::vector<std::size_t> all_counts(std::size_t mine) const;

  // Ends every process of the run at once (an error on one process would
  // leave the others waiting in their next exchange).
  [[noreturn]] void abort(int code) const;

 private:
  int rank_ = 0;
  int size_ = 1;
};

// Whether this build has MPI (SUFFUSE_MPI).
bool built_with_mpi();

}  // namespace suffuse::detail
