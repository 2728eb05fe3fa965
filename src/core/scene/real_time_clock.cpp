#include "tissue_trainer/core/scene/real_time_clock.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

namespace tt {

RealTimeClock::RealTimeClock(double nominalStep, double maxStep) : nominal_(nominalStep), max_(maxStep) {
  if (!(std::isfinite(nominalStep) && nominalStep > 0.0))
    throw std::invalid_argument("real-time clock: the nominal step must be finite and > 0, got " +
                                std::to_string(nominalStep));
  if (!(std::isfinite(maxStep) && maxStep >= nominalStep))
    throw std::invalid_argument("real-time clock: the maximum step must be finite and >= the nominal step " +
                                std::to_string(nominalStep) + " s, got " + std::to_string(maxStep));
}

ClockStep RealTimeClock::next(double wallNow) {
  if (!started_) {
    started_ = true;
    origin_ = wallNow;
    simulated_ = 0.0;
    return {nominal_, 0.0};
  }
  // The frame that starts at wallNow brings the simulation to the end of its own period.
  const double wanted = (wallNow - origin_) + nominal_ - simulated_;
  ClockStep s;
  s.step = std::max(nominal_, wanted);
  if (s.step > max_) {
    s.dropped = s.step - max_;
    s.step = max_;
    origin_ += s.dropped;  // the schedule gives that wall time up
    totalDropped_ += s.dropped;
  }
  return s;
}

void RealTimeClock::advanced(double simulated) {
  if (std::isfinite(simulated) && simulated > 0.0) simulated_ += simulated;
}

double RealTimeClock::nextStart() const { return origin_ + simulated_; }

void RealTimeClock::restart() { started_ = false; }

}  // namespace tt
