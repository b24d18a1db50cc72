#pragma once
// Writers turn the state of a run into files.
//
// A writer gets, at each of its frames, the material points, the grid and,
// when it asks for them, fields the core projects on the grid (nodal
// velocities, pore pressure, Darcy flux) and the mass ledger. Writers of
// VTK data add their files to the run's one `.pvd` collection (OutputSeries),
// so ParaView opens points and grid together with real simulation times.
//
// A run restarted from a checkpoint resumes every writer: it continues its
// files after the checkpoint's time instead of starting over.
#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "suffuse/grid.hpp"
#include "suffuse/mass_ledger.hpp"
#include "suffuse/points.hpp"

namespace suffuse {

// A field on the grid, projected from the points by the core at a frame.
struct GridField {
  std::string name;
  std::string unit;  // SI
  std::string description;
  int components = 1;          // 1, or dim for vectors (interleaved per node)
  std::vector<double> values;  // per node, node order of GridGeometry
};

// The run's VTK collection (<scene>.pvd). Each writer that adds files is one
// "part" of every time step, so ParaView shows them as one multiblock.
class OutputSeries {
 public:
  virtual ~OutputSeries() = default;
  // Lists `file` (a name relative to the output directory) at `time` for the
  // writer now writing; the collection on disk is rewritten (atomically)
  // once every writer of the step has written.
  virtual void add(const std::string& file, double time) = 0;
};

struct OutputFrame {
  const PointSet& points;
  const GridGeometry& grid;
  std::size_t step;
  double time;  // simulation time [s]
  // Nodal fields of this frame; filled only for writers whose
  // wants_grid_fields() is true (empty otherwise).
  const std::vector<GridField>& grid_fields;
  const MassLedger* ledger;  // saturated runs: the balance now; null otherwise
  OutputSeries& series;
};

// Where a resumed writer continues: the checkpoint's time, how many frames
// this writer had written up to it (at times <= time), and what its
// saved_state() returned when the checkpoint was written.
struct ResumePoint {
  double time;
  std::size_t frames;
  std::string state;
};

// What a checkpoint keeps of a run's writers, in the scene's order.
struct WriterCheckpoint {
  std::vector<std::size_t> frames;  // frames each has written
  std::vector<std::string> states;  // each one's saved_state()
  // Every output wrote its frame and rows at the checkpoint's step (a run
  // that ended, failed or was stopped there): a run restarted from it that
  // ends at once (a failure again) writes none twice.
  bool written_at_its_step = false;
};

class Writer {
 public:
  virtual ~Writer() = default;
  // Create the writer's files in `directory`; `basename` names its files.
  virtual void open(const std::filesystem::path& directory, const std::string& basename) = 0;
  // Instead of open() in a restarted run: keep what was written up to
  // `at.time`, drop what came later, and append from there.
  virtual void resume(const std::filesystem::path& directory, const std::string& basename, const ResumePoint& at) = 0;
  // Write one frame. After it returns, every file written so far must be
  // complete and readable, so a run that fails later leaves usable output.
  virtual void write(const OutputFrame& frame) = 0;
  virtual void close() {}
  // When the run sorts its points again into the grid's order
  // (/sort_points_at_spread): on the process that writes, new_number[p] is
  // the new number of the point numbered p until now. A writer that keeps
  // point numbers between frames (a followed point) takes the new ones.
  virtual void points_renumbered(std::span<const std::size_t> new_number) { (void)new_number; }
  // What the writer must find again in a restarted run that its files do
  // not hold (a followed point's number, say), as UTF-8 text; written into every
  // checkpoint and handed back in ResumePoint::state.
  virtual std::string saved_state() const { return {}; }
  // Whether write() reads OutputFrame::grid_fields (the core projects them
  // only then).
  virtual bool wants_grid_fields() const { return false; }
  // Frames over the run when the scene gives no interval: end time / this.
  virtual int default_frame_count() const { return 20; }
};

// For writers of CSV time series, on resume: keeps the header (every line
// before the first whose first cell is a number) and the rows whose first
// cell (the time) is at most `time` (plus round-off), drops the rest.
// Rewrites the file atomically. Returns false, doing nothing, if there is no
// such file (the writer then starts it anew).
bool keep_csv_rows_until(const std::filesystem::path& file, double time);

}  // namespace suffuse
