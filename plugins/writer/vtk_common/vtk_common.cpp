#include "vtk_common.hpp"

#include <iomanip>
#include <sstream>
#include <suffuse/error.hpp>

namespace suffuse::vtk {

namespace fs = std::filesystem;

vtkSmartPointer<vtkDoubleArray> make_array(const std::string& name, FieldKind kind, int dim, std::size_t n,
                                           const double* v) {
  auto array = vtkSmartPointer<vtkDoubleArray>::New();
  array->SetName(name.c_str());
  const int k = components_of(kind, dim);
  if (kind == FieldKind::Vector || kind == FieldKind::Tensor) {
    // ParaView expects 3 (or 9) components: pad the missing ones with zeros.
    const int out = kind == FieldKind::Vector ? 3 : 9;
    array->SetNumberOfComponents(out);
    array->SetNumberOfTuples(static_cast<vtkIdType>(n));
    for (std::size_t p = 0; p < n; ++p) {
      double t[9] = {};
      if (kind == FieldKind::Vector) {
        for (int a = 0; a < dim; ++a) t[a] = v[p * k + a];
      } else {
        for (int i = 0; i < dim; ++i)
          for (int j = 0; j < dim; ++j) t[i * 3 + j] = v[p * k + i * dim + j];
      }
      array->SetTypedTuple(static_cast<vtkIdType>(p), t);
    }
  } else if (kind == FieldKind::SymmetricTensor) {
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

void FrameFiles::open(const fs::path& directory, const std::string& basename) {
  directory_ = directory;
  basename_ = basename;
  frames_ = 0;
}

void FrameFiles::resume(const fs::path& directory, const std::string& basename, const ResumePoint& at) {
  open(directory, basename);
  frames_ = at.frames;
  for (std::size_t k = frames_; fs::exists(directory_ / name(k)); ++k) fs::remove(directory_ / name(k));
}

std::string FrameFiles::name(std::size_t frame) const {
  std::ostringstream out;
  out << basename_ << "_" << std::setw(6) << std::setfill('0') << frame << "." << extension_;
  return out.str();
}

std::string FrameFiles::next_name() const { return name(frames_); }

void FrameFiles::written(OutputSeries& series, double time) {
  series.add(name(frames_), time);
  ++frames_;
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
  if (writer.Write() != 1) throw Error(plugin + ": cannot write " + file.string());
  fs::rename(tmp, file);
}

}  // namespace suffuse::vtk
