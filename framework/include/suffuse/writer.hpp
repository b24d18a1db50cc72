#pragma once
// Writers turn the state of a run into files.
#include <cstddef>
#include <filesystem>
#include <string>

#include "suffuse/grid.hpp"
#include "suffuse/points.hpp"

namespace suffuse {

struct OutputFrame {
  const PointSet& points;
  const GridGeometry& grid;
  std::size_t step;
  double time;  // simulation time [s]
};

class Writer {
 public:
  virtual ~Writer() = default;
  // Create the writer's files in `directory`; `basename` names the series.
  virtual void open(const std::filesystem::path& directory, const std::string& basename) = 0;
  // Write one frame. After it returns, every file written so far must be
  // complete and readable, so a run that fails later leaves usable output.
  virtual void write(const OutputFrame& frame) = 0;
  virtual void close() {}
};

}  // namespace suffuse
