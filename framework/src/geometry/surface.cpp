#include "geometry/surface.hpp"

#include "suffuse/error.hpp"
#include "suffuse/plugin_loader.hpp"

namespace suffuse::detail {

SurfaceSeeds seed_surface(const std::filesystem::path& file, const SurfaceLattice& lattice) {
  // Loaded once, never unloaded (PluginLoader::load_module).
  static SeedSurfaceEntry* const seed = [] {
    const auto at = PluginLoader::load_module("libsuffuse_surfaces.so", "surface module",
                                              "suffuse_surface_module_version", {"suffuse_surface_seed"});
    return reinterpret_cast<SeedSurfaceEntry*>(at[0]);
  }();
  SurfaceSeeds seeds;
  seed(file, lattice, seeds);
  return seeds;
}

}  // namespace suffuse::detail
