#pragma once
// The frames of a scene run against the wall clock (the simulation node): simulated time
// tracks wall time. A frame that starts on time advances the nominal step; a frame that starts
// late (the one before it overran) covers the wall time that passed since the schedule wanted
// it, so the next frame starts at once and is longer, up to the maximum step. Wall time a frame
// cannot cover within the maximum step is dropped: the simulation then runs behind real time
// by that much, is never behind by more than the maximum step at the start of a frame, and
// reports what it dropped.
//
// Wall times are seconds of a monotonic clock; the class keeps no clock of its own, so that
// the rule can be checked with made-up times.
namespace tt {

struct ClockStep {
  double step = 0.0;     // simulated time this frame is to advance (s)
  double dropped = 0.0;  // wall time this frame could not cover within the maximum step (s)
};

class RealTimeClock {
 public:
  // Throws std::invalid_argument unless 0 < nominalStep <= maxStep, both finite.
  RealTimeClock(double nominalStep, double maxStep);

  // At the start of a frame, at wall time `wallNow`: the step it is to take. The first frame
  // after construction or restart() takes the nominal step and sets the schedule's origin.
  // A frame that starts early (timer jitter) still takes the nominal step, never less.
  ClockStep next(double wallNow);
  // What the frame really advanced: its step, or less when it failed (the state was restored:
  // 0) or was cut short. The next frame covers the rest.
  void advanced(double simulated);
  // Wall time the next frame is due; at or before now: start it at once.
  double nextStart() const;
  // The schedule starts again at the next frame (after a reset or a new scene).
  void restart();

  double nominalStep() const { return nominal_; }
  double maxStep() const { return max_; }
  double totalDropped() const { return totalDropped_; }  // s of wall time, since construction

 private:
  double nominal_, max_;
  bool started_ = false;
  double origin_ = 0.0;     // wall time at which the simulated time of the schedule was 0
  double simulated_ = 0.0;  // simulated time advanced since the origin
  double totalDropped_ = 0.0;
};

}  // namespace tt
