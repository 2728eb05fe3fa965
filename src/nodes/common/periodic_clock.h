#pragma once
// Absolute-deadline periodic waiting on CLOCK_MONOTONIC (clock_nanosleep TIMER_ABSTIME), so
// that the period does not drift with the work done in each tick, and real-time scheduling
// for the calling thread when the system permits it.
#include <cstdint>
#include <ctime>
#include <string>

namespace tt_nodes {

// CLOCK_MONOTONIC in seconds: the bridge's clock for ticks, model and device receive times.
double monotonicSeconds();

class PeriodicClock {
 public:
  explicit PeriodicClock(double periodSeconds);

  // Sleeps until the next deadline. A tick more than `maxLag` periods late does not run the
  // missed ticks in a burst: the deadlines restart from now. Returns true if it restarted.
  bool waitNext(int maxLag = 5);

 private:
  std::int64_t periodNs_;
  timespec next_{};
};

// Tries SCHED_FIFO at `priority` for the calling thread. Returns an empty string on success,
// otherwise why it was refused (the thread keeps its normal scheduling).
std::string tryRealtime(int priority);

}  // namespace tt_nodes
