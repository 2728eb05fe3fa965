#include "tissue_trainer/core/haptics/force_extrapolator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tt {

ForceExtrapolator::ForceExtrapolator(const ExtrapolatorOptions& options) : options_(options) {
  if (!(options.blendTime >= 0.0) || !std::isfinite(options.blendTime))
    throw std::invalid_argument("ForceExtrapolator: blendTime must be finite and >= 0");
  if (!(options.maxStiffness > 0.0))
    throw std::invalid_argument("ForceExtrapolator: maxStiffness must be > 0");
  if (options.restartAfterStale < 0)
    throw std::invalid_argument("ForceExtrapolator: restartAfterStale must be >= 0");
}

LinearForceField ForceExtrapolator::fieldOf(const ContactModel& model) const {
  LinearForceField field;
  field.x0 = model.x0;
  if (!model.inContact) return field;
  field.f0 = model.f0;
  if (options_.mode == ExtrapolationMode::kLinear) field.K = model.K;
  return field;
}

double ForceExtrapolator::blendWeight(double tNow) const {
  if (options_.blendTime <= 0.0) return 1.0;
  const double s = (tNow - blendStart_) / options_.blendTime;
  if (!(s > 0.0)) return 0.0;  // also for a NaN time: keep the old field
  if (s >= 1.0) return 1.0;
  return options_.blendShape == BlendShape::kSmoothstep ? s * s * (3.0 - 2.0 * s) : s;
}

ModelVerdict ForceExtrapolator::submit(const ContactModel& model, double tReceive,
                                       const Eigen::Vector3d& xDevice) {
  const bool tooStiff = model.K.allFinite() && model.K.norm() > options_.maxStiffness;
  if (!model.isFinite() || !std::isfinite(tReceive) || tooStiff) {
    ++counters_.malformed;
    consecutiveStale_ = 0;
    return ModelVerdict::kMalformed;
  }
  if (hasModel_ && model.sequence <= lastSequence_) {
    ++counters_.staleSequence;
    if (options_.restartAfterStale == 0 || ++consecutiveStale_ < options_.restartAfterStale)
      return ModelVerdict::kStaleSequence;
    reset();  // the simulation restarted: this model fades in from zero
    ++counters_.restarts;
  }
  consecutiveStale_ = 0;
  // Blend from what the hand feels right now (itself possibly mid-blend), so a model arriving
  // mid-blend does not make a step either. The first model fades in from zero.
  const LinearForceField next = fieldOf(model);
  const LinearForceField felt = field(tReceive);
  if (options_.blendMethod == BlendMethod::kFields) {
    from_ = felt;
  } else {
    // A broken device reading must not cost a good model: take the jump at x0 instead.
    const Eigen::Vector3d& xs = xDevice.allFinite() ? xDevice : next.x0;
    offset_ = felt.at(xs) - next.at(xs);
  }
  to_ = next;
  blendStart_ = tReceive;
  lastReceive_ = tReceive;
  lastSequence_ = model.sequence;
  hasModel_ = true;
  ++counters_.accepted;
  return ModelVerdict::kAccepted;
}

Eigen::Vector3d ForceExtrapolator::force(const Eigen::Vector3d& x, double tNow) const {
  if (!hasModel_) return Eigen::Vector3d::Zero();
  const double w = blendWeight(tNow);
  if (w >= 1.0) return to_.at(x);
  if (options_.blendMethod == BlendMethod::kOffset) return to_.at(x) + (1.0 - w) * offset_;
  return (1.0 - w) * from_.at(x) + w * to_.at(x);
}

LinearForceField ForceExtrapolator::field(double tNow) const {
  if (!hasModel_) return LinearForceField();
  const double w = blendWeight(tNow);
  if (options_.blendMethod == BlendMethod::kFields) return LinearForceField::blend(from_, to_, w);
  LinearForceField f = to_;
  if (w < 1.0) f.f0 += (1.0 - w) * offset_;
  return f;
}

double ForceExtrapolator::modelAge(double tNow) const {
  if (!hasModel_) return std::numeric_limits<double>::infinity();
  return tNow - lastReceive_;
}

void ForceExtrapolator::reset() {
  from_ = LinearForceField();
  to_ = LinearForceField();
  offset_.setZero();
  blendStart_ = lastReceive_ = 0.0;
  lastSequence_ = 0;
  consecutiveStale_ = 0;
  hasModel_ = false;
}

}  // namespace tt
