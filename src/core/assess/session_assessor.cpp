#include "tissue_trainer/core/assess/session_assessor.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace tt {

const Metric* AssessmentReport::find(const std::string& key) const {
  for (const Metric& m : metrics)
    if (m.key == key) return &m;
  return nullptr;
}

namespace {
const AssessmentSettings& validated(const AssessmentSettings& s) {
  s.validate();
  return s;
}
}  // namespace

SessionAssessor::SessionAssessor(const AssessmentSettings& settings)
    : settings_(validated(settings)),
      tip_(settings),
      force_(settings.forceThreshold, settings.maxGap) {}

bool SessionAssessor::admit(StreamCounts& c, double& lastT, double t, bool finite) {
  if (!finite || !std::isfinite(t)) {
    ++c.nonFinite;
    return false;
  }
  if (c.accepted > 0 && !(t > lastT)) {
    ++c.outOfOrder;
    return false;
  }
  lastT = t;
  ++c.accepted;
  return true;
}

bool SessionAssessor::addTip(double t, const Eigen::Vector3d& position) {
  if (!admit(tipCounts_, tipLast_, t, position.allFinite())) return false;
  if (tipCounts_.accepted == 1) tipFirst_ = t;
  tip_.add(t, position);
  return true;
}

bool SessionAssessor::addForce(double t, const Eigen::Vector3d& force, bool inContact,
                               bool simulationRestarted) {
  const double previous = forceLast_;
  if (!admit(forceCounts_, forceLast_, t, force.allFinite())) return false;
  if (forceCounts_.accepted == 1) forceFirst_ = t;
  const bool restart = simulationRestarted && forceCounts_.accepted > 1;
  if (restart) restarts_.push_back(SimulationRestart{t, t - previous});
  force_.add(t, force, inContact, restart);
  return true;
}

bool SessionAssessor::addStatus(double t, double maxStrain, double strainedVolume) {
  if (!admit(statusCounts_, statusLast_, t, std::isfinite(maxStrain) && std::isfinite(strainedVolume)))
    return false;
  if (statusCounts_.accepted == 1) statusFirst_ = t;
  peakStrain_ = statusCounts_.accepted == 1 ? maxStrain : std::max(peakStrain_, maxStrain);
  peakStrainedVolume_ = statusCounts_.accepted == 1 ? strainedVolume
                                                     : std::max(peakStrainedVolume_, strainedVolume);
  return true;
}

AssessmentReport SessionAssessor::report() const {
  AssessmentReport r;
  r.settings = settings_;
  r.tip = tipCounts_;
  r.force = forceCounts_;
  r.status = statusCounts_;
  double sessionStart = std::numeric_limits<double>::infinity();
  if (tipCounts_.accepted > 0) sessionStart = tipFirst_;
  if (forceCounts_.accepted > 0) sessionStart = std::min(sessionStart, forceFirst_);
  if (statusCounts_.accepted > 0) sessionStart = std::min(sessionStart, statusFirst_);
  for (SimulationRestart restart : restarts_) {
    restart.time -= sessionStart;
    r.restarts.push_back(restart);
  }
  const TipPathMetrics k = tip_.metrics();
  const ForceMetrics& f = force_.metrics();
  auto add = [&](const char* key, const char* unit, bool hasData, double value, const char* def) {
    r.metrics.push_back(Metric{key, unit, hasData && std::isfinite(value) ? value : 0.0,
                               hasData && std::isfinite(value), def});
  };
  const bool tipSpan = tipCounts_.accepted >= 2;
  const bool jerk = k.jerkTime > 0.0;
  add("task_time", "s", tipSpan, tipLast_ - tipFirst_, "first to last tip sample");
  add("motion_time", "s", k.speedPoints > 0, k.motionTime,
      "start of the first movement to the end of the last one (smoothed path)");
  add("path_length", "m", tipSpan, k.pathLength, "sum of the distances between tip samples");
  add("path_length_smoothed", "m", k.gridPoints >= 2, k.pathLengthSmoothed,
      "path length of the resampled, smoothed tip path");
  add("movements", "1", k.speedPoints > 0, static_cast<double>(k.movements),
      "smoothed tip speed rising above movement_speed_start (ends below movement_speed_stop)");
  add("mean_squared_jerk", "m^2/s^6", jerk, jerk ? k.squaredJerkIntegral / k.jerkTime : 0.0,
      "time mean of |d3x/dt3|^2 on the smoothed path");
  const double L = k.pathLengthSmoothed, D = k.smoothedDuration;
  add("dimensionless_jerk", "1", jerk && L > 0.0, L > 0.0 ? k.squaredJerkIntegral * std::pow(D, 5) / (L * L) : 0.0,
      "integral of |jerk|^2 dt times duration^5 / path_length^2 (smoothed path)");
  const bool forceSpan = f.span > 0.0, contact = f.contactTime > 0.0;
  add("contact_time", "s", forceSpan, f.contactTime, "time in contact (each sample held until the next)");
  add("force_integral", "N s", forceSpan, f.integral, "integral of |f| dt over the task");
  add("mean_force", "N", contact, contact ? f.integral / f.contactTime : 0.0,
      "time mean of |f| over the contact time");
  add("rms_force", "N", contact, contact ? std::sqrt(f.squaredIntegral / f.contactTime) : 0.0,
      "time RMS of |f| over the contact time");
  add("peak_force", "N", forceCounts_.accepted > 0, f.peak, "largest |f| of any sample");
  add("mean_force_rate", "N/s", forceSpan, forceSpan ? f.variation / f.span : 0.0,
      "time mean of |df/dt| over the task (sum of |f[i+1] - f[i]| / time)");
  add("excessive_force_events", "1", forceCounts_.accepted > 0, static_cast<double>(f.events),
      "times |f| rose above force_threshold");
  add("excessive_force_time", "s", forceSpan, f.excessiveTime, "time with |f| above force_threshold");
  add("peak_strain", "1", statusCounts_.accepted > 0, peakStrain_,
      "largest max_strain (Green-Lagrange strain norm) of the tissue");
  add("peak_strained_volume", "m^3", statusCounts_.accepted > 0, peakStrainedVolume_,
      "largest rest volume of tets above the damage strain");
  return r;
}

}  // namespace tt
