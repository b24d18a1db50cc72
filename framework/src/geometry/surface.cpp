#include "geometry/surface.hpp"

#include "suffuse/error.hpp"
#include "suffuse/plugin_loader.hpp"

namespace suffuse::detail {

namespace {
// The module's entries, loaded once, never unloaded (PluginLoader::load_module).
struct SurfaceModule {
  SeedSurfaceEntry* seed;
  ReadPointsEntry* read_points;
};

const SurfaceModule& surface_module() {
  static const SurfaceModule module = [] {
    const auto at = PluginLoader::load_module("libsuffuse_surfaces.so", "surface module",
                                              "suffuse_surface_module_version",
                                              {"suffuse_surface_seed", "suffuse_points_read"});
    return SurfaceModule{reinterpret_cast<SeedSurfaceEntry*>(at[0]), reinterpret_cast<ReadPointsEntry*>(at[1])};
  }();
  return module;
}
}  // namespace

SurfaceSeeds seed_surface(const std::filesystem::path& file, const SurfaceLattice& lattice) {
  SurfaceSeeds seeds;
  surface_module().seed(file, lattice, seeds);
  return seeds;
}

VtpPoints read_vtp_points(const std::filesystem::path& file, int dim) {
  VtpPoints points;
  surface_module().read_points(file, dim, points);
  return points;
}

}  // namespace suffuse::detail
