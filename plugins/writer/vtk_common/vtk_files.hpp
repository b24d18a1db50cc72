#pragma once
// What the VTK writers share: the numbered frame files of a series
// (resumable after a restart), and the writing of a frame's arrays as VTK
// XML. VTK itself sits in a module loaded when a writer opens its series
// (vtk_files.cpp): linked into the plugins, its libraries would cost every
// run about 9 MB resident (the loader opens every plugin library to list
// what it holds), 90 bytes per point of the 2D benches.
#include <array>
#include <cstddef>
#include <filesystem>
#include <string>
#include <suffuse/points.hpp>
#include <suffuse/writer.hpp>
#include <vector>

namespace suffuse::vtk {

// `tuples` values of a field (components_of(kind, dim) each, interleaved).
// In the file vectors are padded to 3 components, tensors to 9, symmetric
// tensors reordered to VTK's XX YY ZZ XY YZ XZ.
struct Array {
  std::string name;
  FieldKind kind = FieldKind::Scalar;
  std::size_t tuples = 0;
  const double* values = nullptr;
  std::string unit;  // SI, "-" dimensionless: every array's UNITS_LABEL; suffuse plot reads it for its labels
};

// Material points as vertices of a .vtp (PolyData).
struct PointsFrame {
  int dim = 2;
  std::size_t count = 0;
  const double* positions = nullptr;  // dim per point
  std::vector<Array> arrays;
};

// The grid as a .vti (ImageData): nodal and cell arrays.
struct ImageFrame {
  int dim = 2;
  std::array<int, 3> nodes{1, 1, 1};
  std::array<double, 3> origin{}, spacing{1, 1, 1};
  std::vector<Array> node_arrays, cell_arrays;
};

// Each writes its frame to `file` through a temporary name (a reader never
// sees a half-written file), appended binary data, zlib-compressed if asked.
// Throws suffuse::Error naming `plugin`.
void write_points(const PointsFrame& frame, const std::filesystem::path& file, bool compress,
                  const std::string& plugin);
void write_image(const ImageFrame& frame, const std::filesystem::path& file, bool compress, const std::string& plugin);
// Loads the module now, if it is not yet (a writer's open and resume: a
// missing module then stops a run or a restart before its first step).
void load_module(const std::string& plugin);

// The frame files <basename>_NNNNNN.<extension> of one writer.
class FrameFiles {
 public:
  FrameFiles(std::string extension) : extension_(std::move(extension)) {}
  void open(const std::filesystem::path& directory, const std::string& basename);
  // Frames after the checkpoint's are written again: the files of the run
  // that went further are removed so that none is left over.
  void resume(const std::filesystem::path& directory, const std::string& basename, const ResumePoint& at);
  // The next frame's name (relative to the directory) and full path.
  std::string next_name() const;
  std::filesystem::path next_path() const { return directory_ / next_name(); }
  // After the next frame was written: lists it in the run's series.
  void written(OutputSeries& series, double time);

 private:
  std::string name(std::size_t frame) const;
  std::string extension_;
  std::filesystem::path directory_;
  std::string basename_;
  std::size_t frames_ = 0;
};

// The module's entry points, by name (vtk_files.cpp), and the suffuse
// version it was built with: a module of another version is refused (the
// types above are this version's).
using WritePoints = void(const PointsFrame&, const std::filesystem::path&, bool, const std::string&);
using WriteImage = void(const ImageFrame&, const std::filesystem::path&, bool, const std::string&);
using ModuleVersion = const char*();

}  // namespace suffuse::vtk
