#pragma once
// The training assessment accumulator: fed with time-stamped samples of the three session
// streams (tool tip, tool-tissue force, tissue status), each in its own time order, and
// summarised on demand. The streams are independent, so interleaving them differently (live
// topics, a bag read back) gives the same report as long as each stream's samples agree.
#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "tissue_trainer/core/assess/assessment_settings.h"
#include "tissue_trainer/core/assess/force_stats.h"
#include "tissue_trainer/core/assess/tip_path.h"

namespace tt {

struct StreamCounts {
  std::size_t accepted = 0;
  std::size_t nonFinite = 0;   // rejected: a non-finite time or value
  std::size_t outOfOrder = 0;  // rejected: time not later than the previous accepted sample
  std::size_t received() const { return accepted + nonFinite + outOfOrder; }
};

struct Metric {
  std::string key;    // YAML key
  std::string unit;   // "s", "m", "N s", "1", ...
  double value = 0.0; // always finite; 0 when there is no data
  bool hasData = false;
  std::string definition;
};

// A restart of the simulation seen in the force stream (its contact-model sequence began
// again): the metrics skip the time without contact models before it.
struct SimulationRestart {
  double time = 0.0;  // s since the session's first sample: the new process's first model
  double gap = 0.0;   // s since the last model of the process that died
};

// A time series point for the plots (times from the session's first sample).
struct TimedValue {
  double t = 0.0;
  double value = 0.0;
};

struct AssessmentReport {
  AssessmentSettings settings;
  StreamCounts tip, force, status;
  std::vector<Metric> metrics;  // in report order
  std::vector<SimulationRestart> restarts;
  std::vector<Movement> movements;    // times from the session's first sample
  std::vector<PathSample> path;       // the smoothed tip path
  std::vector<TimedValue> forceSeries;   // |f| (N) of every accepted force sample
  std::vector<TimedValue> strainSeries;  // max_strain of every accepted status sample
  const Metric* find(const std::string& key) const;
};

class SessionAssessor {
 public:
  explicit SessionAssessor(const AssessmentSettings& settings);  // validates

  // Each returns false (and counts why) when the sample is rejected.
  bool addTip(double t, const Eigen::Vector3d& position);
  // simulationRestarted: this is the first sample of a restarted simulation (the gap before
  // it carries no weight and is reported).
  bool addForce(double t, const Eigen::Vector3d& force, bool inContact,
                bool simulationRestarted = false);
  bool addStatus(double t, double maxStrain, double strainedVolume);

  AssessmentReport report() const;

 private:
  static bool admit(StreamCounts& c, double& lastT, double t, bool finite);

  AssessmentSettings settings_;
  TipPath tip_;
  ForceStats force_;
  StreamCounts tipCounts_, forceCounts_, statusCounts_;
  double tipFirst_ = 0.0, tipLast_ = 0.0, forceLast_ = 0.0, statusLast_ = 0.0;
  double forceFirst_ = 0.0, statusFirst_ = 0.0;
  std::vector<SimulationRestart> restarts_;  // times relative to the stream, not yet the session
  double peakStrain_ = 0.0, peakStrainedVolume_ = 0.0;
  std::vector<TimedValue> forceSeries_, strainSeries_;  // stream times, not yet the session's
  std::vector<double> contactTimes_;                    // stream times of samples in contact
};

}  // namespace tt
