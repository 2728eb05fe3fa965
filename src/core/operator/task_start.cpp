#include "tissue_trainer/core/operator/task_start.h"

#include <cmath>
#include <stdexcept>
#include <string>

namespace tt {

TaskStart::TaskStart(double waitTimeout, double startDelay)
    : waitTimeout_(waitTimeout), startDelay_(startDelay) {
  if (!(std::isfinite(waitTimeout) && waitTimeout >= 0.0))
    throw std::invalid_argument("task start: expected a wait timeout >= 0 s, got " + std::to_string(waitTimeout));
  if (!(std::isfinite(startDelay) && startDelay >= 0.0))
    throw std::invalid_argument("task start: expected a start delay >= 0 s, got " + std::to_string(startDelay));
  wait_ = waitTimeout > 0.0 ? Wait::kWaiting : Wait::kNoWait;
}

double TaskStart::taskTime(double elapsed, bool simulationSeen) {
  if (wait_ == Wait::kWaiting) {
    if (simulationSeen) wait_ = Wait::kSimulation;
    else if (elapsed >= waitTimeout_) wait_ = Wait::kTimedOut;
    else return -startDelay_ - (waitTimeout_ - elapsed);  // still waiting: before the hold
    waitEnded_ = elapsed;
  }
  return elapsed - waitEnded_ - startDelay_;
}

}  // namespace tt
