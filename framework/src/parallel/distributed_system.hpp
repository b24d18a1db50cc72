#pragma once
// A sparse linear system over the processes of a run, solved by PETSc
// (docs/parallel.md, "Quasi-static runs"): what the quasi-static step's u-p
// system and its transport's backward-Euler step go through on many
// processes. One process keeps Eigen (quasi_static_linear.hpp), so serial
// runs and builds without PETSc are as before.
//
// PETSc lives in a module of its own, libsuffuse_petsc.so next to the
// bundled plugins' directory (petsc_system.cpp), loaded by the first
// system a run makes: PETSc and what it links (MUMPS, ScaLAPACK, HYPRE,
// Trilinos, HDF5; about 90 libraries and 25 MB resident) cost a run that
// never solves through it nothing, neither start-up time nor memory.
//
// Rows are split in contiguous ranges (rows()); every process may add to any
// entry, and the sums are PETSc's (MatSetValues with ADD_VALUES). The
// right-hand side is passed whole, the same on every process, and the whole
// solution comes back on every process: the quasi-static step keeps its
// nodal unknowns on every process (a grid's, not the points').
//
// The default solve is direct: LU by MUMPS, as robust as the serial
// factorisation on the u-p system's indefinite, badly scaled matrix. Any
// PETSc solver replaces it through PETSc's options with the system's prefix
// (suffuse_qs_, suffuse_transport_), on the command line of mpirun's
// processes or in PETSC_OPTIONS, e.g. GMRES preconditioned by a Schur
// complement split (the displacements and the pressures are given as the
// split's two fields):
//   PETSC_OPTIONS="-suffuse_qs_ksp_type fgmres -suffuse_qs_pc_type fieldsplit
//     -suffuse_qs_pc_fieldsplit_type schur ..."
#include <Eigen/SparseCore>
#include <cstddef>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "parallel/communicator.hpp"

namespace suffuse::detail {

// Whether this build solves on many processes (PETSc found with MPI).
bool built_with_petsc();

class DistributedSystem {
 public:
  using Entry = Eigen::Triplet<double>;
  virtual ~DistributedSystem() = default;

  // A new matrix of `size` equations (its pattern new), and the rows this
  // process holds, [first, last).
  virtual void start(std::size_t size) = 0;
  virtual std::pair<std::size_t, std::size_t> rows() const = 0;
  // The same pattern's entries anew (zeroed): the symbolic factorisation is kept.
  virtual void restart() = 0;
  // Adds entries (any rows); `per_row` bounds the entries of a row, for the
  // preallocation (more are allowed, at a cost).
  virtual void add(std::span<const Entry> entries, std::size_t per_row) = 0;
  // Ends the assembly. With `scaled`, scales rows and columns symmetrically
  // by 1 / sqrt(|diagonal|) (1 where it is zero), as the serial solve does:
  // its blocks differ by many orders of magnitude.
  virtual void finish(bool scaled) = 0;
  // The scaling of every equation, on every process (1 if not scaled).
  virtual const std::vector<double>& scale() const = 0;
  // The displacements are equations [0, split), the pressures [split, size):
  // the fields of a fieldsplit preconditioner, if the options choose one.
  virtual void set_fields(std::size_t split) = 0;
  // Solves the (unscaled) system for `rhs`, whole on every process; returns
  // the whole solution on every process, or throws with PETSc's reason.
  virtual void solve(std::span<const double> rhs, std::vector<double>& x) = 0;
  // The same by GMRES, preconditioned by the preconditioner of the pattern's
  // last solve() (its factors), as the serial solve reuses a step's factors
  // (quasi_static_linear.hpp): false, and x untouched, where there are none
  // or GMRES does not reach the serial solve's tolerances. Adds GMRES's
  // iterations to `iterations`.
  virtual bool solve_reusing_factors(std::span<const double> rhs, std::vector<double>& x, int& iterations) = 0;
};

// The PETSc module's entry points, found by name (petsc_system.cpp asserts
// its definitions have these types). A module of another build is refused:
// DistributedSystem's layout is this build's.
using MakePetscSystem = DistributedSystem*(const Communicator&, const std::string& name, const std::string& prefix);
using FinalizePetsc = void();
using PetscModuleVersion = const char*();

// A system of PETSc's, from the module (loaded on the first call). `name` for
// messages; `prefix` that of its PETSc options. Throws suffuse::Error in a
// build without PETSc, or if the module cannot be loaded (naming its path).
std::unique_ptr<DistributedSystem> make_distributed_system(const Communicator& comm, std::string name,
                                                           std::string prefix);

// Ends PETSc if a system started it (before MPI ends: ParallelProcesses).
void finalize_distributed_systems();

}  // namespace suffuse::detail
