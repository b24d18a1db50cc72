// writer/vtk_particles: one binary .vtp per frame with every output field of
// the points, listed in the run's .pvd collection with its simulation time.
#include <suffuse/plugin.hpp>

#include "vtk_files.hpp"

namespace {

namespace fs = std::filesystem;

class VtkParticles final : public suffuse::Writer {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.boolean("compress").fallback(true).doc("Compress the appended binary data with zlib");
    return s;
  }
  explicit VtkParticles(const suffuse::PluginArgs& args) : compress_(args.params.boolean("compress")) {}

  void open(const fs::path& directory, const std::string& basename) override {
    suffuse::vtk::load_module("writer/vtk_particles");
    files_.open(directory, basename);
  }
  void resume(const fs::path& directory, const std::string& basename, const suffuse::ResumePoint& at) override {
    suffuse::vtk::load_module("writer/vtk_particles");
    files_.resume(directory, basename, at);
  }

  void write(const suffuse::OutputFrame& frame) override {
    const suffuse::PointSet& pts = frame.points;
    suffuse::vtk::PointsFrame out;
    out.dim = pts.dim();
    out.count = pts.size();
    out.positions = pts.data(pts.core().position);
    for (suffuse::FieldId f = 0; f < pts.field_count(); ++f) {
      const suffuse::FieldInfo& info = pts.info(f);
      if (info.output) out.arrays.push_back({info.name, info.kind, pts.size(), pts.data(f), info.unit});
    }
    suffuse::vtk::write_points(out, files_.next_path(), compress_, "writer/vtk_particles");
    files_.written(frame.series, frame.time);
  }

 private:
  bool compress_;
  suffuse::vtk::FrameFiles files_{"vtp"};
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Writer, VtkParticles>(
      "writer/vtk_particles",
      "Material points as binary VTK PolyData (.vtp) per frame, in the run's .pvd time series for ParaView");
}
