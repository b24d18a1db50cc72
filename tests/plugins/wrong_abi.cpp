// A library that claims another plugin ABI major version: must be refused.
#include <suffuse/plugin.hpp>

static void register_nothing(suffuse::Registry&) {}

extern "C" __attribute__((visibility("default"))) const suffuse::PluginEntry* suffuse_plugin_entry() {
  static const suffuse::PluginEntry entry{suffuse::abi_major + 1, 0, "99.0.0", suffuse::build_type,
                                          &register_nothing};
  return &entry;
}
