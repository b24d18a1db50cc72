// The VTK module of the writers (vtk_files.hpp): the only code of a run
// that links VTK, loaded when a VTK writer opens its series.
#include "vtk_files.hpp"

#include <vtkCellArray.h>
#include <vtkCellData.h>
#include <vtkDoubleArray.h>
#include <vtkImageData.h>
#include <vtkInformation.h>
#include <vtkNew.h>
#include <vtkPointData.h>
#include <vtkPoints.h>
#include <vtkPolyData.h>
#include <vtkSmartPointer.h>
#include <vtkXMLImageDataWriter.h>
#include <vtkXMLPolyDataWriter.h>

#include <suffuse/error.hpp>
#include <suffuse/version.hpp>
#include <type_traits>

namespace {

namespace fs = std::filesystem;
using suffuse::FieldKind;

vtkSmartPointer<vtkDoubleArray> make_array(const suffuse::vtk::Array& a, int dim) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(a.name.c_str());
  const int k = suffuse::components_of(a.kind, dim);
  const std::size_t n = a.tuples;
  const double* v = a.values;
  if (a.kind == FieldKind::Vector || a.kind == FieldKind::Tensor) {
    // ParaView expects 3 (or 9) components: pad the missing ones with zeros.
    const int out = a.kind == FieldKind::Vector ? 3 : 9;
    array->SetNumberOfComponents(out);
    array->SetNumberOfTuples(static_cast<vtkIdType>(n));
    for (std::size_t p = 0; p < n; ++p) {
      double t[9] = {};
      if (a.kind == FieldKind::Vector) {
        for (int i = 0; i < dim; ++i) t[i] = v[p * k + i];
      } else {
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) t[i * 3 + j] = v[p * k + i * dim + j];
      }
      array->SetTypedTuple(static_cast<vtkIdType>(p), t);
    }
  } else if (a.kind == FieldKind::SymmetricTensor) {
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
  array->GetInformation()->Set(vtkDataArray::UNITS_LABEL(), a.unit.c_str());
  return array;
}

void write_atomically(vtkXMLWriter& writer, const fs::path& file, bool compress, const std::string& plugin) {
  const fs::path tmp = file.string() + ".part";
  writer.SetFileName(tmp.c_str());
  writer.SetDataModeToAppended();
  writer.EncodeAppendedDataOff();
  if (compress)
    writer.SetCompressorTypeToZLib();
  else
    writer.SetCompressorTypeToNone();
  if (writer.Write() != 1) throw suffuse::Error(plugin + ": cannot write " + file.string());
  fs::rename(tmp, file);
}

}  // namespace

extern "C" void suffuse_vtk_write_points(const suffuse::vtk::PointsFrame& frame, const fs::path& file, bool compress,
                                         const std::string& plugin) {
  const std::size_t n = frame.count;
  const int dim = frame.dim;
  vtkNew<vtkPoints> points;
  points->SetDataTypeToDouble();
  points->SetNumberOfPoints(static_cast<vtkIdType>(n));
  for (std::size_t p = 0; p < n; ++p) {
    double xyz[3] = {0, 0, 0};
    for (int a = 0; a < dim; ++a) xyz[a] = frame.positions[p * dim + a];
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
  for (const suffuse::vtk::Array& a : frame.arrays) poly->GetPointData()->AddArray(make_array(a, dim));
  vtkNew<vtkXMLPolyDataWriter> writer;
  writer->SetInputData(poly);
  write_atomically(*writer, file, compress, plugin);
}

extern "C" void suffuse_vtk_write_image(const suffuse::vtk::ImageFrame& frame, const fs::path& file, bool compress,
                                        const std::string& plugin) {
  vtkNew<vtkImageData> image;
  image->SetDimensions(frame.nodes[0], frame.nodes[1], frame.nodes[2]);
  image->SetOrigin(frame.origin[0], frame.origin[1], frame.origin[2]);
  image->SetSpacing(frame.spacing[0], frame.spacing[1], frame.spacing[2]);
  for (const suffuse::vtk::Array& a : frame.node_arrays) image->GetPointData()->AddArray(make_array(a, frame.dim));
  for (const suffuse::vtk::Array& a : frame.cell_arrays) image->GetCellData()->AddArray(make_array(a, frame.dim));
  vtkNew<vtkXMLImageDataWriter> writer;
  writer->SetInputData(image);
  write_atomically(*writer, file, compress, plugin);
}

extern "C" const char* suffuse_vtk_module_version() { return suffuse::framework_version; }

static_assert(std::is_same_v<decltype(suffuse_vtk_write_points), suffuse::vtk::WritePoints>);
static_assert(std::is_same_v<decltype(suffuse_vtk_write_image), suffuse::vtk::WriteImage>);
static_assert(std::is_same_v<decltype(suffuse_vtk_module_version), suffuse::vtk::ModuleVersion>);
