#include "tissue_trainer/core/haptics/wall_probe.h"

#include <algorithm>
#include <cmath>

namespace tt {

Eigen::Vector3d NonlinearWall::force(const Eigen::Vector3d& x) const {
  const double d = penetration(x);
  if (d <= 0.0) return Eigen::Vector3d::Zero();
  return (k * d + k3 * d * d * d) * normal;
}

Eigen::Matrix3d NonlinearWall::stiffness(const Eigen::Vector3d& x) const {
  // f = n g(d), d = n.(p - x): df/dx = -g'(d) n n^T, so K = -df/dx = (k + 3 k3 d^2) n n^T.
  const double d = penetration(x);
  if (d <= 0.0) return Eigen::Matrix3d::Zero();
  return (k + 3.0 * k3 * d * d) * normal * normal.transpose();
}

ContactModel NonlinearWall::model(const Eigen::Vector3d& x, std::uint64_t sequence, double stamp) const {
  ContactModel m;
  m.stamp = stamp;
  m.simTime = stamp;
  m.sequence = sequence;
  m.inContact = penetration(x) > 0.0;
  m.x0 = x;
  m.f0 = force(x);
  m.K = stiffness(x);
  return m;
}

Eigen::Vector3d WallProbe::device(double t) const {
  const double phase = 2.0 * M_PI * frequency * t;
  return center + a * std::sin(phase) + b * std::cos(phase);
}

double WallProbe::peakSpeed() const {
  // |a cos - b sin| is largest along the major axis of the ellipse.
  const double aa = a.squaredNorm(), bb = b.squaredNorm(), ab = a.dot(b);
  const double major = 0.5 * (aa + bb) + std::sqrt(0.25 * (aa - bb) * (aa - bb) + ab * ab);
  return 2.0 * M_PI * frequency * std::sqrt(major);
}

ForceErrorStats measureExtrapolationError(const WallProbe& probe, const ExtrapolatorOptions& options) {
  ForceExtrapolator extrapolator(options);
  ForceErrorStats stats;
  const long ticks = std::lround(probe.duration / probe.hapticPeriod);
  long nextSample = 0;  // index of the next simulation step
  double sumError2 = 0.0, sumForce2 = 0.0;
  Eigen::Vector3d previous = Eigen::Vector3d::Zero();
  for (long i = 0; i <= ticks; ++i) {
    const double t = i * probe.hapticPeriod;
    // Deliver every model whose arrival time has come (the tolerance keeps coincident
    // arrivals and ticks from depending on round-off).
    const Eigen::Vector3d x = probe.device(t);
    while (nextSample * probe.simPeriod + probe.latency <= t + 1e-9) {
      const double sampled = nextSample * probe.simPeriod;
      extrapolator.submit(probe.wall.model(probe.device(sampled), nextSample + 1, sampled), t, x);
      ++nextSample;
    }
    const Eigen::Vector3d out = extrapolator.force(x, t);
    if (t >= probe.warmup) {
      const Eigen::Vector3d exact = probe.wall.force(x);
      const double error = (out - exact).norm();
      sumError2 += error * error;
      sumForce2 += exact.squaredNorm();
      stats.max = std::max(stats.max, error);
      stats.maxStep = std::max(stats.maxStep, (out - previous).norm());
      ++stats.ticks;
    }
    previous = out;
  }
  if (stats.ticks > 0) {
    stats.rms = std::sqrt(sumError2 / stats.ticks);
    stats.rmsForce = std::sqrt(sumForce2 / stats.ticks);
  }
  return stats;
}

}  // namespace tt
