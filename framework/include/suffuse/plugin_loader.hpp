#pragma once
// Finds and loads plugin libraries into a Registry.
#include <filesystem>
#include <memory>
#include <set>
#include <string>
#include <vector>

#include "suffuse/plugin.hpp"

namespace suffuse {

struct LoadedLibrary {
  std::filesystem::path path;
  std::string framework_version;  // the SDK version it was built against
  int abi_major = 0, abi_minor = 0;
  std::vector<std::string> plugins;  // names it registered
};

class PluginLoader {
 public:
  explicit PluginLoader(Registry& registry) : registry_(registry) {}

  // Loads one library. Throws suffuse::Error naming the file and the reason:
  // the dlopen message, a missing entry point, another ABI major version, a
  // debug/release mismatch, or a library that registers nothing.
  // A file already loaded is skipped. Libraries are never unloaded.
  void load_library(const std::filesystem::path& file);
  // Loads every "*.so" file of a directory, in name order. A file that is not
  // a suffuse plugin at all (dlopen fails, or no entry point) is skipped with
  // a warning on stderr, kept in warnings(); a plugin library that fails a
  // check (ABI, build type, duplicate names) is still an error.
  void load_directory(const std::filesystem::path& dir);
  // A file is loaded, a directory is scanned; a missing path is an error.
  void load_path(const std::filesystem::path& path);

  // The paths searched after the scene's own: $SUFFUSE_PLUGIN_PATH (colon
  // separated), then the plugin directory next to the core library
  // (<libdir>/suffuse/plugins, which is also where the build tree puts them).
  static std::vector<std::filesystem::path> default_search_path();
  static std::filesystem::path bundled_plugin_directory();

  // A module of this build: a library beside the bundled plugins' directory
  // (<libdir>/suffuse/<file>) holding heavy libraries few runs need (PETSc,
  // VTK), loaded where first needed and never unloaded (their clean-up at
  // exit must find its code). It must export `version_entry`, a
  // `const char*()` returning this suffuse's version (its entries take this
  // build's types), and each of `entries`, whose addresses are returned in
  // that order (cast each back to its own type). Throws suffuse::Error
  // "cannot load the <what> <path> (why)".
  using ModuleEntry = void (*)();
  static std::vector<ModuleEntry> load_module(const std::string& file, const std::string& what,
                                        const std::string& version_entry, const std::vector<std::string>& entries);

  const std::vector<LoadedLibrary>& libraries() const { return libraries_; }
  // One message per file a directory scan skipped, naming the file and why.
  const std::vector<std::string>& warnings() const { return warnings_; }

 private:
  Registry& registry_;
  std::set<std::filesystem::path> loaded_;
  // Library handles (boost::dll::shared_library, type-erased to keep Boost out
  // of the SDK). They are opened with RTLD_NODELETE, so the code stays mapped
  // for the life of the process even after the loader is gone.
  std::vector<std::shared_ptr<void>> handles_;
  std::vector<LoadedLibrary> libraries_;
  std::vector<std::string> warnings_;
};

}  // namespace suffuse
