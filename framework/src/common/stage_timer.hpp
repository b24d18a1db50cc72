#pragma once
// The one timer of the step: adds the wall time of a scope to a stage.
#include <chrono>

#include "suffuse/simulation.hpp"

namespace suffuse::detail {

class StageTimer {
 public:
  StageTimer(StageTimes& times, Stage stage) : total_(times[stage]), start_(Clock::now()) {}
  ~StageTimer() { total_ += std::chrono::duration<double>(Clock::now() - start_).count(); }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  using Clock = std::chrono::steady_clock;
  double& total_;
  Clock::time_point start_;
};

}  // namespace suffuse::detail
