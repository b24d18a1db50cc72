#pragma once
// What a run writes while it steps: the writers' frames (with the one .pvd
// collection), the mass ledger and the reactions as CSV. Every file is
// complete after each output step, and a restarted run resumes each of them
// after the checkpoint's time.
#include <cstddef>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <vector>

#include "io/grid_projection.hpp"
#include "io/output_series.hpp"
#include "suffuse/scene.hpp"
#include "suffuse/simulation.hpp"
#include "suffuse/writer.hpp"

namespace suffuse::detail {

class Reactions;
class SpeciesTransport;

class RunOutputs {
 public:
  RunOutputs(const Scene& scene, std::vector<std::unique_ptr<Writer>>& writers, const std::filesystem::path& dir,
             Domain& domain, const SpeciesTransport* species, Reactions& reactions, GridProjection& grid,
             StageTimes& times);

  // A new run: creates the files and writes the initial state.
  void start(double time, std::size_t step);
  // A restarted run: keeps what was written up to `time` (each writer had
  // written saved.frames[w] frames) and appends after it.
  void resume(double time, std::size_t step, const WriterCheckpoint& saved);
  // After a step: the frames and rows due at `now` (at the end, every one
  // not yet written at this step: a quasi-static step that failed, under
  // /failure, leaves the step as it was).
  void after_step(double now, std::size_t step, bool at_end);
  // From a quasi-static run's failure at `from` on (/failure/collapse): a
  // frame of every writer and a row of every CSV each `interval`.
  void follow_collapse(double from, double interval);
  void close();

  // What a checkpoint keeps of the writers now: the frames each has written
  // and, on the process that writes, its state.
  WriterCheckpoint checkpoint() const;

 private:
  double next_multiple(double interval, double now) const;
  void write_frame(std::size_t w, double now, std::size_t step);
  std::optional<MassLedger> ledger_at(double time) const;
  void open_csv(std::ofstream& csv, const char* suffix, std::optional<double> resume_time,
                const std::optional<MassLedger>& ledger);
  void write_rows(double now);

  const Scene& scene_;
  std::vector<std::unique_ptr<Writer>>& writers_;
  std::filesystem::path dir_;
  Domain& domain_;
  const SpeciesTransport* species_;
  Reactions& reactions_;
  GridProjection& grid_;
  StageTimes& times_;
  // On many processes the first one writes; the others take part in what a
  // frame gathers (points, projected fields, the ledger's sums).
  bool writes_;
  std::unique_ptr<PvdSeries> series_;
  std::vector<double> interval_, next_;
  std::vector<std::size_t> frames_;
  double row_interval_, next_row_;
  double origin_ = 0;  // of the multiples of the intervals (a collapse's start)
  static constexpr std::size_t none = static_cast<std::size_t>(-1);
  std::vector<std::size_t> written_step_;  // per writer: the step of its last frame
  std::size_t rows_step_ = none;           // the step of the last rows
  std::size_t last_step_ = none;           // of the last after_step
  std::ofstream ledger_, reactions_csv_;
};

}  // namespace suffuse::detail
