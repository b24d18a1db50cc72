#include "suffuse/error.hpp"
#include "suffuse/plugin.hpp"

namespace suffuse {

std::string to_string(PluginKind kind) {
  switch (kind) {
#define SUFFUSE_KIND_NAME(type, name) \
  case PluginKind::type:              \
    return name;
    SUFFUSE_PLUGIN_KINDS(SUFFUSE_KIND_NAME)
#undef SUFFUSE_KIND_NAME
  }
  return "?";
}

void Registry::add_info(PluginInfo info) {
  info.library = current_library_;
  auto it = plugins_.find(info.name);
  if (it != plugins_.end())
    throw Error("plugin '" + info.name + "' is registered twice: by " +
                (it->second.library.empty() ? "the program itself" : it->second.library) + " and by " +
                (info.library.empty() ? "the program itself" : info.library));
  if (!info.schema || !info.factory) throw Error("plugin '" + info.name + "' has no schema or factory");
  std::string name = info.name;
  plugins_.emplace(std::move(name), std::move(info));
}

const PluginInfo* Registry::find(const std::string& name) const {
  auto it = plugins_.find(name);
  return it == plugins_.end() ? nullptr : &it->second;
}

std::vector<std::string> Registry::names_of(PluginKind kind) const {
  std::vector<std::string> names;
  for (const auto& [name, info] : plugins_)
    if (info.kind == kind) names.push_back(name);
  return names;
}

const PluginInfo& Registry::checked(const std::string& name, PluginKind kind) const {
  const PluginInfo* info = find(name);
  if (!info) throw Error("no plugin named '" + name + "' is loaded");
  if (info->kind != kind)
    throw Error("plugin '" + name + "' is a " + to_string(info->kind) + ", not a " + to_string(kind));
  return *info;
}

}  // namespace suffuse
