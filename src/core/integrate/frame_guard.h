#pragma once
// Shared by the integrators: remembers the state at the start of a frame so that a step
// that produced a non-finite value can be undone, and times the frame.
#include <chrono>
#include <cmath>
#include <string>

#include "tissue_trainer/core/integrate/integrator.h"

namespace tt {
namespace detail {

class FrameGuard {
 public:
  explicit FrameGuard(const State& s) : start_(s), clock_(std::chrono::steady_clock::now()) {}

  // True when the state holds only finite numbers.
  static bool finite(const State& s) { return s.x.allFinite() && s.v.allFinite(); }

  // Puts back the frame's initial state and marks the report failed.
  void restore(State& s, StepReport& report, const std::string& why) const {
    s = start_;
    report.ok = false;
    report.failure = why;
  }

  void finish(StepReport& report) const {
    report.wallSeconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - clock_).count();
  }

  const State& start() const { return start_; }

 private:
  State start_;
  std::chrono::steady_clock::time_point clock_;
};

// Number of equal substeps of at most maxStep that make up frameTime (at least one).
inline int equalSubsteps(double frameTime, double maxStep) {
  if (!(maxStep > 0.0) || !(frameTime > 0.0)) return 1;
  const double n = std::ceil(frameTime / maxStep * (1.0 - 1e-12));
  return n < 1.0 ? 1 : static_cast<int>(n);
}

// End time of substep i of n within a frame; the last one ends exactly at the frame's end.
inline double substepEnd(double frameStart, double frameTime, int i, int n) {
  return i + 1 == n ? frameStart + frameTime : frameStart + frameTime * (i + 1) / n;
}

}  // namespace detail
}  // namespace tt
