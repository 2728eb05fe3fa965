#pragma once
// Timing statistics of a periodic loop from its tick timestamps (s): achieved rate, tick
// period percentiles and overruns, for the haptic bridge's status report.
#include <cstddef>
#include <cstdint>
#include <vector>

namespace tt {

struct LoopStats {
  std::size_t ticks = 0;    // timestamps summarised
  double rate = 0.0;        // (ticks - 1) / (last - first), Hz; 0 with fewer than two ticks
  double periodP50 = 0.0;   // s, nearest-rank percentiles of the tick-to-tick periods
  double periodP99 = 0.0;
  double periodMax = 0.0;
  std::size_t overruns = 0;  // periods longer than the overrun threshold
};

// Nearest-rank percentile (p in [0, 1]) of values, which it reorders; 0 for none.
double nearestRankPercentile(std::vector<double>& values, double p);

// Statistics of tick timestamps in the order they were taken.
LoopStats computeLoopStats(const std::vector<double>& tickTimes, double overrunThreshold);

// The last `capacity` tick times of a running loop. record() neither allocates nor sorts, so
// it can sit in the real-time loop; summary() sorts a preallocated copy.
class LoopStatsWindow {
 public:
  // Throws std::invalid_argument for capacity < 2 or a non-positive threshold.
  LoopStatsWindow(std::size_t capacity, double overrunThreshold);

  void record(double tickTime);  // non-finite times are ignored
  LoopStats summary() const;

  std::uint64_t totalTicks() const { return totalTicks_; }
  std::uint64_t totalOverruns() const { return totalOverruns_; }  // since construction

 private:
  std::vector<double> times_;  // ring buffer
  std::size_t next_ = 0;
  std::size_t filled_ = 0;
  double overrunThreshold_;
  double lastTime_ = 0.0;
  std::uint64_t totalTicks_ = 0;
  std::uint64_t totalOverruns_ = 0;
  mutable std::vector<double> scratch_;
};

}  // namespace tt
