#pragma once
// Kinematic metrics of the instrument tip from time-stamped positions: raw path length,
// and from a resampled, smoothed path the speed, the movements (hysteresis on the speed)
// with their own duration, path length, peak speed and log dimensionless jerk, and jerk.
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
//
// Movements: the smoothed speed rising above movement_speed_start starts one, falling below
// movement_speed_stop ends it; a pause shorter than movement_min_pause is an arrest inside
// the movement, not its end (Hogan and Sternad 2009, "Sensitivity of smoothness measures to
// movement duration, amplitude, and arrests": arrests are what a smoothness measure must see).
// Each movement is then widened outward from its threshold crossings while the speed keeps
// falling and is above 0.1 % of the movement's peak speed (at rest), so that it spans the
// whole rise and fall of the speed and not only its part above the thresholds: the jerk of a
// reach is largest where it leaves and reaches rest. The smoothing widens a movement by a few
// sigma, so short movements read less smooth: a minimum-jerk reach (exactly -ln 360 = -5.886)
// reads -5.86 over 2 s, -6.03 over 1 s, -6.47 over 0.5 s at smoothing_time 0.03 s, whatever
// its amplitude.
#include <cstddef>
#include <vector>

#include <Eigen/Core>

#include "tissue_trainer/core/assess/assessment_settings.h"

namespace tt {

// One movement of the tip (times on the smoothed grid, from the session's first sample).
struct Movement {
  double start = 0.0, end = 0.0;   // s
  double pathLength = 0.0;         // m, along the smoothed path
  double chord = 0.0;              // m, straight distance from start to end
  double peakSpeed = 0.0;          // m/s
  double jerkCost = 0.0;           // m^2/s^5, 1/2 integral of |jerk|^2 dt over the movement
  // Dimensionless jerk: jerkCost * duration^5 / pathLength^2 (360 for a minimum-jerk reach,
  // the least any rest-to-rest movement can have); its log: -ln of it (-5.886 for that reach,
  // lower = less smooth). Zero and no data for a movement without length.
  double dimensionlessJerk = 0.0;
  double logDimensionlessJerk = 0.0;
  bool hasJerk = false;
  // The tool touched the tissue during the movement (a press or a release); false: a reach
  // through free space, the kind of movement the reaching literature's smoothness refers to.
  bool inContact = false;
  double duration() const { return end - start; }
};

// One point of the smoothed tip path.
struct PathSample {
  double t = 0.0;                  // s, centre of the window
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  double speed = 0.0;              // m/s
  int movement = -1;               // index into movements, or -1 between them
};

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
  std::vector<Movement> movementList;  // in time order
  std::vector<PathSample> path;        // every grid point of segments with a speed
  double idleTime = 0.0;            // s, between the first movement's start and the last one's end, in no movement
};

class TipPath {
 public:
  explicit TipPath(const AssessmentSettings& settings);

  // Accepts a sample later than the previous one (the caller checks order and finiteness).
  void add(double t, const Eigen::Vector3d& p);
  // Times in the result count from `origin` (s).
  TipPathMetrics metrics(double origin = 0.0) const;

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

// The movements of one segment of the smoothed path, from the speed at each grid point (step
// h seconds); indices are grid points, [first, last] inclusive (exposed for tests).
struct MovementSpan {
  int first = 0, last = 0;
};
std::vector<MovementSpan> segmentMovements(const std::vector<double>& speed, double h,
                                          const AssessmentSettings& settings);

// Gaussian smoothing with point reflection at the ends (exposed for tests).
std::vector<Eigen::Vector3d> smoothPath(const std::vector<Eigen::Vector3d>& x, double sigmaSamples);

}  // namespace tt
