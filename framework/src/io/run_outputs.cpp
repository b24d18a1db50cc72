#include "io/run_outputs.hpp"

#include <algorithm>
#include <cmath>

#include "mpm/reactions.hpp"
#include "transport/species_transport.hpp"
#include "common/stage_timer.hpp"
#include "suffuse/error.hpp"

namespace suffuse::detail {

namespace fs = std::filesystem;

RunOutputs::RunOutputs(const Scene& scene, std::vector<std::unique_ptr<Writer>>& writers, const fs::path& dir,
                       Domain& domain, const SpeciesTransport* species, Reactions& reactions, GridProjection& grid,
                       StageTimes& times)
    : scene_(scene),
      writers_(writers),
      dir_(dir),
      domain_(domain),
      species_(species),
      reactions_(reactions),
      grid_(grid),
      times_(times),
      writes_(domain.comm.root()),
      // Rows of the ledger and the reactions: every end/200 s.
      row_interval_(scene.end_time / 200),
      next_row_(0) {
  for (std::size_t w = 0; w < writers_.size(); ++w)
    interval_.push_back(scene.outputs[w].interval.value_or(scene.end_time / writers_[w]->default_frame_count()));
  next_.assign(writers_.size(), 0.0);
  written_step_.assign(writers_.size(), none);
  frames_.assign(writers_.size(), 0);
}

// The next multiple of `interval` after `now`, counted from the origin (one
// frame per step at most).
double RunOutputs::next_multiple(double interval, double now) const {
  const double eps = 1e-9 * interval;
  return origin_ + (std::floor((now - origin_ + eps) / interval) + 1) * interval;
}

void RunOutputs::follow_collapse(double from, double interval) {
  origin_ = from;
  interval_.assign(writers_.size(), interval);
  row_interval_ = interval;
  for (std::size_t w = 0; w < writers_.size(); ++w) next_[w] = next_multiple(interval, from);
  next_row_ = next_multiple(interval, from);
}

// The ledger at `time`: a sum over every process's points, so every process
// computes it wherever the first one writes a row.
std::optional<MassLedger> RunOutputs::ledger_at(double time) const {
  if (!species_) return std::nullopt;
  return species_->mass_ledger(time);
}

void RunOutputs::open_csv(std::ofstream& csv, const char* suffix, std::optional<double> resume_time,
                          const std::optional<MassLedger>& ledger) {
  const fs::path file = dir_ / (scene_.name + suffix);
  const bool append = resume_time && keep_csv_rows_until(file, *resume_time);
  csv.open(file, append ? std::ios::app : std::ios::trunc);
  if (!csv) throw Error("cannot write " + file.string());
  csv.precision(10);
  if (append) return;
  if (&csv == &ledger_)
    species_->write_ledger_row(csv, *ledger, true);
  else
    reactions_.write_header(csv);
  csv.flush();
}

void RunOutputs::start(double time, std::size_t step) {
  if (dir_.empty()) return;
  const std::optional<MassLedger> ledger = ledger_at(time);  // the ledger's first row
  if (!writes_) {  // the same exchanges as the first process's below
    for (std::size_t w = 0; w < writers_.size(); ++w) {
      write_frame(w, time, step);
      written_step_[w] = step;
      next_[w] = interval_[w];
    }
    next_row_ = row_interval_;
    rows_step_ = step;
    return;
  }
  if (!writers_.empty() || species_ || !reactions_.empty()) fs::create_directories(dir_);
  series_ = std::make_unique<PvdSeries>(dir_ / (scene_.name + ".pvd"));
  if (species_) open_csv(ledger_, ".ledger.csv", std::nullopt, ledger);
  if (!reactions_.empty()) open_csv(reactions_csv_, ".reactions.csv", std::nullopt, ledger);
  for (std::size_t w = 0; w < writers_.size(); ++w) writers_[w]->open(dir_, output_basename(scene_, w));
  for (std::size_t w = 0; w < writers_.size(); ++w) {
    write_frame(w, time, step);
    written_step_[w] = step;
    next_[w] = interval_[w];
  }
  if (!series_->empty()) series_->save();
  next_row_ = row_interval_;
  rows_step_ = step;
}

WriterCheckpoint RunOutputs::checkpoint() const {
  WriterCheckpoint saved{frames_, {}};
  saved.written_at_its_step =
      last_step_ != none && rows_step_ == last_step_ &&
      std::all_of(written_step_.begin(), written_step_.end(), [&](std::size_t s) { return s == last_step_; });
  if (writes_)
    for (const auto& w : writers_) saved.states.push_back(w->saved_state());
  return saved;
}

void RunOutputs::resume(double time, std::size_t step, const WriterCheckpoint& saved) {
  if (dir_.empty()) return;
  if (saved.written_at_its_step) {
    written_step_.assign(writers_.size(), step);
    rows_step_ = step;
  }
  const std::vector<std::size_t>& frames = saved.frames;
  if (frames.size() != writers_.size())
    throw Error("cannot restart: the checkpoint has " + std::to_string(frames.size()) + " writers, the scene " +
                std::to_string(writers_.size()));
  const std::optional<MassLedger> ledger = ledger_at(time);  // for a ledger CSV written anew
  frames_ = frames;
  for (std::size_t w = 0; w < writers_.size(); ++w) next_[w] = next_multiple(interval_[w], time);
  next_row_ = next_multiple(row_interval_, time);
  if (!writes_) return;
  fs::create_directories(dir_);
  const fs::path pvd = dir_ / (scene_.name + ".pvd");
  series_ = fs::exists(pvd) ? std::make_unique<PvdSeries>(PvdSeries::resumed(pvd, time))
                            : std::make_unique<PvdSeries>(pvd);
  if (species_) open_csv(ledger_, ".ledger.csv", time, ledger);
  if (!reactions_.empty()) open_csv(reactions_csv_, ".reactions.csv", time, ledger);
  for (std::size_t w = 0; w < writers_.size(); ++w)
    writers_[w]->resume(dir_, output_basename(scene_, w),
                        ResumePoint{time, frames[w], w < saved.states.size() ? saved.states[w] : std::string()});
  series_->save();
}

void RunOutputs::write_frame(std::size_t w, double now, std::size_t step) {
  StageTimer timer(times_, Stage::output);
  static const std::vector<GridField> none;
  const std::vector<GridField>& fields = writers_[w]->wants_grid_fields() ? grid_.project(domain_) : none;
  std::optional<MassLedger> ledger;
  if (species_) ledger = species_->mass_ledger(now);
  const PointSet& points = domain_.gathered_points();
  if (!writes_) {
    ++frames_[w];
    return;
  }
  series_->set_part(static_cast<int>(w));
  writers_[w]->write(OutputFrame{points, domain_.grid, step, now, fields, ledger ? &*ledger : nullptr, *series_});
  ++frames_[w];
}

void RunOutputs::write_rows(double now) {
  const std::optional<MassLedger> ledger = ledger_at(now);
  if (!writes_) return;
  if (ledger_.is_open()) {
    species_->write_ledger_row(ledger_, *ledger, false);
    ledger_.flush();
  }
  if (reactions_csv_.is_open()) {
    reactions_.write_row(reactions_csv_, now);
    reactions_csv_.flush();
  }
}

void RunOutputs::after_step(double now, std::size_t step, bool at_end) {
  if (dir_.empty()) return;
  last_step_ = step;
  bool wrote = false;
  for (std::size_t w = 0; w < writers_.size(); ++w) {
    if (now >= next_[w] - 1e-9 * interval_[w] || (at_end && written_step_[w] != step)) {
      write_frame(w, now, step);
      written_step_[w] = step;
      next_[w] = next_multiple(interval_[w], now);
      wrote = true;
    }
  }
  if (wrote && series_) series_->save();
  if (now >= next_row_ - 1e-9 * row_interval_ || (at_end && rows_step_ != step)) {
    write_rows(now);
    rows_step_ = step;
    next_row_ = next_multiple(row_interval_, now);
  }
}

void RunOutputs::close() {
  if (!writes_) return;
  for (auto& w : writers_) w->close();
}

}  // namespace suffuse::detail
