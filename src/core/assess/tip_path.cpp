#include "tissue_trainer/core/assess/tip_path.h"

#include <algorithm>
#include <cmath>

namespace tt {

namespace {

// A movement is widened until its speed falls to this fraction of its peak (the tip is at
// rest; a minimum-jerk reach is there within 1.6 % of its duration from either end).
constexpr double kRestFraction = 1e-3;

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

std::vector<MovementSpan> segmentMovements(const std::vector<double>& speed, double h,
                                          const AssessmentSettings& settings) {
  const int n = static_cast<int>(speed.size());
  std::vector<MovementSpan> raw;
  bool moving = false;
  for (int k = 0; k < n; ++k) {
    if (!moving && speed[k] > settings.movementSpeedStart) {
      moving = true;
      raw.push_back(MovementSpan{k, n - 1});  // a movement still going at the end ends there
    } else if (moving && speed[k] < settings.movementSpeedStop) {
      moving = false;
      raw.back().last = k;
    }
  }
  std::vector<MovementSpan> spans;
  for (const MovementSpan& m : raw) {
    if (!spans.empty() && (m.first - spans.back().last) * h < settings.movementMinPause)
      spans.back().last = m.last;  // an arrest inside the movement
    else
      spans.push_back(m);
  }
  for (std::size_t i = 0; i < spans.size(); ++i) {
    MovementSpan& m = spans[i];
    double peak = 0.0;
    for (int k = m.first; k <= m.last; ++k) peak = std::max(peak, speed[k]);
    const double rest = kRestFraction * peak;
    const int lower = i > 0 ? spans[i - 1].last : 0;
    const int upper = i + 1 < spans.size() ? spans[i + 1].first : n - 1;
    while (m.first > lower && speed[m.first] > rest && speed[m.first - 1] < speed[m.first]) --m.first;
    while (m.last < upper && speed[m.last] > rest && speed[m.last + 1] < speed[m.last]) ++m.last;
  }
  return spans;
}

TipPathMetrics TipPath::metrics(double origin) const {
  TipPathMetrics m;
  m.pathLength = pathLength_;
  const double h = h_;
  double moveTime = 0.0;
  for (const Segment& seg : segments_) {
    const std::vector<Eigen::Vector3d> x = smoothPath(seg.grid, settings_.smoothingTime / h);
    const int n = static_cast<int>(x.size());
    m.gridPoints += x.size();
    for (int k = 0; k + 1 < n; ++k) m.pathLengthSmoothed += (x[k + 1] - x[k]).norm();
    if (n < 3) continue;  // derivatives need two neighbours (reflected at the ends)
    auto at = [&](int j) { return reflectedAt(x, j); };
    m.smoothedDuration += n * h;  // the windows cover n h seconds
    std::vector<double> speed(n), jerk2(n);
    for (int k = 0; k < n; ++k) {
      speed[k] = (at(k + 1) - at(k - 1)).norm() / (2.0 * h);
      jerk2[k] = ((at(k + 2) - 2.0 * at(k + 1) + 2.0 * at(k - 1) - at(k - 2)) / (2.0 * h * h * h)).squaredNorm();
      m.squaredJerkIntegral += jerk2[k] * h;
      m.jerkTime += h;
    }
    m.speedPoints += n;
    const double t0 = seg.firstCentre - origin;
    const std::size_t firstSample = m.path.size();
    for (int k = 0; k < n; ++k) m.path.push_back(PathSample{t0 + k * h, x[k], speed[k], -1});
    for (const MovementSpan& span : segmentMovements(speed, h, settings_)) {
      Movement mv;
      mv.start = t0 + span.first * h;
      mv.end = t0 + span.last * h;
      for (int k = span.first; k <= span.last; ++k) {
        if (k < span.last) mv.pathLength += (x[k + 1] - x[k]).norm();
        mv.peakSpeed = std::max(mv.peakSpeed, speed[k]);
        // Trapezoidal rule over [start, end], as the duration below.
        const double weight = (k == span.first || k == span.last) ? 0.5 : 1.0;
        mv.jerkCost += 0.5 * weight * jerk2[k] * h;
        m.path[firstSample + k].movement = static_cast<int>(m.movementList.size());
      }
      mv.chord = (x[span.last] - x[span.first]).norm();
      const double D = mv.duration(), A = mv.pathLength;
      if (D > 0.0 && A > 0.0 && mv.jerkCost > 0.0) {
        mv.dimensionlessJerk = mv.jerkCost * std::pow(D, 5) / (A * A);
        mv.logDimensionlessJerk = -std::log(mv.dimensionlessJerk);
        mv.hasJerk = std::isfinite(mv.logDimensionlessJerk);
      }
      moveTime += D;
      m.movementList.push_back(mv);
    }
  }
  m.movements = m.movementList.size();
  if (!m.movementList.empty()) {
    m.motionTime = m.movementList.back().end - m.movementList.front().start;
    m.idleTime = std::max(0.0, m.motionTime - moveTime);
  }
  return m;
}

}  // namespace tt
