// The PETSc module (libsuffuse_petsc.so): DistributedSystem on PETSc's
// matrices and solvers (distributed_system.hpp). Only this file includes
// PETSc; the core loads the module when a run first needs a system, so runs
// that never solve through PETSc never load it.
#include <petscksp.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <cstdio>
#include <exception>

#include <type_traits>

#include "parallel/distributed_system.hpp"
#include "suffuse/error.hpp"
#include "suffuse/version.hpp"

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
  bool solve_reusing_factors(std::span<const double> rhs, std::vector<double>& x, int& iterations) override;

 private:
  // The right-hand side, scaled, into p.rhs; the solution p.x, unscaled,
  // whole into x.
  void set_rhs(std::span<const double> rhs);
  void gather_solution(std::vector<double>& x);
  // The reused factors' preconditioner (PCSHELL): (S0/S) P0 (S0/S), with P0
  // the solver's preconditioner as last set up and S0 its matrix's scaling.
  static PetscErrorCode apply_reused(PC shell, Vec in, Vec out);

  struct Petsc {  // PETSc's objects
    Mat matrix = nullptr;
    KSP ksp = nullptr;
    // GMRES on the reused factors, and the scaling of their matrix over
    // that of the current one (S0/S), a work vector.
    KSP reuse = nullptr;
    Vec rhs = nullptr, x = nullptr, whole = nullptr, diagonal = nullptr;
    Vec factor_diagonal = nullptr, ratio = nullptr, work = nullptr, residual = nullptr;
    VecScatter to_all = nullptr;
    IS fields[2] = {nullptr, nullptr};
    void clear() {
      if (matrix) MatDestroy(&matrix);
      if (ksp) KSPDestroy(&ksp);
      if (reuse) KSPDestroy(&reuse);
      for (Vec* v : {&rhs, &x, &whole, &diagonal, &factor_diagonal, &ratio, &work, &residual})
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
  bool has_factors_ = false;  // the solver's preconditioner was set up on this pattern
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
  has_factors_ = false;
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
  for (Vec* v : {&p.diagonal, &p.factor_diagonal, &p.ratio, &p.work, &p.residual})
    check(VecDuplicate(p.x, v), name_, "VecDuplicate");
  check(VecSet(p.diagonal, 1.0), name_, "VecSet");
  has_factors_ = false;
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
    check(VecSet(p.diagonal, 1.0), name_, "VecSet");
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

void PetscSystem::set_rhs(std::span<const double> rhs) {
  PetscScalar* b = nullptr;
  check(VecGetArray(petsc_.rhs, &b), name_, "VecGetArray");
  for (std::size_t i = rows_.first; i < rows_.second; ++i) b[i - rows_.first] = scale_[i] * rhs[i];
  check(VecRestoreArray(petsc_.rhs, &b), name_, "VecRestoreArray");
}

void PetscSystem::gather_solution(std::vector<double>& x) {
  Petsc& p = petsc_;
  check(VecScatterBegin(p.to_all, p.x, p.whole, INSERT_VALUES, SCATTER_FORWARD), name_, "VecScatterBegin");
  check(VecScatterEnd(p.to_all, p.x, p.whole, INSERT_VALUES, SCATTER_FORWARD), name_, "VecScatterEnd");
  const PetscScalar* all = nullptr;
  check(VecGetArrayRead(p.whole, &all), name_, "VecGetArrayRead");
  x.resize(size_);
  for (std::size_t i = 0; i < size_; ++i) x[i] = scale_[i] * all[i];
  check(VecRestoreArrayRead(p.whole, &all), name_, "VecRestoreArrayRead");
}

void PetscSystem::solve(std::span<const double> rhs, std::vector<double>& x) {
  x.resize(size_);
  if (size_ == 0) return;
  Petsc& p = petsc_;
  set_rhs(rhs);
  PC pc = nullptr;
  check(KSPGetPC(p.ksp, &pc), name_, "KSPGetPC");
  check(PCSetReusePreconditioner(pc, PETSC_FALSE), name_, "PCSetReusePreconditioner");  // factorise anew
  has_factors_ = false;
  check(KSPSolve(p.ksp, p.rhs, p.x), name_, "KSPSolve");
  KSPConvergedReason reason;
  check(KSPGetConvergedReason(p.ksp, &reason), name_, "KSPGetConvergedReason");
  if (reason < 0) {
    const char* text = nullptr;
    KSPGetConvergedReasonString(p.ksp, &text);
    throw Error(name_ + ": PETSc's solver did not converge (" + (text ? text : std::to_string(reason)) +
                "; its options have the prefix -" + prefix_ + ")");
  }
  // MUMPS factorises a singular system whose pivots round-off left small
  // rather than zero (a mechanism: the strip load past its limit) and
  // returns a solution of the size of their inverse, where Eigen's
  // factorisation reports the zero pivot. A solution that does not solve
  // the system is refused: the strip's singular system left 1.6e-6 of the
  // right-hand side, its solves before 1e-15 to 3e-10, the flood levee's
  // 1e-14 at most.
  PetscReal b_norm = 0, r_norm = 0;
  check(MatMult(p.matrix, p.x, p.residual), name_, "MatMult");
  check(VecAYPX(p.residual, -1.0, p.rhs), name_, "VecAYPX");
  check(VecNorm(p.rhs, NORM_2, &b_norm), name_, "VecNorm");
  check(VecNorm(p.residual, NORM_2, &r_norm), name_, "VecNorm");
  if (!(r_norm <= 1e-8 * b_norm)) {
    char ratio[32];
    std::snprintf(ratio, sizeof ratio, "%.2g", r_norm / b_norm);
    throw Error(name_ + ": the factorised system's solution leaves a residual of " + ratio +
                " of the right-hand side");
  }
  check(VecCopy(p.diagonal, p.factor_diagonal), name_, "VecCopy");
  has_factors_ = true;
  gather_solution(x);
}

PetscErrorCode PetscSystem::apply_reused(PC shell, Vec in, Vec out) {
  void* context = nullptr;
  PetscCall(PCShellGetContext(shell, &context));
  Petsc& p = static_cast<PetscSystem*>(context)->petsc_;
  PC factors = nullptr;
  PetscCall(KSPGetPC(p.ksp, &factors));
  PetscCall(VecPointwiseMult(p.work, p.ratio, in));
  PetscCall(PCApply(factors, p.work, out));
  PetscCall(VecPointwiseMult(out, p.ratio, out));
  return 0;
}

// The serial solve's counterpart (quasi_static_linear.hpp,
// solve_reusing_factors): GMRES to a relative 1e-6 in at most 30 iterations,
// preconditioned by the factors of the step's last factorised matrix, and
// refused where the true residual is above 1e-5 of the right-hand side. The
// solver's preconditioner (MUMPS's LU, or whatever the options chose) is
// applied as it was last set up: PCSetReusePreconditioner keeps PETSc from
// setting it up again for the matrix it now holds. A factorisation (LU,
// Cholesky) is then one fixed operator; other preconditioners may read the
// current matrix or iterate when applied (SOR, multigrid smoothers, a
// fieldsplit with Krylov sub-solves), which the flexible GMRES allows.
bool PetscSystem::solve_reusing_factors(std::span<const double> rhs, std::vector<double>& x, int& iterations) {
  if (size_ == 0 || !has_factors_) return false;
  Petsc& p = petsc_;
  PC factors = nullptr;
  check(KSPGetPC(p.ksp, &factors), name_, "KSPGetPC");
  if (!p.reuse) {
    PetscBool factorisation = PETSC_FALSE;
    check(PetscObjectTypeCompareAny(reinterpret_cast<PetscObject>(factors), &factorisation, PCLU, PCCHOLESKY, ""),
          name_, "PCType");
    check(KSPCreate(PETSC_COMM_WORLD, &p.reuse), name_, "KSPCreate");
    check(KSPSetType(p.reuse, factorisation ? KSPGMRES : KSPFGMRES), name_, "KSPSetType");
    check(KSPGMRESSetRestart(p.reuse, 30), name_, "KSPGMRESSetRestart");
    check(KSPSetTolerances(p.reuse, 1e-6, 0.0, PETSC_DEFAULT, 30), name_, "KSPSetTolerances");
    PC shell = nullptr;
    check(KSPGetPC(p.reuse, &shell), name_, "KSPGetPC");
    check(PCSetType(shell, PCSHELL), name_, "PCSetType");
    check(PCShellSetContext(shell, this), name_, "PCShellSetContext");
    check(PCShellSetApply(shell, &PetscSystem::apply_reused), name_, "PCShellSetApply");
  }
  check(KSPSetOperators(p.reuse, p.matrix, p.matrix), name_, "KSPSetOperators");
  check(VecPointwiseDivide(p.ratio, p.factor_diagonal, p.diagonal), name_, "VecPointwiseDivide");
  check(PCSetReusePreconditioner(factors, PETSC_TRUE), name_, "PCSetReusePreconditioner");
  set_rhs(rhs);
  const PetscErrorCode solved = KSPSolve(p.reuse, p.rhs, p.x);
  check(PCSetReusePreconditioner(factors, PETSC_FALSE), name_, "PCSetReusePreconditioner");
  check(solved, name_, "KSPSolve");
  PetscInt its = 0;
  KSPConvergedReason reason;
  check(KSPGetIterationNumber(p.reuse, &its), name_, "KSPGetIterationNumber");
  check(KSPGetConvergedReason(p.reuse, &reason), name_, "KSPGetConvergedReason");
  iterations += static_cast<int>(its);
  if (reason <= 0) return false;
  // GMRES measured the preconditioned residual: the true one is checked.
  PetscReal b_norm = 0, r_norm = 0;
  check(MatMult(p.matrix, p.x, p.residual), name_, "MatMult");
  check(VecAYPX(p.residual, -1.0, p.rhs), name_, "VecAYPX");
  check(VecNorm(p.rhs, NORM_2, &b_norm), name_, "VecNorm");
  check(VecNorm(p.residual, NORM_2, &r_norm), name_, "VecNorm");
  if (!(r_norm <= 1e-5 * b_norm)) return false;
  gather_solution(x);
  return true;
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

extern "C" const char* suffuse_petsc_module_version() { return suffuse::framework_version; }

static_assert(std::is_same_v<decltype(suffuse_make_petsc_system), suffuse::detail::MakePetscSystem>);
static_assert(std::is_same_v<decltype(suffuse_finalize_petsc), suffuse::detail::FinalizePetsc>);
static_assert(std::is_same_v<decltype(suffuse_petsc_module_version), suffuse::detail::PetscModuleVersion>);
