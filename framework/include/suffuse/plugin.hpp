#pragma once
// The plugin SDK entry: how a shared library registers its plugins.
//
//   #include <suffuse/plugin.hpp>
//   class MyLaw : public suffuse::ErosionLaw {
//    public:
//     static suffuse::ParameterSchema schema();          // declares the parameters
//     // optional: problems involving several parameters, reported with the scene's errors
//     static std::vector<suffuse::ParameterIssue> check(const suffuse::Parameters&, int dim);
//     // optional: point fields of other parts it reads (phases), checked at validation
//     static std::vector<std::string> required_fields(const suffuse::Parameters&, int dim);
//     // optional, phases: wraps the phase given under "base" (PluginArgs::base)
//     static constexpr bool wraps_base_phase = true;
//     explicit MyLaw(const suffuse::PluginArgs& args);   // reads them once
//     void rate(const suffuse::ErosionBatch&) const override;
//   };
//   SUFFUSE_PLUGIN_LIBRARY(registry) {
//     registry.add<suffuse::ErosionLaw, MyLaw>("erosion/my_law", "One-line description.");
//   }
//
// A library may register any number of plugins of any kinds.
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "suffuse/boundary_condition.hpp"
#include "suffuse/erosion_law.hpp"
#include "suffuse/liquid.hpp"
#include "suffuse/parameters.hpp"
#include "suffuse/phase.hpp"
#include "suffuse/shape_function.hpp"
#include "suffuse/version.hpp"
#include "suffuse/writer.hpp"

namespace suffuse {

// Every kind of plugin, in one list: interface class and the name used in
// messages and docs. The enum, the names and the class-to-kind mapping below
// are generated from it, so a new kind is one line here (and its interface
// header above). Append new kinds at the end: the enum values are part of the
// plugin ABI.
#define SUFFUSE_PLUGIN_KINDS(X)                \
  X(ShapeFunction, "shape function")          \
  X(Phase, "phase")                           \
  X(Liquid, "liquid")                         \
  X(PermeabilityLaw, "permeability law")      \
  X(ErosionLaw, "erosion law")                \
  X(BoundaryCondition, "boundary condition")  \
  X(Writer, "writer")

#define SUFFUSE_KIND_ENUM(type, name) type,
enum class PluginKind { SUFFUSE_PLUGIN_KINDS(SUFFUSE_KIND_ENUM) };
#undef SUFFUSE_KIND_ENUM

#define SUFFUSE_KIND_VALUE(type, name) PluginKind::type,
inline constexpr PluginKind all_plugin_kinds[] = {SUFFUSE_PLUGIN_KINDS(SUFFUSE_KIND_VALUE)};
#undef SUFFUSE_KIND_VALUE

std::string to_string(PluginKind kind);

template <class T> struct KindOf;
#define SUFFUSE_KIND_OF(type, name) \
  template <> struct KindOf<type> { static constexpr PluginKind value = PluginKind::type; };
SUFFUSE_PLUGIN_KINDS(SUFFUSE_KIND_OF)
#undef SUFFUSE_KIND_OF

// A problem that involves several parameters of one node, found by a
// plugin's optional static check(). `key` names the parameter to point at
// ("" for the node itself).
struct ParameterIssue {
  std::string key;
  std::string problem;
  std::string expected;
  std::string found;
};

// What a plugin's constructor receives.
struct PluginArgs {
  const Parameters& params;   // validated, defaults filled in
  int dim;                    // 2 or 3
  std::string instance;       // JSON pointer of the scene node, for messages
  // A phase that wraps another (static constexpr bool wraps_base_phase =
  // true): the base phase of the scene node's "base", built and owned by the
  // core, which registers the base's fields just before the wrapper's
  // add_fields(). Null for every other plugin.
  const Phase* base = nullptr;
};

struct PluginInfo {
  PluginKind kind;
  std::string name;         // e.g. "phase/linear_elastic"
  std::string description;  // one line
  std::function<ParameterSchema()> schema;
  // Returns a pointer to the kind's interface (ShapeFunction*, Phase*, ...),
  // owned by the caller. Use Registry::create<Kind>() rather than this.
  std::function<void*(const PluginArgs&)> factory;
  // Optional cross-parameter check, run during scene validation after the
  // schema checks passed, before anything is constructed.
  std::function<std::vector<ParameterIssue>(const Parameters&, int dim)> check;
  // Optional: names of the per-point fields of other parts the plugin reads
  // (e.g. "eroded_fraction"). A scene that provides none of that name is
  // refused at validation, naming the field.
  std::function<std::vector<std::string>(const Parameters&, int dim)> required_fields;
  // A phase that wraps a base phase, given in its scene node under "base".
  bool wraps_phase = false;
  std::string library;  // file the plugin was loaded from (set by the loader)
};

class Registry {
 public:
  template <class Kind, class Impl>
  void add(std::string name, std::string description) {
    static_assert(std::is_base_of_v<Kind, Impl>, "plugin class must derive from its kind");
    PluginInfo info;
    info.kind = KindOf<Kind>::value;
    info.name = std::move(name);
    info.description = std::move(description);
    info.schema = &Impl::schema;
    info.factory = [](const PluginArgs& args) -> void* {
      return static_cast<Kind*>(new Impl(args));
    };
    // A plugin may declare `static std::vector<ParameterIssue> check(const Parameters&, int dim)`.
    if constexpr (requires(const Parameters& p) { Impl::check(p, 2); }) info.check = &Impl::check;
    // ... and `static std::vector<std::string> required_fields(const Parameters&, int dim)`.
    if constexpr (requires(const Parameters& p) { Impl::required_fields(p, 2); })
      info.required_fields = &Impl::required_fields;
    // ... and `static constexpr bool wraps_base_phase = true` (phases only).
    if constexpr (requires { Impl::wraps_base_phase; }) info.wraps_phase = Impl::wraps_base_phase;
    add_info(std::move(info));
  }

  // Throws suffuse::Error on a duplicate name, naming both libraries.
  void add_info(PluginInfo info);

  const PluginInfo* find(const std::string& name) const;
  const std::map<std::string, PluginInfo>& all() const { return plugins_; }
  std::vector<std::string> names_of(PluginKind kind) const;

  template <class Kind>
  std::unique_ptr<Kind> create(const std::string& name, const PluginArgs& args) const {
    const PluginInfo& info = checked(name, KindOf<Kind>::value);
    return std::unique_ptr<Kind>(static_cast<Kind*>(info.factory(args)));
  }

  // Library being loaded; recorded in each PluginInfo added meanwhile.
  void set_current_library(std::string path) { current_library_ = std::move(path); }

 private:
  const PluginInfo& checked(const std::string& name, PluginKind kind) const;
  std::map<std::string, PluginInfo> plugins_;
  std::string current_library_;
};

// What a plugin library exports, under the symbol name `suffuse_plugin_entry`.
// The layout of this struct never changes: the loader reads abi_major first.
struct PluginEntry {
  int abi_major;
  int abi_minor;
  const char* framework_version;  // version of the SDK the library was built against
  const char* build_type;         // "release" or "debug": mixing them is refused
  void (*register_plugins)(Registry& registry);
};

#if defined(NDEBUG)
inline constexpr const char* build_type = "release";
#else
inline constexpr const char* build_type = "debug";
#endif

}  // namespace suffuse

#define SUFFUSE_PLUGIN_ENTRY_SYMBOL suffuse_plugin_entry

// Defines the library's entry point and opens the body of its registration function.
#define SUFFUSE_PLUGIN_LIBRARY(registry_arg)                                              \
  static void suffuse_register_plugins_(::suffuse::Registry& registry_arg);              \
  extern "C" __attribute__((visibility("default"))) const ::suffuse::PluginEntry*        \
  SUFFUSE_PLUGIN_ENTRY_SYMBOL() {                                                       \
    static const ::suffuse::PluginEntry entry{::suffuse::abi_major, ::suffuse::abi_minor, \
                                              ::suffuse::framework_version,             \
                                              ::suffuse::build_type,                    \
                                              &suffuse_register_plugins_};              \
    return &entry;                                                                      \
  }                                                                                     \
  static void suffuse_register_plugins_(::suffuse::Registry& registry_arg)
