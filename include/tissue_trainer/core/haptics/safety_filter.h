#pragma once
// The last stage before the haptic device. Each tick it
//  - replaces a non-finite requested force by the last output shrunk toward zero,
//  - clamps the force magnitude to maxForce, keeping its direction,
//  - scales it by a gain that fades to zero within fadeTime when the contact model is older
//    than modelTimeout (watchdog), when the enable/deadman input is false, or when the clock
//    is unusable, and comes back over resumeTime once all is well,
//  - limits the change of the output to maxForceRate * dt.
// Guarantees, for any inputs: the output is finite, |F| <= maxForce, |F_k - F_k-1| <=
// maxForceRate * dt_k, and it is exactly zero at every tick at least fadeTime after the first
// tick of a watchdog trip or of a disable (and stays zero while the condition lasts).
// These hold because the magnitude bound shrinks no faster than the rate limit allows
// (maxForceRate * fadeTime >= maxForce is required) and the output is projected onto it.
// Time is an explicit input; nothing here reads a clock.
#include <cstdint>

#include <Eigen/Core>

namespace tt {

struct SafetyOptions {
  double maxForce = 5.0;         // N
  double maxForceRate = 1000.0;  // N/s
  double modelTimeout = 0.1;     // s: an older contact model trips the watchdog
  double fadeTime = 0.03;        // s, at most 0.05: full force to zero
  double resumeTime = 0.1;       // s: gain from zero back to one
  double nominalPeriod = 0.001;  // s: the tick length assumed when the clock is unusable
};

struct SafetyCounters {
  std::uint64_t ticks = 0;
  std::uint64_t nonFiniteInputs = 0;  // requested force had a NaN or Inf
  std::uint64_t timeFaults = 0;       // tick time non-finite or not after the previous one
  std::uint64_t watchdogTrips = 0;    // transitions from fresh to stale contact model
  std::uint64_t forceClamped = 0;     // ticks where |requested| exceeded maxForce
  std::uint64_t rateLimited = 0;      // ticks where the rate limit changed the output
};

// v scaled down to magnitude m if longer, direction kept; safe for huge finite components.
Eigen::Vector3d clampMagnitude(const Eigen::Vector3d& v, double m);

class SafetyFilter {
 public:
  // Throws std::invalid_argument unless every option is finite and positive,
  // fadeTime <= 0.05 s and maxForceRate * fadeTime >= maxForce.
  explicit SafetyFilter(const SafetyOptions& options = {});

  // One tick: requested force (N), tick time (s), age of the contact model (s; +inf or NaN
  // when there is none), enable/deadman input. Returns the force to send.
  Eigen::Vector3d step(const Eigen::Vector3d& requested, double tNow, double modelAge, bool enabled);

  const Eigen::Vector3d& output() const { return output_; }
  double gain() const { return gain_; }
  bool watchdogTripped() const { return stale_; }
  const SafetyCounters& counters() const { return counters_; }
  const SafetyOptions& options() const { return options_; }

  // Back to the initial state: zero output, zero gain, no previous tick.
  void reset();

 private:
  double tickLength(double tNow, bool& timeOk);
  void updateGain(double dt, bool ok);

  SafetyOptions options_;
  Eigen::Vector3d output_ = Eigen::Vector3d::Zero();
  double gain_ = 0.0;  // starts at zero: the force fades in after start-up
  double lastTime_ = 0.0;
  bool started_ = false;
  bool stale_ = false;
  SafetyCounters counters_;
};

}  // namespace tt
