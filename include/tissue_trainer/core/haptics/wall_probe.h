#pragma once
// A reference scenario for force extrapolation: a stiff nonlinear wall,
//     f(x) = n (k d + k3 d^3),  d = n . (p - x) > 0 (penetration), else zero,
// probed by a device moving on a periodic path, while a 'simulation' samples the exact
// contact model (f, K = -df/dx) at a lower rate and delivers it after a latency. The haptic
// loop's output is compared, tick by tick, with the exact force at the device position.
#include <cstddef>

#include <Eigen/Core>

#include "tissue_trainer/core/haptics/contact_model.h"
#include "tissue_trainer/core/haptics/force_extrapolator.h"

namespace tt {

struct NonlinearWall {
  Eigen::Vector3d point = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();  // unit, pointing out of the tissue
  double k = 200.0;   // N/m
  double k3 = 1e6;    // N/m^3

  double penetration(const Eigen::Vector3d& x) const { return normal.dot(point - x); }
  Eigen::Vector3d force(const Eigen::Vector3d& x) const;
  Eigen::Matrix3d stiffness(const Eigen::Vector3d& x) const;  // -df/dx
  ContactModel model(const Eigen::Vector3d& x, std::uint64_t sequence, double stamp) const;
};

struct WallProbe {
  NonlinearWall wall;
  // Device path x(t) = center + a sin(2 pi f t) + b cos(2 pi f t).
  Eigen::Vector3d center = Eigen::Vector3d(0.0, 0.0, -0.006);
  Eigen::Vector3d a = Eigen::Vector3d(0.0, 0.0, 0.004);
  Eigen::Vector3d b = Eigen::Vector3d(0.003, 0.0, 0.0);
  double frequency = 1.0;       // Hz
  double hapticPeriod = 0.001;  // s
  double simPeriod = 0.02;      // s
  double latency = 0.0;         // s from sampling the device to the model's arrival
  double duration = 3.0;        // s
  double warmup = 0.2;          // s not counted in the errors

  Eigen::Vector3d device(double t) const;
  double peakSpeed() const;  // m/s
};

struct ForceErrorStats {
  double rms = 0.0;      // N, over the counted ticks
  double max = 0.0;      // N
  double maxStep = 0.0;  // N, largest output change between two ticks
  double rmsForce = 0.0; // N, RMS of the exact force, for scale
  std::size_t ticks = 0;
};

// Runs the extrapolator alone (no safety filter) through the probe scenario.
ForceErrorStats measureExtrapolationError(const WallProbe& probe, const ExtrapolatorOptions& options);

}  // namespace tt
