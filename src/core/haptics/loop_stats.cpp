#include "tissue_trainer/core/haptics/loop_stats.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tt {

namespace {

// Statistics of tick-to-tick periods (reordered here) spanning `span` seconds.
LoopStats summarisePeriods(std::vector<double>& periods, double span, double overrunThreshold) {
  LoopStats s;
  if (periods.empty()) return s;
  s.ticks = periods.size() + 1;
  s.rate = span > 0.0 ? static_cast<double>(periods.size()) / span : 0.0;
  s.overruns = static_cast<std::size_t>(
      std::count_if(periods.begin(), periods.end(), [&](double p) { return p > overrunThreshold; }));
  s.periodMax = *std::max_element(periods.begin(), periods.end());
  s.periodP99 = nearestRankPercentile(periods, 0.99);
  s.periodP50 = nearestRankPercentile(periods, 0.50);
  return s;
}

}  // namespace

double nearestRankPercentile(std::vector<double>& values, double p) {
  if (values.empty()) return 0.0;
  const double n = static_cast<double>(values.size());
  const std::size_t rank = static_cast<std::size_t>(std::max(1.0, std::ceil(p * n)));
  const auto nth = values.begin() + static_cast<std::ptrdiff_t>(std::min(rank, values.size()) - 1);
  std::nth_element(values.begin(), nth, values.end());
  return *nth;
}

LoopStats computeLoopStats(const std::vector<double>& tickTimes, double overrunThreshold) {
  LoopStats s;
  s.ticks = tickTimes.size();
  if (tickTimes.size() < 2) return s;
  std::vector<double> periods(tickTimes.size() - 1);
  for (std::size_t i = 1; i < tickTimes.size(); ++i) periods[i - 1] = tickTimes[i] - tickTimes[i - 1];
  return summarisePeriods(periods, tickTimes.back() - tickTimes.front(), overrunThreshold);
}

LoopStatsWindow::LoopStatsWindow(std::size_t capacity, double overrunThreshold)
    : times_(capacity), overrunThreshold_(overrunThreshold) {
  if (capacity < 2) throw std::invalid_argument("LoopStatsWindow: capacity must be >= 2");
  if (!(overrunThreshold > 0.0))
    throw std::invalid_argument("LoopStatsWindow: overrunThreshold must be > 0");
  scratch_.reserve(capacity - 1);
}

void LoopStatsWindow::record(double tickTime) {
  if (!std::isfinite(tickTime)) return;  // the safety filter counts clock faults
  if (totalTicks_ > 0 && tickTime - lastTime_ > overrunThreshold_) ++totalOverruns_;
  lastTime_ = tickTime;
  ++totalTicks_;
  times_[next_] = tickTime;
  next_ = (next_ + 1) % times_.size();
  filled_ = std::min(filled_ + 1, times_.size());
}

LoopStats LoopStatsWindow::summary() const {
  LoopStats s;
  s.ticks = filled_;
  if (filled_ < 2) return s;
  const std::size_t oldest = (next_ + times_.size() - filled_) % times_.size();
  auto at = [&](std::size_t i) { return times_[(oldest + i) % times_.size()]; };
  scratch_.clear();
  for (std::size_t i = 1; i < filled_; ++i) scratch_.push_back(at(i) - at(i - 1));
  return summarisePeriods(scratch_, at(filled_ - 1) - at(0), overrunThreshold_);
}

}  // namespace tt
