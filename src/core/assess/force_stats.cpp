#include "tissue_trainer/core/assess/force_stats.h"

#include <algorithm>

namespace tt {

void ForceStats::add(double t, const Eigen::Vector3d& f, bool inContact, bool afterGap) {
  const double magnitude = f.norm();
  const bool above = magnitude > threshold_;
  if (any_ && !afterGap) {
    const double dt = t - lastT_;
    if (dt <= maxGap_) {  // the previous sample holds over [lastT_, t)
      const double last = lastF_.norm();
      m_.span += dt;
      if (lastContact_) m_.contactTime += dt;
      m_.integral += last * dt;
      m_.squaredIntegral += last * last * dt;
      if (lastAbove_) {
        m_.excessiveTime += dt;
        m_.excessIntegral += (last - threshold_) * dt;
      }
      m_.variation += (f - lastF_).norm();
    }
  }
  if (above && !lastAbove_) ++m_.events;
  m_.peak = std::max(m_.peak, magnitude);
  any_ = true;
  lastT_ = t;
  lastF_ = f;
  lastContact_ = inContact;
  lastAbove_ = above;
}

}  // namespace tt
