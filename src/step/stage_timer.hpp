// Private to step/: the scoped timer of a step's stages (StageTimes).
#pragma once

#include <chrono>

namespace cbps::detail {

/// Adds the seconds from its construction to its end to `into`: one stage's wall time.
class StageTimer {
 public:
  explicit StageTimer(double& into) : into_(into), start_(std::chrono::steady_clock::now()) {}
  ~StageTimer() {
    into_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  double& into_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace cbps::detail
