#include "distributed_system.hpp"

#include "suffuse/error.hpp"
#include "suffuse/version.hpp"

#ifdef SUFFUSE_PETSC
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <exception>
#include <filesystem>
#include <mutex>
#include <optional>
#include <utility>
#endif

namespace suffuse::detail {

#ifdef SUFFUSE_PETSC

namespace {

// The module is never unloaded: PETSc, once started, is the process's
// (PetscInitialize's state is global), and its clean-up at exit must find
// its code.
struct PetscModule {
  std::mutex mutex;
  std::optional<boost::dll::shared_library> library;
  MakePetscSystem* make = nullptr;
  FinalizePetsc* finalize = nullptr;
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
      boost::dll::shared_library library(path.string(), boost::dll::load_mode::rtld_now);
      const std::string version = library.get<PetscModuleVersion>("suffuse_petsc_module_version")();
      if (version != framework_version)
        throw Error("it is suffuse " + version + "'s, this is suffuse " + framework_version);
      module.make = &library.get<MakePetscSystem>("suffuse_make_petsc_system");
      module.finalize = &library.get<FinalizePetsc>("suffuse_finalize_petsc");
      module.library.emplace(std::move(library));
    } catch (const std::exception& e) {
      module.make = nullptr, module.finalize = nullptr;
      throw Error(name + ": cannot load PETSc's module " + path.string() + " (" + e.what() +
                  "); reinstall suffuse, or run the scene on one process");
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
