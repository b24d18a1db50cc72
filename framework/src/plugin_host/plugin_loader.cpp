#include "suffuse/plugin_loader.hpp"

#include <dlfcn.h>

#include <algorithm>
#include <boost/dll/runtime_symbol_info.hpp>
#include <boost/dll/shared_library.hpp>
#include <cstdlib>
#include <cstring>
#include <iostream>
#include <memory>
#include <mutex>

#include "suffuse/error.hpp"
#include "suffuse/version.hpp"

namespace suffuse {

namespace fs = std::filesystem;

namespace {

// A file that is no suffuse plugin at all: not loadable, or without the entry
// point. A directory scan skips it; a library named explicitly is refused.
class NotAPluginError : public Error {
 public:
  using Error::Error;
};

}  // namespace

void PluginLoader::load_library(const fs::path& file) {
  std::error_code ec;
  fs::path canonical = fs::canonical(file, ec);
  if (ec) throw Error("plugin library " + file.string() + " does not exist");
  if (loaded_.count(canonical)) return;
  // Loaded into this registry already, by another loader: nothing to add.
  for (const auto& [name, info] : registry_.all())
    if (info.library == canonical.string()) return;

  // The library must stay loaded for the life of the process: plugin objects
  // and the registry's factories point into its code. RTLD_NODELETE keeps the
  // code mapped even after the handle is closed.
  std::shared_ptr<boost::dll::shared_library> library;
  try {
    const auto mode = static_cast<boost::dll::load_mode::type>(
        boost::dll::load_mode::rtld_now | boost::dll::load_mode::rtld_local | RTLD_NODELETE);
    library = std::make_shared<boost::dll::shared_library>(canonical.string(), mode);
  } catch (const std::exception& e) {
    const char* why = dlerror();  // boost keeps the dlerror text in its message as well
    throw NotAPluginError("cannot load plugin library " + canonical.string() + ": " + e.what() +
                          (why ? std::string(" (") + why + ")" : std::string()));
  }
  const char* symbol = "suffuse_plugin_entry";
  if (!library->has(symbol))
    throw NotAPluginError(canonical.string() + " is not a suffuse plugin: it exports no '" + symbol +
                          "' entry point (define one with SUFFUSE_PLUGIN_LIBRARY)");
  const PluginEntry* entry = library->get<const PluginEntry*()>(symbol)();
  if (entry == nullptr) throw Error(canonical.string() + ": its entry point returned no plugin description");
  if (entry->abi_major != abi_major)
    throw Error(canonical.string() + " was built for plugin ABI " + std::to_string(entry->abi_major) + "." +
                std::to_string(entry->abi_minor) + " but this suffuse (" + framework_version +
                ") has plugin ABI " + std::to_string(abi_major) + "." + std::to_string(abi_minor) +
                ": rebuild the plugin against this version");
  if (entry->abi_minor > abi_minor)
    throw Error(canonical.string() + " needs plugin ABI " + std::to_string(entry->abi_major) + "." +
                std::to_string(entry->abi_minor) + ", newer than this suffuse's " + std::to_string(abi_major) +
                "." + std::to_string(abi_minor) + ": upgrade suffuse");
  if (entry->build_type == nullptr || std::strcmp(entry->build_type, build_type) != 0)
    throw Error(canonical.string() + " is a " + (entry->build_type ? entry->build_type : "unknown") +
                " build but this suffuse is a " + build_type +
                " build: build the plugin with the same CMAKE_BUILD_TYPE (suffuse_add_plugin does)");
  if (entry->register_plugins == nullptr) throw Error(canonical.string() + ": no registration function");

  // Register into a staging table first, so that a library that throws or
  // clashes half-way leaves the registry as it was.
  Registry staging;
  staging.set_current_library(canonical.string());
  entry->register_plugins(staging);
  if (staging.all().empty())
    throw Error(canonical.string() + " is a suffuse plugin library but registered no plugin");
  for (const auto& [name, info] : staging.all()) {
    if (const PluginInfo* existing = registry_.find(name))
      throw Error("plugin '" + name + "' is registered twice: by " + existing->library + " and by " +
                  canonical.string());
  }
  registry_.set_current_library(canonical.string());
  for (const auto& [name, info] : staging.all()) registry_.add_info(info);
  registry_.set_current_library("");

  LoadedLibrary record;
  record.path = canonical;
  record.framework_version = entry->framework_version ? entry->framework_version : "";
  record.abi_major = entry->abi_major;
  record.abi_minor = entry->abi_minor;
  for (const auto& [name, info] : staging.all()) record.plugins.push_back(name);
  libraries_.push_back(std::move(record));
  loaded_.insert(canonical);
  handles_.push_back(std::move(library));
}

void PluginLoader::load_directory(const fs::path& dir) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(dir))
    if (entry.is_regular_file() && entry.path().extension() == ".so") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    try {
      load_library(f);
    } catch (const NotAPluginError& e) {
      warnings_.push_back("skipped a file in plugin directory " + dir.string() + ": " + e.what());
      std::cerr << "suffuse: warning: " << warnings_.back() << "\n";
    }
  }
}

void PluginLoader::load_path(const fs::path& path) {
  if (fs::is_directory(path)) {
    load_directory(path);
  } else if (fs::exists(path)) {
    load_library(path);
  } else {
    throw Error("plugin path " + path.string() + " does not exist");
  }
}

std::vector<PluginLoader::ModuleEntry> PluginLoader::load_module(const std::string& file, const std::string& what,
                                             const std::string& version_entry,
                                             const std::vector<std::string>& entries) {
  const fs::path path = bundled_plugin_directory().parent_path() / file;
  try {
    auto library = std::make_unique<boost::dll::shared_library>(path.string(), boost::dll::load_mode::rtld_now);
    const std::string version = library->get<const char*()>(version_entry)();
    if (version != framework_version)
      throw Error("it is suffuse " + version + "'s, this is suffuse " + framework_version);
    std::vector<ModuleEntry> addresses;
    for (const std::string& entry : entries) {
      if (!library->has(entry)) throw Error("it has no " + entry);
      addresses.push_back(&library->get<void()>(entry));
    }
    // Never unloaded; held where the leak checker sees it (the process keeps it).
    static std::mutex mutex;
    static auto* kept = new std::vector<std::unique_ptr<boost::dll::shared_library>>;
    const std::lock_guard lock(mutex);
    kept->push_back(std::move(library));
    return addresses;
  } catch (const std::exception& e) {
    throw Error("cannot load the " + what + " " + path.string() + " (" + e.what() + ")");
  }
}

fs::path PluginLoader::bundled_plugin_directory() {
  // The directory of the core library itself, found at run time, so an
  // installed tree can be moved and the build tree works without installing.
  const fs::path core = boost::dll::this_line_location().string();
  return core.parent_path() / "suffuse" / "plugins";
}

std::vector<fs::path> PluginLoader::default_search_path() {
  std::vector<fs::path> paths;
  if (const char* env = std::getenv("SUFFUSE_PLUGIN_PATH")) {
    std::string s = env;
    std::size_t start = 0;
    while (start <= s.size()) {
      std::size_t end = s.find(':', start);
      if (end == std::string::npos) end = s.size();
      if (end > start) paths.emplace_back(s.substr(start, end - start));
      start = end + 1;
    }
  }
  const fs::path bundled = bundled_plugin_directory();
  if (fs::is_directory(bundled)) paths.push_back(bundled);
  return paths;
}

}  // namespace suffuse
