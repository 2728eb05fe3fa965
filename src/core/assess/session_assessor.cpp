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
// Median (mean of the middle two for an even count); 0 for none.
double median(std::vector<double> v) {
  if (v.empty()) return 0.0;
  std::sort(v.begin(), v.end());
  const std::size_t n = v.size();
  return n % 2 ? v[n / 2] : 0.5 * (v[n / 2 - 1] + v[n / 2]);
}

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
  forceSeries_.push_back(TimedValue{t, force.norm()});
  if (inContact) contactTimes_.push_back(t);
  return true;
}

bool SessionAssessor::addStatus(double t, double maxStrain, double strainedVolume) {
  if (!admit(statusCounts_, statusLast_, t, std::isfinite(maxStrain) && std::isfinite(strainedVolume)))
    return false;
  if (statusCounts_.accepted == 1) statusFirst_ = t;
  peakStrain_ = statusCounts_.accepted == 1 ? maxStrain : std::max(peakStrain_, maxStrain);
  strainSeries_.push_back(TimedValue{t, maxStrain});
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
  if (!std::isfinite(sessionStart)) sessionStart = 0.0;
  TipPathMetrics k = tip_.metrics(sessionStart);
  const ForceMetrics& f = force_.metrics();
  for (const TimedValue& v : forceSeries_) r.forceSeries.push_back(TimedValue{v.t - sessionStart, v.value});
  for (const TimedValue& v : strainSeries_) r.strainSeries.push_back(TimedValue{v.t - sessionStart, v.value});
  auto add = [&](const char* key, const char* unit, bool hasData, double value, const char* def) {
    r.metrics.push_back(Metric{key, unit, hasData && std::isfinite(value) ? value : 0.0,
                               hasData && std::isfinite(value), def});
  };
  const bool tipSpan = tipCounts_.accepted >= 2;
  const bool jerk = k.jerkTime > 0.0;
  const bool moved = !k.movementList.empty();
  std::vector<double> ldlj, reachLdlj, durations, peakSpeeds;
  double chords = 0.0, movedLength = 0.0;
  for (Movement& m : k.movementList) {
    // A contact sample within the movement (times in the session's frame, as the movement's).
    const auto first = std::lower_bound(contactTimes_.begin(), contactTimes_.end(), m.start + sessionStart);
    m.inContact = first != contactTimes_.end() && *first <= m.end + sessionStart;
    if (m.hasJerk) ldlj.push_back(m.logDimensionlessJerk);
    if (m.hasJerk && !m.inContact) reachLdlj.push_back(m.logDimensionlessJerk);
    durations.push_back(m.duration());
    peakSpeeds.push_back(m.peakSpeed);
    chords += m.chord;
    movedLength += m.pathLength;
  }
  add("task_time", "s", tipSpan, tipLast_ - tipFirst_, "first to last tip sample");
  add("motion_time", "s", k.speedPoints > 0, k.motionTime,
      "start of the first movement to the end of the last one (smoothed path)");
  add("idle_time", "s", moved, k.idleTime,
      "time between the first movement's start and the last one's end spent in no movement");
  add("path_length", "m", tipSpan, k.pathLength, "sum of the distances between tip samples");
  add("path_length_smoothed", "m", k.gridPoints >= 2, k.pathLengthSmoothed,
      "path length of the resampled, smoothed tip path");
  add("economy_of_motion", "1", movedLength > 0.0, movedLength > 0.0 ? chords / movedLength : 0.0,
      "sum over movements of the straight start-to-end distance / their path length (1: straight)");
  add("movements", "1", k.speedPoints > 0, static_cast<double>(k.movements),
      "smoothed tip speed rising above movement_speed_start (ends below movement_speed_stop "
      "for at least movement_min_pause)");
  add("movement_duration_median", "s", moved, median(durations), "median duration of a movement");
  add("peak_speed_median", "m/s", moved, median(peakSpeeds), "median of the movements' peak speeds");
  add("ldlj_median", "1", !ldlj.empty(), median(ldlj),
      "median over movements of the log dimensionless jerk -ln(1/2 int |jerk|^2 dt D^5 / A^2) "
      "(minimum-jerk reach: -5.886; lower is less smooth)");
  add("ldlj_reach_median", "1", !reachLdlj.empty(), median(reachLdlj),
      "median log dimensionless jerk of the movements without tool-tissue contact (the reaches, "
      "comparable with the reaching literature)");
  add("ldlj_worst", "1", !ldlj.empty(), ldlj.empty() ? 0.0 : *std::min_element(ldlj.begin(), ldlj.end()),
      "lowest log dimensionless jerk of any movement");
  add("mean_squared_jerk", "m^2/s^6", jerk, jerk ? k.squaredJerkIntegral / k.jerkTime : 0.0,
      "time mean of |d3x/dt3|^2 on the smoothed path");
  r.movements = std::move(k.movementList);
  r.path = std::move(k.path);
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
  add("excess_force_integral", "N s", forceSpan, f.excessIntegral,
      "integral of (|f| - force_threshold) dt over the time above it");
  add("peak_strain", "1", statusCounts_.accepted > 0, peakStrain_,
      "largest max_strain (Green-Lagrange strain norm) of the tissue");
  add("peak_strained_volume", "m^3", statusCounts_.accepted > 0, peakStrainedVolume_,
      "largest rest volume of tets above the damage strain");
  return r;
}

}  // namespace tt
