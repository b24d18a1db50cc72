#pragma once
// A run on many processes (docs/parallel.md): `mpirun -np N suffuse run
// SCENE.json` runs the scene unchanged on N processes, equal bit for bit to
// the serial run. A program that runs scenes keeps one ParallelProcesses
// alive around them; started without mpirun (or built without MPI) it is
// one process and does nothing.
namespace suffuse {

class ParallelProcesses {
 public:
  // Starts MPI when the environment says mpirun (or another launcher)
  // started this process.
  ParallelProcesses(int& argc, char**& argv);
  ~ParallelProcesses();
  ParallelProcesses(const ParallelProcesses&) = delete;
  ParallelProcesses& operator=(const ParallelProcesses&) = delete;

  int rank() const { return rank_; }
  int size() const { return size_; }
  // Ends every process at once with `code` (after an error on one of them).
  [[noreturn]] void abort(int code) const;

 private:
  [[maybe_unused]] bool started_ = false;  // MPI started here (builds with MPI)
  int rank_ = 0, size_ = 1;
};

// Whether this build can run on many processes.
bool has_mpi();

}  // namespace suffuse
