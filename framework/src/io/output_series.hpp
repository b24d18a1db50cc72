#pragma once
// The run's VTK collection <scene>.pvd: every file the writers list, with its
// simulation time and the writer's part number, rewritten atomically after
// each output step so that a run stopped at any point leaves a readable series.
#include <filesystem>
#include <string>
#include <vector>

#include "suffuse/writer.hpp"

namespace suffuse::detail {

class PvdSeries final : public OutputSeries {
 public:
  // A new, empty collection (written at once, so the series exists from the start).
  PvdSeries(std::filesystem::path file);
  // A restarted run's: the entries of the existing file up to `time` (plus
  // round-off); later ones are dropped. A missing file is an error.
  static PvdSeries resumed(std::filesystem::path file, double time);

  // The writer whose files add() lists next (its part number).
  void set_part(int part) { part_ = part; }
  void add(const std::string& file, double time) override;
  // Rewrites the file if anything was added since the last save.
  void save();
  bool empty() const { return entries_.empty(); }

 private:
  struct Entry {
    double time;
    int part;
    std::string file;
  };
  std::filesystem::path file_;
  std::vector<Entry> entries_;
  int part_ = 0;
  bool changed_ = true;
};

}  // namespace suffuse::detail
