#include "distributed_system.hpp"

#include "suffuse/error.hpp"

#ifdef SUFFUSE_PETSC
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#endif

namespace suffuse::detail {

#ifdef SUFFUSE_PETSC

// What the module exports (petsc_system.cpp).
using MakeSystem = DistributedSystem*(const Communicator&, const std::string&, const std::string&);
using FinalizePetsc = void();

namespace {

// The module is never unloaded: PETSc, once started, is the process's
// (PetscInitialize's state is global), and its clean-up at exit must find
// its code.
struct PetscModule {
  std::mutex mutex;
  std::optional<boost::dll::shared_library> library;
};
PetscModule& petsc_module() {
  static PetscModule* module = new PetscModule;
  return *module;
}

// Next to the bundled plugins (<libdir>/suffuse), found from the core's own
// location as they are, so a build tree and a moved install both work.
std::filesystem::path petsc_module_path() {
  const std::filesystem::path core = boost::dll::this_line_location().string();
  return core.parent_path() / "suffuse" / "libsuffuse_petsc.so";
}

}  // namespace

bool built_with_petsc() { return true; }

std::unique_ptr<DistributedSystem> make_distributed_system(const Communicator& comm, std::string name,
                                                           std::string prefix) {
  PetscModule& module = petsc_module();
  std::lock_guard lock(module.mutex);
  if (!module.library) {
    const auto path = petsc_module_path();
    try {
      module.library.emplace(path.string(), boost::dll::load_mode::rtld_now);
    } catch (const std::exception& e) {
      throw Error(name + ": cannot load PETSc's module " + path.string() + " (" + e.what() +
                  "); reinstall suffuse, or run the scene on one process");
    }
  }
  return std::unique_ptr<DistributedSystem>(
      module.library->get<MakeSystem>("suffuse_make_petsc_system")(comm, name, prefix));
}

void finalize_distributed_systems() {
  PetscModule& module = petsc_module();
  std::lock_guard lock(module.mutex);
  if (module.library) module.library->get<FinalizePetsc>("suffuse_finalize_petsc")();
}

#else  // no PETSc: many processes run the explicit scheme only

bool built_with_petsc() { return false; }

std::unique_ptr<DistributedSystem> make_distributed_system(const Communicator&, std::string name, std::string) {
  throw Error(name + ": this build has no PETSc (install libpetsc-real-dev and rebuild; docs/parallel.md)");
}

void finalize_distributed_systems() {}

#endif

}  // namespace suffuse::detail
