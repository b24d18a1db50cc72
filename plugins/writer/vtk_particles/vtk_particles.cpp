// writer/vtk_particles: one binary .vtp per frame with every output field of
// the points, listed in the run's .pvd collection with its simulation time.
#include <vtkCellArray.h>
#include <vtkDoubleArray.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkXMLPolyDataWriter.h>

#include <filesystem>
#include <iomanip>
#include <sstream>
#include <suffuse/error.hpp>
#include <suffuse/plugin.hpp>

namespace {

namespace fs = std::filesystem;
using suffuse::FieldKind;

class VtkParticles final : public suffuse::Writer {
 public:
  static suffuse::ParameterSchema schema() {
    suffuse::ParameterSchema s;
    s.boolean("compress").fallback(true).doc("Compress the appended binary data with zlib");
    return s;
  }
  explicit VtkParticles(const suffuse::PluginArgs& args) : compress_(args.params.boolean("compress")) {}

  void open(const fs::path& directory, const std::string& basename) override {
    directory_ = directory;
    basename_ = basename;
    frames_ = 0;
  }

  // Frames after the checkpoint's are written again: the files of the run
  // that went further are removed so that none is left over.
  void resume(const fs::path& directory, const std::string& basename, const suffuse::ResumePoint& at) override {
    open(directory, basename);
    frames_ = at.frames;
    for (std::size_t k = frames_; fs::exists(directory_ / file_name(k)); ++k) fs::remove(directory_ / file_name(k));
  }

  void write(const suffuse::OutputFrame& frame) override {
    const std::string name = file_name(frames_);
    write_polydata(frame, directory_ / name);
    ++frames_;
    frame.series.add(name, frame.time);
  }

 private:
  void write_polydata(const suffuse::OutputFrame& frame, const fs::path& file) const {
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
      poly->GetPointData()->AddArray(make_array(pts, f));
    }

    vtkNew<vtkXMLPolyDataWriter> writer;
    const fs::path tmp = file.string() + ".part";
    writer->SetFileName(tmp.c_str());
    writer->SetInputData(poly);
    writer->SetDataModeToAppended();
    writer->EncodeAppendedDataOff();
    if (compress_)
      writer->SetCompressorTypeToZLib();
    else
      writer->SetCompressorTypeToNone();
    if (writer->Write() != 1) throw suffuse::Error("writer/vtk_particles: cannot write " + file.string());
    fs::rename(tmp, file);  // a reader never sees a half-written frame
  }

  static vtkSmartPointer<vtkDoubleArray> make_array(const suffuse::PointSet& pts, suffuse::FieldId f) {
    const suffuse::FieldInfo& info = pts.info(f);
    const int dim = pts.dim(), k = pts.components(f);
    const std::size_t n = pts.size();
    const double* v = pts.data(f);
    auto array = vtkSmartPointer<vtkDoubleArray>::New();
    array->SetName(info.name.c_str());
    if (info.kind == FieldKind::Vector || info.kind == FieldKind::Tensor) {
      // ParaView expects 3 (or 9) components: pad the missing ones with zeros.
      const int out = info.kind == FieldKind::Vector ? 3 : 9;
      array->SetNumberOfComponents(out);
      array->SetNumberOfTuples(static_cast<vtkIdType>(n));
      for (std::size_t p = 0; p < n; ++p) {
        double t[9] = {};
        if (info.kind == FieldKind::Vector) {
          for (int a = 0; a < dim; ++a) t[a] = v[p * k + a];
        } else {
          for (int i = 0; i < dim; ++i)
            for (int j = 0; j < dim; ++j) t[i * 3 + j] = v[p * k + i * dim + j];
        }
        array->SetTypedTuple(static_cast<vtkIdType>(p), t);
      }
    } else if (info.kind == FieldKind::SymmetricTensor) {
      // VTK's symmetric tensor order is XX YY ZZ XY YZ XZ; ours is xx yy zz yz xz xy.
      array->SetNumberOfComponents(6);
      array->SetNumberOfTuples(static_cast<vtkIdType>(n));
      const char* names[6] = {"XX", "YY", "ZZ", "XY", "YZ", "XZ"};
      for (int c = 0; c < 6; ++c) array->SetComponentName(c, names[c]);
      for (std::size_t p = 0; p < n; ++p) {
        const double* s = v + p * 6;
        const double t[6] = {s[0], s[1], s[2], s[5], s[3], s[4]};
        array->SetTypedTuple(static_cast<vtkIdType>(p), t);
      }
    } else {
      array->SetNumberOfComponents(1);
      array->SetNumberOfTuples(static_cast<vtkIdType>(n));
      for (std::size_t p = 0; p < n; ++p) array->SetValue(static_cast<vtkIdType>(p), v[p]);
    }
    return array;
  }

  std::string file_name(std::size_t frame) const {
    std::ostringstream name;
    name << basename_ << "_" << std::setw(6) << std::setfill('0') << frame << ".vtp";
    return name.str();
  }

  bool compress_;
  fs::path directory_;
  std::string basename_;
  std::size_t frames_ = 0;
};

}  // namespace

SUFFUSE_PLUGIN_LIBRARY(registry) {
  registry.add<suffuse::Writer, VtkParticles>(
      "writer/vtk_particles",
      "Material points as binary VTK PolyData (.vtp) per frame, in the run's .pvd time series for ParaView");
}
