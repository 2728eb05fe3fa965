#pragma once
// Kinematic metrics of the instrument tip from time-stamped positions: raw path length,
// and from a resampled, smoothed path the speed (movement count with hysteresis) and jerk.
//
// Resampling: the samples are joined by straight lines and averaged over consecutive windows
// of 1/resample_rate seconds (exact integral), one grid point per complete window at its
// centre. This averages the ~10 samples of a 1 kHz stream per 100 Hz point and is exact for
// straight-line motion. A gap longer than max_gap ends a segment; the next sample starts a
// new one. Smoothing: a centred Gaussian (sigma = smoothing_time) per segment, with the
// segment point-reflected at its ends (x(-t) = 2 x(0) - x(t)), so straight lines stay exact.
// White position noise of spectral density S (m^2/Hz per axis: sigma^2 / sample rate) leaves
// a jerk variance of about 0.53 S / smoothing_time^7 per axis, so the smoothing time trades
// noise against the jerk of fast movements: 0.03 s (-3 dB at 4.4 Hz) leaves ~0.008 m^2/s^6
// from 10 um noise at 1 kHz, 7 % of a minimum-jerk 10 cm / 2 s reach.
// Derivatives are central differences on the smoothed grid, point-reflected at its ends the
// same way, so every grid point of a segment of at least 3 points has a speed and a jerk.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "tissue_trainer/core/assess/assessment_settings.h"

namespace tt {

struct TipPathMetrics {
  double pathLength = 0.0;          // m, sum of |p[i+1] - p[i]| over the accepted samples
  double pathLengthSmoothed = 0.0;  // m, same over the smoothed grid
  std::size_t movements = 0;        // upward crossings of movement_speed_start (hysteresis)
  double motionTime = 0.0;          // s, first movement start to last movement end
  double squaredJerkIntegral = 0.0; // m^2/s^5, integral of |jerk|^2 over the grid
  double jerkTime = 0.0;            // s, time covered by the jerk estimates
  double smoothedDuration = 0.0;    // s, time covered by the windows of segments with a jerk
  std::size_t gridPoints = 0;
  std::size_t speedPoints = 0;      // grid points with a speed estimate
};

class TipPath {
 public:
  explicit TipPath(const AssessmentSettings& settings);

  // Accepts a sample later than the previous one (the caller checks order and finiteness).
  void add(double t, const Eigen::Vector3d& p);
  TipPathMetrics metrics() const;

 private:
  struct Segment {
    std::vector<Eigen::Vector3d> grid;  // window means, one per complete window
    double firstCentre = 0.0;           // s, centre time of grid[0]
  };
  void startSegment(double t);
  void integrate(double t0, const Eigen::Vector3d& p0, double t1, const Eigen::Vector3d& p1);

  AssessmentSettings settings_;
  double h_;  // grid step (s)
  bool any_ = false;
  double lastT_ = 0.0;
  Eigen::Vector3d lastP_ = Eigen::Vector3d::Zero();
  double pathLength_ = 0.0;
  std::vector<Segment> segments_;
  double segmentStart_ = 0.0;    // s, time of the current segment's first sample
  std::size_t windowIndex_ = 0;  // open window: [start + i h, start + (i + 1) h)
  Eigen::Vector3d windowSum_ = Eigen::Vector3d::Zero();  // integral of p over it so far (m s)
};

// Gaussian smoothing with point reflection at the ends (exposed for tests).
std::vector<Eigen::Vector3d> smoothPath(const std::vector<Eigen::Vector3d>& x, double sigmaSamples);

}  // namespace tt
