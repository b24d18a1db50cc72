// libFuzzer target: scene parsing and validation, suffuse::parse_scene, with
// the bundled plugins loaded once. Expected failures are exceptions derived
// from std::exception (suffuse::Error, SceneError); a crash, a hang, a
// sanitizer report or any other exception is a finding. See docs/robustness.md.
//
//   build-asan/bin/fuzz_scene -dict=fuzz/scene.dict -max_total_time=60 corpus/ share/scenes/
#include <cstddef>
#include <cstdint>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <suffuse/plugin_loader.hpp>
#include <suffuse/scene.hpp>

#include "scene/validation.hpp"

namespace {

struct Context {
  suffuse::Registry registry;
  suffuse::PluginLoader loader{registry};
  // Relative paths in a scene (gradation files) resolve as for the example
  // scenes of the seed corpus.
  std::filesystem::path base_dir = std::filesystem::path(SUFFUSE_SOURCE_DIR) / "share" / "scenes";
};

Context& context() {
  // Built once, never destroyed: the plugins stay loaded for every input.
  static Context* c = [] {
    // Only the bundled plugins, whatever the environment says.
    unsetenv("SUFFUSE_PLUGIN_PATH");
    auto* ctx = new Context;
    for (const auto& path : suffuse::PluginLoader::default_search_path()) ctx->loader.load_path(path);
    if (ctx->registry.all().empty()) std::abort();  // no plugins: the fuzzer would test nothing
    return ctx;
  }();
  return *c;
}

}  // namespace

extern "C" int LLVMFuzzerInitialize(int*, char***) {
  context();
  return 0;
}

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  Context& ctx = context();
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    // A scene's "plugin_paths" would dlopen whatever the fuzzer names (any
    // directory of the machine): such inputs are left out of the corpus.
    const auto root = suffuse::detail::parse_scene_text(text, "fuzz.json");
    if (root.is_object() && root.contains("plugin_paths")) return -1;
  } catch (const std::exception&) {
  }
  try {
    suffuse::parse_scene(text, "fuzz.json", ctx.base_dir, ctx.registry, ctx.loader);
  } catch (const std::exception&) {
    // Refused with a message: what a bad scene should get.
  }
  return 0;
}
