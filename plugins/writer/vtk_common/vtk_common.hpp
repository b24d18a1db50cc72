#pragma once
// What the VTK writers share: arrays in ParaView's layout, the numbered
// frame files of a series (resumable after a restart), and atomic writes.
#include <vtkDoubleArray.h>
#include <vtkSmartPointer.h>
#include <vtkXMLWriter.h>

#include <cstddef>
#include <filesystem>
#include <string>
#include <suffuse/points.hpp>
#include <suffuse/writer.hpp>

namespace suffuse::vtk {

// n tuples of `values` (k components each, interleaved) as a VTK array:
// vectors padded to 3 components, tensors to 9, symmetric tensors reordered
// to VTK's XX YY ZZ XY YZ XZ.
vtkSmartPointer<vtkDoubleArray> make_array(const std::string& name, FieldKind kind, int dim, std::size_t n,
                                           const double* values);

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

// Writes `writer`'s input to `file` through a temporary name (a reader never
// sees a half-written file), appended binary data, zlib-compressed if asked.
// Throws suffuse::Error naming `plugin`.
void write_atomically(vtkXMLWriter& writer, const std::filesystem::path& file, bool compress, const std::string& plugin);

}  // namespace suffuse::vtk
