#include "parallel/communicator.hpp"

#include <algorithm>
#include <climits>
#include <cstdio>
#include <cstdlib>
#include <string>

#include "suffuse/error.hpp"

#ifdef SUFFUSE_MPI
#include <mpi.h>
#endif

namespace suffuse::detail {

bool built_with_mpi() {
#ifdef SUFFUSE_MPI
  return true;
#else
  return false;
#endif
}

#ifdef SUFFUSE_MPI

namespace {
bool mpi_running() {
  int initialised = 0, finalised = 0;
  MPI_Initialized(&initialised);
  MPI_Finalized(&finalised);
  return initialised && !finalised;
}

// MPI counts are ints: a message of more values is refused, not truncated.
std::vector<int> int_counts(const std::vector<std::size_t>& counts, std::vector<int>& displacements) {
  std::vector<int> out(counts.size());
  displacements.assign(counts.size(), 0);
  std::size_t total = 0;
  for (std::size_t r = 0; r < counts.size(); ++r) {
    if (counts[r] > static_cast<std::size_t>(INT_MAX) || total > static_cast<std::size_t>(INT_MAX))
      throw Error("internal: an exchange of more than " + std::to_string(INT_MAX) + " values between processes");
    out[r] = static_cast<int>(counts[r]);
    displacements[r] = static_cast<int>(total);
    total += counts[r];
  }
  return out;
}
}  // namespace

Communicator::Communicator() {
  if (!mpi_running()) return;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
}

double Communicator::min(double local) const {
  if (!parallel()) return local;
  double out = local;
  MPI_Allreduce(&local, &out, 1, MPI_DOUBLE, MPI_MIN, MPI_COMM_WORLD);
  return out;
}

double Communicator::max(double local) const { return -min(-local); }

void Communicator::sum(std::span<double> values) const {
  if (!parallel()) return;
  // In slices: MPI counts are ints.
  constexpr std::size_t slice = std::size_t{1} << 26;
  for (std::size_t first = 0; first < values.size(); first += slice) {
    const int n = static_cast<int>(std::min(slice, values.size() - first));
    double* v = values.data() + first;
    MPI_Reduce(root() ? MPI_IN_PLACE : v, root() ? v : nullptr, n, MPI_DOUBLE, MPI_SUM, 0, MPI_COMM_WORLD);
    MPI_Bcast(v, n, MPI_DOUBLE, 0, MPI_COMM_WORLD);
  }
}

void Communicator::max(std::span<double> values) const {
  if (!parallel()) return;
  constexpr std::size_t slice = std::size_t{1} << 26;
  for (std::size_t first = 0; first < values.size(); first += slice) {
    const int n = static_cast<int>(std::min(slice, values.size() - first));
    MPI_Allreduce(MPI_IN_PLACE, values.data() + first, n, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  }
}

void Communicator::sum_below(std::span<double> values) const {
  if (!parallel()) {
    std::fill(values.begin(), values.end(), 0.0);
    return;
  }
  constexpr std::size_t slice = std::size_t{1} << 26;  // MPI counts are ints
  std::vector<double> mine;
  for (std::size_t first = 0; first < values.size(); first += slice) {
    const std::size_t n = std::min(slice, values.size() - first);
    mine.assign(values.begin() + static_cast<std::ptrdiff_t>(first),
                values.begin() + static_cast<std::ptrdiff_t>(first + n));
    MPI_Exscan(mine.data(), values.data() + first, static_cast<int>(n), MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    if (root()) std::fill(values.begin() + static_cast<std::ptrdiff_t>(first),
                          values.begin() + static_cast<std::ptrdiff_t>(first + n), 0.0);  // undefined there
  }
}

bool Communicator::any(bool local) const {
  if (!parallel()) return local;
  int mine = local ? 1 : 0, out = 0;
  MPI_Allreduce(&mine, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
  return out != 0;
}

std::vector<std::size_t> Communicator::all_counts(std::size_t mine) const {
  if (!parallel()) return {mine};
  std::vector<unsigned long long> all(static_cast<std::size_t>(size_));
  unsigned long long m = mine;
  MPI_Allgather(&m, 1, MPI_UNSIGNED_LONG_LONG, all.data(), 1, MPI_UNSIGNED_LONG_LONG, MPI_COMM_WORLD);
  return {all.begin(), all.end()};
}

void Communicator::all_gather(std::span<const double> mine, const std::vector<std::size_t>& counts,
                              std::vector<double>& all) const {
  std::size_t total = 0;
  for (std::size_t c : counts) total += c;
  all.resize(total);
  if (!parallel()) {
    std::copy(mine.begin(), mine.end(), all.begin());
    return;
  }
  std::vector<int> displacements;
  const std::vector<int> n = int_counts(counts, displacements);
  MPI_Allgatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, all.data(), n.data(), displacements.data(),
                 MPI_DOUBLE, MPI_COMM_WORLD);
}

void Communicator::all_to_all(std::span<const double> send, const std::vector<std::size_t>& send_counts,
                              const std::vector<std::size_t>& recv_counts, std::vector<double>& received) const {
  std::size_t total = 0;
  for (std::size_t c : recv_counts) total += c;
  received.resize(total);
  if (!parallel()) {
    std::copy(send.begin(), send.end(), received.begin());
    return;
  }
  std::vector<int> send_at, recv_at;
  const std::vector<int> ns = int_counts(send_counts, send_at), nr = int_counts(recv_counts, recv_at);
  MPI_Alltoallv(send.data(), ns.data(), send_at.data(), MPI_DOUBLE, received.data(), nr.data(), recv_at.data(),
                MPI_DOUBLE, MPI_COMM_WORLD);
}

void Communicator::gather_to_root(std::span<const double> mine, const std::vector<std::size_t>& counts,
                                  std::vector<double>& all) const {
  if (!parallel()) {
    all.assign(mine.begin(), mine.end());
    return;
  }
  std::vector<int> displacements;
  const std::vector<int> n = int_counts(counts, displacements);
  if (root()) {
    std::size_t total = 0;
    for (std::size_t c : counts) total += c;
    all.resize(total);
  }
  MPI_Gatherv(mine.data(), static_cast<int>(mine.size()), MPI_DOUBLE, root() ? all.data() : nullptr, n.data(),
              displacements.data(), MPI_DOUBLE, 0, MPI_COMM_WORLD);
}

void Communicator::abort(int code) const {
  if (parallel()) MPI_Abort(MPI_COMM_WORLD, code);
  std::exit(code);
}

#else  // one process

Communicator::Communicator() = default;
double Communicator::min(double local) const { return local; }
double Communicator::max(double local) const { return local; }
void Communicator::sum(std::span<double>) const {}
void Communicator::max(std::span<double>) const {}
void Communicator::sum_below(std::span<double> values) const { std::fill(values.begin(), values.end(), 0.0); }
bool Communicator::any(bool local) const { return local; }
std::vector<std::size_t> Communicator::all_counts(std::size_t mine) const { return {mine}; }
void Communicator::all_gather(std::span<const double> mine, const std::vector<std::size_t>&,
                              std::vector<double>& all) const {
  all.assign(mine.begin(), mine.end());
}
void Communicator::gather_to_root(std::span<const double> mine, const std::vector<std::size_t>&,
                                  std::vector<double>& all) const {
  all.assign(mine.begin(), mine.end());
}
void Communicator::all_to_all(std::span<const double> send, const std::vector<std::size_t>&,
                              const std::vector<std::size_t>&, std::vector<double>& received) const {
  received.assign(send.begin(), send.end());
}
void Communicator::abort(int code) const { std::exit(code); }

#endif

}  // namespace suffuse::detail

// ---------------------------------------------------------------------------

#include "parallel/distributed_system.hpp"
#include "suffuse/parallel.hpp"

namespace suffuse {

bool has_mpi() { return detail::built_with_mpi(); }

namespace {
// Set by the launchers of OpenMPI, MPICH (Hydra) and PMIx: a process started
// otherwise never starts MPI, so serial runs pay nothing for it.
bool launched_by_mpirun() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE", "PMIX_RANK"})
    if (std::getenv(name)) return true;
  return false;
}
}  // namespace

ParallelProcesses::ParallelProcesses(int& argc, char**& argv) {
#ifdef SUFFUSE_MPI
  if (!launched_by_mpirun()) return;
  // Only the thread that started MPI exchanges, outside OpenMP's regions.
  int provided = 0;
  MPI_Init_thread(&argc, &argv, MPI_THREAD_FUNNELED, &provided);
  started_ = true;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank_);
  MPI_Comm_size(MPI_COMM_WORLD, &size_);
#else
  (void)argc;
  (void)argv;
  // N copies of a serial run would write the same files at once.
  const char* size = std::getenv("OMPI_COMM_WORLD_SIZE");
  if (!size) size = std::getenv("PMI_SIZE");
  if (launched_by_mpirun() && size && std::atoi(size) > 1) {
    std::fprintf(stderr,
                 "suffuse: error: started by mpirun on %s processes, but this build has no MPI (install "
                 "libopenmpi-dev and rebuild; docs/parallel.md)\n",
                 size);
    std::exit(2);
  }
#endif
}

ParallelProcesses::~ParallelProcesses() {
#ifdef SUFFUSE_MPI
  detail::finalize_distributed_systems();  // PETSc ends within MPI
  if (started_) MPI_Finalize();
#endif
}

void ParallelProcesses::abort(int code) const {
#ifdef SUFFUSE_MPI
  if (started_ && size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
#endif
  std::exit(code);
}

}  // namespace suffuse
