#include "tissue_trainer/core/haptics/safety_filter.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tt {

namespace {

// Below this the gain is taken as zero, so that round-off in the summed tick lengths cannot
// leave a residue of force one tick after the fade time.
constexpr double kGainSnap = 1e-9;
constexpr double kMaxFadeTime = 0.05;

bool positiveFinite(double v) { return std::isfinite(v) && v > 0.0; }

// The point of the closed ball of radius r nearest to v (r >= 0).
Eigen::Vector3d projectOntoBall(const Eigen::Vector3d& v, double r) {
  return r > 0.0 ? clampMagnitude(v, r) : Eigen::Vector3d::Zero();
}

}  // namespace

Eigen::Vector3d clampMagnitude(const Eigen::Vector3d& v, double m) {
  const double norm2 = v.squaredNorm();
  if (norm2 <= m * m) return v;
  if (std::isfinite(norm2) && norm2 > 1e-300) return v * (m / std::sqrt(norm2));
  const double largest = v.cwiseAbs().maxCoeff();
  if (largest == 0.0) return v;
  const Eigen::Vector3d unitish = v / largest;  // no overflow in the norm of huge vectors
  const double norm = unitish.norm();           // |v| = largest * norm
  if (largest <= m / norm) return v;
  return unitish * (m / norm);
}

SafetyFilter::SafetyFilter(const SafetyOptions& options) : options_(options) {
  const SafetyOptions& o = options;
  if (!positiveFinite(o.maxForce) || !positiveFinite(o.maxForceRate) ||
      !positiveFinite(o.modelTimeout) || !positiveFinite(o.fadeTime) ||
      !positiveFinite(o.resumeTime) || !positiveFinite(o.nominalPeriod))
    throw std::invalid_argument("SafetyFilter: every option must be finite and > 0");
  if (o.fadeTime > kMaxFadeTime)
    throw std::invalid_argument("SafetyFilter: fadeTime must be <= 0.05 s");
  if (o.maxForceRate * o.fadeTime < o.maxForce)
    throw std::invalid_argument(
        "SafetyFilter: maxForceRate * fadeTime must be >= maxForce, or the fade could not "
        "reach zero within fadeTime under the rate limit");
}

void SafetyFilter::reset() {
  output_.setZero();
  gain_ = 0.0;
  lastTime_ = 0.0;
  started_ = false;
  stale_ = false;
}

// The length of this tick. An unusable time (non-finite, or not after the previous tick)
// counts as a fault and as one nominal period.
double SafetyFilter::tickLength(double tNow, bool& timeOk) {
  timeOk = std::isfinite(tNow) && (!started_ || tNow > lastTime_);
  if (!timeOk) {
    ++counters_.timeFaults;
    if (std::isfinite(tNow)) lastTime_ = tNow;  // the clock went back: follow it
    return options_.nominalPeriod;
  }
  const double dt = started_ ? tNow - lastTime_ : 0.0;
  lastTime_ = tNow;
  started_ = true;
  return dt;
}

void SafetyFilter::updateGain(double dt, bool ok) {
  if (ok) {
    gain_ = std::min(1.0, gain_ + dt / options_.resumeTime);
  } else {
    gain_ = std::max(0.0, gain_ - dt / options_.fadeTime);
    if (gain_ < kGainSnap) gain_ = 0.0;
  }
}

Eigen::Vector3d SafetyFilter::step(const Eigen::Vector3d& requested, double tNow, double modelAge,
                                   bool enabled) {
  ++counters_.ticks;
  bool timeOk = true;
  const double dt = tickLength(tNow, timeOk);

  const bool stale = !(modelAge <= options_.modelTimeout);  // NaN and +inf are stale
  if (stale && !stale_) ++counters_.watchdogTrips;
  stale_ = stale;

  const double capBefore = gain_ * options_.maxForce;
  updateGain(dt, enabled && !stale && timeOk);
  const double cap = gain_ * options_.maxForce;

  Eigen::Vector3d target;
  if (!requested.allFinite() || !timeOk) {
    if (!requested.allFinite()) ++counters_.nonFiniteInputs;
    const double shrink = options_.maxForce / options_.fadeTime * dt;
    target = clampMagnitude(output_, std::max(0.0, output_.norm() - shrink));
  } else {
    target = clampMagnitude(requested, options_.maxForce);
    if (target != requested) ++counters_.forceClamped;
    target *= gain_;
  }

  // Rate limit, keeping back what projecting onto the shrinking bound may move the output:
  // the projection moves it by at most (capBefore - cap), so the total stays <= rate * dt.
  const double budget =
      std::max(0.0, options_.maxForceRate * dt - std::max(0.0, capBefore - cap));
  const Eigen::Vector3d change = target - output_;
  const Eigen::Vector3d limited = clampMagnitude(change, budget);
  if (limited != change) ++counters_.rateLimited;
  output_ = projectOntoBall(output_ + limited, cap);
  return output_;
}

}  // namespace tt
