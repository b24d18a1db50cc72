// The PETSc module (libsuffuse_petsc.so): DistributedSystem on PETSc's
// matrices and solvers (distributed_system.hpp). Only this file includes
// PETSc; the core loads the module when a run first needs a system, so runs
// that never solve through PETSc never load it.
#include <petscksp.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <exception>

#include "distributed_system.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {
namespace {

// PETSc's error codes as exceptions (its handler only returns them: PETSc
// prints nothing, the run's error says what failed).
void check(PetscErrorCode code, const std::string& system, const char* what) {
  if (code == 0) return;
  const char* text = nullptr;
  PetscErrorMessage(code, &text, nullptr);
  throw Error(system + ": PETSc failed in " + what + " (" + (text ? text : "error " + std::to_string(code)) + ")");
}

// PETSc starts on the first system, inside the run's MPI, without its signal
// handlers (a crash is reported by the run, not by PETSc).
void start_petsc() {
  PetscBool started = PETSC_FALSE;
  PetscInitialized(&started);
  if (started) return;
  static char program[] = "suffuse", no_handler[] = "-no_signal_handler";
  static char* arguments[] = {program, no_handler, nullptr};
  int argc = 2;
  char** argv = arguments;
  if (PetscInitialize(&argc, &argv, nullptr, nullptr) != 0)
    throw Error("PETSc could not start (PetscInitialize failed)");
  PetscPushErrorHandler(PetscReturnErrorHandler, nullptr);
}

class PetscSystem final : public DistributedSystem {
 public:
  PetscSystem(const Communicator& comm, std::string name, std::string prefix)
      : comm_(comm), name_(std::move(name)), prefix_(std::move(prefix)) {
    start_petsc();
  }
  ~PetscSystem() override;
  PetscSystem(const PetscSystem&) = delete;
  PetscSystem& operator=(const PetscSystem&) = delete;

  void start(std::size_t size) override;
  std::pair<std::size_t, std::size_t> rows() const override { return rows_; }
  void restart() override;
  void add(std::span<const Entry> entries, std::size_t per_row) override;
  void finish(bool scaled) override;
  const std::vector<double>& scale() const override { return scale_; }
  void set_fields(std::size_t split) override { split_ = split; }
  void solve(std::span<const double> rhs, std::vector<double>& x) override;

 private:
  struct Petsc {  // PETSc's objects
    Mat matrix = nullptr;
    KSP ksp = nullptr;
    Vec rhs = nullptr, x = nullptr, whole = nullptr, diagonal = nullptr;
    VecScatter to_all = nullptr;
    IS fields[2] = {nullptr, nullptr};
    void clear() {
      if (matrix) MatDestroy(&matrix);
      if (ksp) KSPDestroy(&ksp);
      for (Vec* v : {&rhs, &x, &whole, &diagonal})
        if (*v) VecDestroy(v);
      if (to_all) VecScatterDestroy(&to_all);
      for (IS& f : fields)
        if (f) ISDestroy(&f);
    }
  };
  const Communicator& comm_;
  std::string name_, prefix_;
  Petsc petsc_;
  std::pair<std::size_t, std::size_t> rows_{0, 0};
  std::size_t size_ = 0, split_ = 0;
  std::vector<double> scale_;
};

PetscSystem::~PetscSystem() {
  // Destroying PETSc's objects is collective: a process unwinding from an
  // error (on its own) leaves them, as it is about to end every process.
  PetscBool finished = PETSC_FALSE;
  PetscFinalized(&finished);
  if (!finished && std::uncaught_exceptions() == 0) petsc_.clear();
}

void PetscSystem::start(std::size_t size) {
  if (size > static_cast<std::size_t>(INT_MAX))
    throw Error(name_ + ": " + std::to_string(size) + " equations, more than this PETSc build indexes (32-bit)");
  Petsc& p = petsc_;
  p.clear();
  size_ = size;
  scale_.clear();
  if (size == 0) return;  // nothing to solve (every unknown prescribed): PETSc is not asked
  const auto ranks = static_cast<std::size_t>(comm_.size()), rank = static_cast<std::size_t>(comm_.rank());
  rows_ = {size * rank / ranks, size * (rank + 1) / ranks};
  const auto local = static_cast<PetscInt>(rows_.second - rows_.first), n = static_cast<PetscInt>(size);
  check(MatCreate(PETSC_COMM_WORLD, &p.matrix), name_, "MatCreate");
  check(MatSetSizes(p.matrix, local, local, n, n), name_, "MatSetSizes");
  check(MatSetType(p.matrix, MATAIJ), name_, "MatSetType");
  check(MatCreateVecs(p.matrix, &p.x, &p.rhs), name_, "MatCreateVecs");
  check(VecDuplicate(p.x, &p.diagonal), name_, "VecDuplicate");
  check(VecScatterCreateToAll(p.x, &p.to_all, &p.whole), name_, "VecScatterCreateToAll");
  scale_.assign(size, 1.0);
}

void PetscSystem::restart() {
  if (size_ > 0) check(MatZeroEntries(petsc_.matrix), name_, "MatZeroEntries");
}

void PetscSystem::add(std::span<const Entry> entries, std::size_t per_row) {
  if (size_ == 0) return;
  Petsc& p = petsc_;
  PetscBool assembled = PETSC_FALSE;
  MatAssembled(p.matrix, &assembled);
  if (!assembled) {  // the first assembly of this pattern: preallocate
    const auto local = static_cast<PetscInt>(rows_.second - rows_.first), n = static_cast<PetscInt>(size_);
    const auto bound = static_cast<PetscInt>(per_row);
    check(MatSeqAIJSetPreallocation(p.matrix, std::min(bound, n), nullptr), name_, "preallocation");
    check(MatMPIAIJSetPreallocation(p.matrix, std::min(bound, local), nullptr, std::min(bound, n - local), nullptr),
          name_, "preallocation");
    // Entries beyond the bound are allowed (slower), not an error.
    check(MatSetOption(p.matrix, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_FALSE), name_, "MatSetOption");
  }
  // One call per run of entries in the same row.
  std::vector<PetscInt> columns;
  std::vector<PetscScalar> values;
  for (std::size_t k = 0; k < entries.size();) {
    const PetscInt row = entries[k].row();
    columns.clear(), values.clear();
    for (; k < entries.size() && entries[k].row() == row; ++k) {
      columns.push_back(entries[k].col());
      values.push_back(entries[k].value());
    }
    check(MatSetValues(p.matrix, 1, &row, static_cast<PetscInt>(columns.size()), columns.data(), values.data(),
                       ADD_VALUES),
          name_, "MatSetValues");
  }
}

void PetscSystem::finish(bool scaled) {
  if (size_ == 0) return;
  Petsc& p = petsc_;
  check(MatAssemblyBegin(p.matrix, MAT_FINAL_ASSEMBLY), name_, "MatAssemblyBegin");
  check(MatAssemblyEnd(p.matrix, MAT_FINAL_ASSEMBLY), name_, "MatAssemblyEnd");
  if (scaled) {
    check(MatGetDiagonal(p.matrix, p.diagonal), name_, "MatGetDiagonal");
    PetscScalar* d = nullptr;
    check(VecGetArray(p.diagonal, &d), name_, "VecGetArray");
    for (std::size_t i = 0; i < rows_.second - rows_.first; ++i) d[i] = d[i] != 0 ? 1 / std::sqrt(std::abs(d[i])) : 1.0;
    check(VecRestoreArray(p.diagonal, &d), name_, "VecRestoreArray");
    check(MatDiagonalScale(p.matrix, p.diagonal, p.diagonal), name_, "MatDiagonalScale");
    check(VecScatterBegin(p.to_all, p.diagonal, p.whole, INSERT_VALUES, SCATTER_FORWARD), name_, "VecScatterBegin");
    check(VecScatterEnd(p.to_all, p.diagonal, p.whole, INSERT_VALUES, SCATTER_FORWARD), name_, "VecScatterEnd");
    const PetscScalar* all = nullptr;
    check(VecGetArrayRead(p.whole, &all), name_, "VecGetArrayRead");
    std::copy(all, all + size_, scale_.begin());
    check(VecRestoreArrayRead(p.whole, &all), name_, "VecRestoreArrayRead");
  } else {
    std::fill(scale_.begin(), scale_.end(), 1.0);
  }
  if (!p.ksp) {  // a new pattern: a new solver (its fields and symbolic factorisation)
    check(KSPCreate(PETSC_COMM_WORLD, &p.ksp), name_, "KSPCreate");
    check(KSPSetOperators(p.ksp, p.matrix, p.matrix), name_, "KSPSetOperators");
    check(KSPSetType(p.ksp, KSPPREONLY), name_, "KSPSetType");
    PC pc = nullptr;
    check(KSPGetPC(p.ksp, &pc), name_, "KSPGetPC");
    check(PCSetType(pc, PCLU), name_, "PCSetType");
    check(PCFactorSetMatSolverType(pc, MATSOLVERMUMPS), name_, "PCFactorSetMatSolverType");
    check(KSPSetOptionsPrefix(p.ksp, prefix_.c_str()), name_, "KSPSetOptionsPrefix");
    check(KSPSetFromOptions(p.ksp), name_, "KSPSetFromOptions");
    PetscBool split = PETSC_FALSE;
    check(PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &split), name_, "PCType");
    if (split) {
      const std::size_t bounds[3] = {0, std::clamp(split_, rows_.first, rows_.second), size_};
      for (int f = 0; f < 2; ++f) {
        const std::size_t first = std::max(bounds[f], rows_.first), last = std::min(bounds[f + 1], rows_.second);
        check(ISCreateStride(PETSC_COMM_WORLD, static_cast<PetscInt>(last > first ? last - first : 0),
                             static_cast<PetscInt>(first), 1, &p.fields[f]),
              name_, "ISCreateStride");
        check(PCFieldSplitSetIS(pc, f == 0 ? "u" : "p", p.fields[f]), name_, "PCFieldSplitSetIS");
      }
    }
  } else {  // the same pattern, new values: only the numeric factorisation again
    check(KSPSetOperators(p.ksp, p.matrix, p.matrix), name_, "KSPSetOperators");
  }
}

void PetscSystem::solve(std::span<const double> rhs, std::vector<double>& x) {
  x.resize(size_);
  if (size_ == 0) return;
  Petsc& p = petsc_;
  PetscScalar* b = nullptr;
  check(VecGetArray(p.rhs, &b), name_, "VecGetArray");
  for (std::size_t i = rows_.first; i < rows_.second; ++i) b[i - rows_.first] = scale_[i] * rhs[i];
  check(VecRestoreArray(p.rhs, &b), name_, "VecRestoreArray");
  check(KSPSolve(p.ksp, p.rhs, p.x), name_, "KSPSolve");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(p.ksp, &reason), name_, "KSPGetConvergedReason");
  if (reason < 0) {
    const char* text = nullptr;
    KSPGetConvergedReasonString(p.ksp, &text);
    throw Error(name_ + ": PETSc's solver did not converge (" + (text ? text : std::to_string(reason)) +
                "; its options have the prefix -" + prefix_ + ")");
  }
  check(VecScatterBegin(p.to_all, p.x, p.whole, INSERT_VALUES, SCATTER_FORWARD), name_, "VecScatterBegin");
  check(VecScatterEnd(p.to_all, p.x, p.whole, INSERT_VALUES, SCATTER_FORWARD), name_, "VecScatterEnd");
  const PetscScalar* all = nullptr;
  check(VecGetArrayRead(p.whole, &all), name_, "VecGetArrayRead");
  x.resize(size_);
  for (std::size_t i = 0; i < size_; ++i) x[i] = scale_[i] * all[i];
  check(VecRestoreArrayRead(p.whole, &all), name_, "VecRestoreArrayRead");
}

}  // namespace
}  // namespace suffuse::detail

// The module's entry points, found by name (distributed_system.cpp).
extern "C" suffuse::detail::DistributedSystem* suffuse_make_petsc_system(const suffuse::detail::Communicator& comm,
                                                                        const std::string& name,
                                                                        const std::string& prefix) {
  return new suffuse::detail::PetscSystem(comm, name, prefix);
}

extern "C" void suffuse_finalize_petsc() {
  PetscBool started = PETSC_FALSE, finished = PETSC_FALSE;
  PetscInitialized(&started);
  PetscFinalized(&finished);
  if (started && !finished) PetscFinalize();
}
