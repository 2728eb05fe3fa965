#pragma once
// Thresholds and filter settings of the training assessment. The same keys are the node's
// private parameters (config/assessment.yaml) and the YAML file assess_bag --config reads.
#include <array>
#include <string>

namespace tt {

struct AssessmentSettings {
  double forceThreshold = 1.5;       // force_threshold (N): excessive-force level
  double movementSpeedStart = 0.01;  // movement_speed_start (m/s): a movement starts above it
  double movementSpeedStop = 0.005;  // movement_speed_stop (m/s): and ends below it (hysteresis)
  double movementMinPause = 0.2;     // movement_min_pause (s): a shorter pause is an arrest inside a movement
  double resampleRate = 100.0;       // resample_rate (Hz): tip path window-averaged to this grid
  double smoothingTime = 0.03;       // smoothing_time (s): Gaussian sigma on the resampled path
  double maxGap = 0.5;               // max_gap (s): a longer gap between samples carries no weight

  // Throws std::invalid_argument "KEY: expected ..., got VALUE" for the first bad value.
  void validate() const;
};

// Every setting with its key, for the readers (the YAML file below, the node's parameters).
struct AssessmentSettingKey {
  const char* key;
  double AssessmentSettings::*value;
};
extern const std::array<AssessmentSettingKey, 7> kAssessmentSettingKeys;

// Reads the keys above from a flat YAML map (unknown keys and non-numbers are errors; missing
// keys keep their defaults) and validates. Throws InputError "FILE: KEY: what was expected".
AssessmentSettings loadAssessmentSettings(const std::string& yamlFile);

}  // namespace tt
