#include "tissue_trainer/core/integrate/step_control.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "frame_guard.h"

namespace tt {

void StepSizeController::restart() {
  proposed_ = initialStep();
  fresh_ = true;
  rejectedLast_ = false;
  started_ = true;
}

bool StepSizeController::judge(double h, const StepMeasure& measure, bool lastInFrame) {
  const bool keep = !adaptive() || keeps(h, measure);
  proposed_ = keep ? afterKeep(h, measure, lastInFrame) : afterReject(h, measure);
  if (keep) fresh_ = false;
  rejectedLast_ = !keep;
  return keep;
}

void StepSizeController::notConverged(double h, double factor) {
  proposed_ = h * factor;
  rejectedLast_ = true;
}

void StepSizeController::keepAtLeast(double planned) { proposed_ = std::max(proposed_, planned); }

FixedStepControl FixedStepControl::ofCount(int count) {
  FixedStepControl c;
  c.count_ = std::max(1, count);
  return c;
}

FixedStepControl FixedStepControl::ofLength(double length) {
  FixedStepControl c;
  c.length_ = length;
  return c;
}

int FixedStepControl::equalSteps(double frameTime, int divisor) const {
  if (length_ > 0.0) return detail::equalSubsteps(frameTime, length_ / divisor);
  return count_;
}

ErrorStepControl::ErrorStepControl(ErrorStepParams params)
    : params_(params), exponent_(1.0 / (params.estimatorOrder + 1)) {
  if (params_.estimatorOrder < 1 || !(params_.safety > 0.0 && params_.safety <= 1.0) ||
      !(params_.maxGrowth > 1.0) || !(params_.maxShrink > 1.0) || !(params_.minStep > 0.0) ||
      !(params_.initialStep > 0.0) || !(params_.maxStep > 0.0))
    throw std::invalid_argument(
        "error step control: needs estimator order >= 1, 0 < safety <= 1, growth and shrink "
        "limits > 1 and positive step lengths");
}

double ErrorStepControl::quotient(const StepMeasure& m) const {
  double safety = params_.safety;
  if (params_.newtonIterationLimit > 0) {
    const int k = params_.newtonIterationLimit;
    safety = std::min(params_.safety, params_.safety * (2 * k + 1) / (2.0 * k + m.iterations));
  }
  return std::clamp(std::pow(m.error, exponent_) / safety, 1.0 / params_.maxGrowth,
                    params_.maxShrink);
}

double ErrorStepControl::afterReject(double h, const StepMeasure& m) {
  // A first step that fails is far too long: the error says little about how far.
  return fresh() ? 0.1 * h : h / quotient(m);
}

double ErrorStepControl::afterKeep(double h, const StepMeasure& m, bool lastInFrame) {
  double q = quotient(m);
  double proposal = h / q;
  if (!fresh()) {
    // Gustafsson's predictive correction from the error ratio of the last two kept steps.
    const double predictive =
        std::clamp(keptStep_ / h * std::pow(m.error * m.error / keptError_, exponent_) /
                       params_.safety,
                   1.0 / params_.maxGrowth, params_.maxShrink);
    q = std::max(q, predictive);
    proposal = h / q;
  }
  keptStep_ = h;
  keptError_ = std::max(1e-2, m.error);
  if (rejectedLast()) proposal = std::min(proposal, h);  // no growth right after a rejection
  proposal = std::min(proposal, m.nextStepCap);
  const double growth = proposal / h;
  if (m.sameStepIsCheap && growth >= 1.0 && growth <= params_.holdBelowGrowth && !lastInFrame)
    proposal = h;
  return proposal;
}

HalvingDoublingControl::HalvingDoublingControl(HalvingDoublingParams params) : params_(params) {
  if (!(params_.lower < params_.upper) || !(params_.minStep > 0.0) ||
      !(params_.initialStep > 0.0) || !(params_.maxStep > 0.0))
    throw std::invalid_argument(
        "halving/doubling step control: needs lower < upper and positive step lengths");
}

double HalvingDoublingControl::measured(const StepMeasure& m) const {
  return params_.quantity == HalvingDoublingParams::Quantity::kError ? m.error
                                                                     : m.iterations;
}

bool HalvingDoublingControl::keeps(double h, const StepMeasure& m) const {
  if (params_.keepAtMinStep && h <= params_.minStep * (1.0 + 1e-9)) return true;
  return !(params_.rejectAboveUpper && !(measured(m) <= params_.upper));
}

double HalvingDoublingControl::halved(double h) const {
  return params_.keepAtMinStep ? std::max(0.5 * h, params_.minStep) : 0.5 * h;
}

double HalvingDoublingControl::afterKeep(double h, const StepMeasure& m, bool) {
  const double q = measured(m);
  // A doubling the method cannot take (its history is too short) waits.
  if (q <= params_.lower) return 2.0 * h <= m.nextStepCap * (1.0 + 1e-9) ? 2.0 * h : h;
  if (q > params_.upper) return halved(h);
  return h;
}

PowerLawStepControl::PowerLawStepControl(PowerLawStepParams params) : params_(params) {
  const PowerLawStepParams& p = params_;
  if (!(p.safety > 0.0 && p.safety <= 1.0) || !(p.growExponent > 0.0) ||
      !(p.shrinkExponent > 0.0) || !(p.maxGrowth > 1.0) || !(p.maxShrink > 1.0) ||
      !(p.initialStep > 0.0) || !(p.minStep > 0.0) || !(p.maxStep >= p.minStep))
    throw std::invalid_argument(
        "power-law step control: needs 0 < safety <= 1, positive exponents, growth and shrink "
        "limits > 1 and positive step lengths with min <= max");
}

double PowerLawStepControl::afterKeep(double h, const StepMeasure& m, bool) {
  // e = 0 (an exactly polynomial motion) grows by the limit; pow would give infinity.
  const double growth =
      m.error > 0.0 ? std::min(params_.maxGrowth, params_.safety * std::pow(m.error, -params_.growExponent))
                    : params_.maxGrowth;
  return std::min(h * growth, m.nextStepCap);
}

double PowerLawStepControl::afterReject(double h, const StepMeasure& m) {
  const double shrink = params_.safety * std::pow(m.error, -params_.shrinkExponent);
  return h * std::max(shrink, 1.0 / params_.maxShrink);
}

}  // namespace tt
