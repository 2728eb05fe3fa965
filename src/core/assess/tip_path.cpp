#include "tissue_trainer/core/assess/tip_path.h"

#include <algorithm>
#include <cmath>

namespace tt {

namespace {

// x[j] for j in [-(n-1), 2(n-1)]: the path point-reflected about its end points, which keeps
// straight lines straight (and a start from rest, x0 + c t^3, a smooth cubic).
Eigen::Vector3d reflectedAt(const std::vector<Eigen::Vector3d>& x, int j) {
  const int n = static_cast<int>(x.size());
  if (j < 0) return 2.0 * x[0] - x[-j];
  if (j >= n) return 2.0 * x[n - 1] - x[2 * (n - 1) - j];
  return x[j];
}

}  // namespace

std::vector<Eigen::Vector3d> smoothPath(const std::vector<Eigen::Vector3d>& x, double sigmaSamples) {
  const int n = static_cast<int>(x.size());
  if (!(sigmaSamples > 0.0) || n < 3) return x;
  const int r = std::min(static_cast<int>(std::ceil(3.0 * sigmaSamples)), n - 1);
  std::vector<double> w(2 * r + 1);
  double sum = 0.0;
  for (int i = -r; i <= r; ++i) sum += w[i + r] = std::exp(-0.5 * i * i / (sigmaSamples * sigmaSamples));
  for (double& v : w) v /= sum;
  std::vector<Eigen::Vector3d> out(x.size(), Eigen::Vector3d::Zero());
  for (int k = 0; k < n; ++k)
    for (int i = -r; i <= r; ++i) out[k] += w[i + r] * reflectedAt(x, k + i);
  return out;
}

TipPath::TipPath(const AssessmentSettings& settings)
    : settings_(settings), h_(1.0 / settings.resampleRate) {}

void TipPath::startSegment(double t) {
  segments_.push_back(Segment{{}, t + 0.5 * h_});
  segmentStart_ = t;
  windowIndex_ = 0;
  windowSum_.setZero();
}

void TipPath::integrate(double t0, const Eigen::Vector3d& p0, double t1, const Eigen::Vector3d& p1) {
  auto lerp = [&](double t) -> Eigen::Vector3d { return p0 + (p1 - p0) * ((t - t0) / (t1 - t0)); };
  double a = t0;
  Eigen::Vector3d pa = p0;
  while (true) {
    const double end = segmentStart_ + static_cast<double>(windowIndex_ + 1) * h_;
    if (t1 < end) {
      windowSum_ += 0.5 * (t1 - a) * (pa + p1);
      return;
    }
    const Eigen::Vector3d pe = lerp(end);
    windowSum_ += 0.5 * (end - a) * (pa + pe);
    segments_.back().grid.push_back(windowSum_ / h_);
    windowSum_.setZero();
    ++windowIndex_;
    a = end;
    pa = pe;
    if (t1 == end) return;
  }
}

void TipPath::add(double t, const Eigen::Vector3d& p) {
  if (!any_) {
    any_ = true;
    startSegment(t);
  } else {
    pathLength_ += (p - lastP_).norm();
    if (t - lastT_ > settings_.maxGap)
      startSegment(t);
    else
      integrate(lastT_, lastP_, t, p);
  }
  lastT_ = t;
  lastP_ = p;
}

TipPathMetrics TipPath::metrics() const {
  TipPathMetrics m;
  m.pathLength = pathLength_;
  const double h = h_;
  bool anyMovement = false;
  double firstStart = 0.0, lastEnd = 0.0;
  for (const Segment& seg : segments_) {
    const std::vector<Eigen::Vector3d> x = smoothPath(seg.grid, settings_.smoothingTime / h);
    const int n = static_cast<int>(x.size());
    m.gridPoints += x.size();
    for (int k = 0; k + 1 < n; ++k) m.pathLengthSmoothed += (x[k + 1] - x[k]).norm();
    if (n < 3) continue;  // derivatives need two neighbours (reflected at the ends)
    auto at = [&](int j) { return reflectedAt(x, j); };
    m.smoothedDuration += n * h;  // the windows cover n h seconds
    bool moving = false;
    for (int k = 0; k < n; ++k) {
      const double time = seg.firstCentre + k * h;
      const double speed = (at(k + 1) - at(k - 1)).norm() / (2.0 * h);
      ++m.speedPoints;
      if (!moving && speed > settings_.movementSpeedStart) {
        moving = true;
        ++m.movements;
        if (!anyMovement) firstStart = time;
        anyMovement = true;
      } else if (moving && speed < settings_.movementSpeedStop) {
        moving = false;
        lastEnd = time;
      }
      if (moving) lastEnd = time;  // a movement still going at the segment's end ends there
    }
    for (int k = 0; k < n; ++k) {
      const Eigen::Vector3d jerk = (at(k + 2) - 2.0 * at(k + 1) + 2.0 * at(k - 1) - at(k - 2)) / (2.0 * h * h * h);
      m.squaredJerkIntegral += jerk.squaredNorm() * h;
      m.jerkTime += h;
    }
  }
  if (anyMovement) m.motionTime = lastEnd - firstStart;
  return m;
}

}  // namespace tt
