#pragma once
// Tool-tissue force metrics from time-stamped force samples (f0 of the contact model when in
// contact, else zero). Each sample holds until the next one (zero-order hold, as the haptic
// loop renders it); the last sample gets no weight, nor does a gap longer than max_gap.
#include <cstddef>

#include <Eigen/Core>

namespace tt {

struct ForceMetrics {
  double span = 0.0;             // s, weighted time (first to last sample, gaps excluded)
  double contactTime = 0.0;      // s, weighted time in contact
  double integral = 0.0;         // N s, integral of |f| dt
  double squaredIntegral = 0.0;  // N^2 s, integral of |f|^2 dt
  double peak = 0.0;             // N, largest |f| of any sample
  double variation = 0.0;        // N, sum of |f[i+1] - f[i]| (vector) over weighted intervals
  std::size_t events = 0;        // excessive-force events: |f| rises above the threshold
  double excessiveTime = 0.0;    // s, weighted time with |f| above the threshold
  double excessIntegral = 0.0;   // N s, integral of max(0, |f| - threshold) dt
};

class ForceStats {
 public:
  ForceStats(double threshold, double maxGap) : threshold_(threshold), maxGap_(maxGap) {}

  // Accepts a sample later than the previous one (the caller checks order and finiteness).
  // afterGap: the source restarted before this sample, so the previous one holds over no time
  // (as a gap longer than max_gap).
  void add(double t, const Eigen::Vector3d& f, bool inContact, bool afterGap = false);
  const ForceMetrics& metrics() const { return m_; }

 private:
  double threshold_, maxGap_;
  ForceMetrics m_;
  bool any_ = false, lastContact_ = false, lastAbove_ = false;
  double lastT_ = 0.0;
  Eigen::Vector3d lastF_ = Eigen::Vector3d::Zero();
};

}  // namespace tt
