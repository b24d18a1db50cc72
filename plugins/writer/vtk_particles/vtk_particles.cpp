// writer/vtk_particles: one binary .vtp per frame with every output field of
// the points, listed in the run's .pvd collection with its simulation time.
#include <vtkCellArray.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <suffuse/plugin.hpp>

#include "vtk_common.hpp"

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

  void open(const fs::path& directory, const std::string& basename) override { files_.open(directory, basename); }
  void resume(const fs::path& directory, const std::string& basename, const suffuse::ResumePoint& at) override {
    files_.resume(directory, basename, at);
  }

  void write(const suffuse::OutputFrame& frame) override {
    const suffuse::PointSet& pts = frame.points;
    const int dim = pts.dim();
    const std::size_t n = pts.size();
    const double* x = pts.data(pts.core().position);

    vtkNew<vtkPoints> points;
    points->SetDataTypeToDouble();
    points->SetNumberOfPoints(static_cast<vtkIdType>(n));
    for (std::size_t p = 0; p < n; ++p) {
      double xyz[3] = {0, 0, 0};
      for (int a = 0; a < dim; ++a) xyz[a] = x[p * dim + a];
      points->SetPoint(static_cast<vtkIdType>(p), xyz);
    }
    vtkNew<vtkCellArray> vertices;
    vertices->AllocateExact(static_cast<vtkIdType>(n), static_cast<vtkIdType>(n));
    for (std::size_t p = 0; p < n; ++p) {
      vtkIdType id = static_cast<vtkIdType>(p);
      vertices->InsertNextCell(1, &id);
    }
    vtkNew<vtkPolyData> poly;
    poly->SetPoints(points);
    poly->SetVerts(vertices);
    for (suffuse::FieldId f = 0; f < pts.field_count(); ++f) {
      const suffuse::FieldInfo& info = pts.info(f);
      if (!info.output) continue;
      auto array = suffuse::vtk::make_array(info.name, info.kind, dim, n, pts.data(f));
      // The unit travels with the array (suffuse plot reads it for its labels).
      array->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), info.unit.c_str());
      poly->GetPointData()->AddArray(array);
    }
    vtkNew<vtkXMLPolyDataWriter> writer;
    writer->SetInputData(poly);
    suffuse::vtk::write_atomically(*writer, files_.next_path(), compress_, "writer/vtk_particles");
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
