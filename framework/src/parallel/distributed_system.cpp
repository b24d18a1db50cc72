#include "parallel/distributed_system.hpp"

#include "suffuse/error.hpp"

#ifdef SUFFUSE_PETSC
#include <mutex>

#include "suffuse/plugin_loader.hpp"
#endif

namespace suffuse::detail {

#ifdef SUFFUSE_PETSC

namespace {

// The module is never unloaded (PluginLoader::load_module): PETSc, once
// started, is the process's (PetscInitialize's state is global), and its
// clean-up at exit must find its code.
struct PetscModule {
  std::mutex mutex;
  MakePetscSystem* make = nullptr;
  FinalizePetsc* finalize = nullptr;
};
PetscModule& petsc_module() {
  static PetscModule* module = new PetscModule;
  return *module;
}

}  // namespace

bool built_with_petsc() { return true; }

std::unique_ptr<DistributedSystem> make_distributed_system(const Communicator& comm, std::string name,
                                                           std::string prefix) {
  PetscModule& module = petsc_module();
  std::lock_guard lock(module.mutex);
  if (!module.make) {
    try {
      const auto at = PluginLoader::load_module("libsuffuse_petsc.so", "PETSc module", "suffuse_petsc_module_version",
                                                {"suffuse_make_petsc_system", "suffuse_finalize_petsc"});
      module.make = reinterpret_cast<MakePetscSystem*>(at[0]);
      module.finalize = reinterpret_cast<FinalizePetsc*>(at[1]);
    } catch (const Error& e) {
      throw Error(name + ": " + e.what() + "; reinstall suffuse, or run the scene on one process");
    }
  }
  return std::unique_ptr<DistributedSystem>(module.make(comm, name, prefix));
}

void finalize_distributed_systems() {
  PetscModule& module = petsc_module();
  std::lock_guard lock(module.mutex);
  if (module.finalize) module.finalize();
}

#else  // no PETSc: many processes run the explicit scheme only

bool built_with_petsc() { return false; }

std::unique_ptr<DistributedSystem> make_distributed_system(const Communicator&, std::string name, std::string) {
  throw Error(name + ": this build has no PETSc (install libpetsc-real-dev and rebuild; docs/parallel.md)");
}

void finalize_distributed_systems() {}

#endif

}  // namespace suffuse::detail
