#include "tissue_trainer/core/assess/assessment_settings.h"

#include <yaml-cpp/yaml.h>

#include <cmath>
#include <sstream>
#include <stdexcept>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/registry/yaml_file.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {
namespace {

std::string show(double v) {
  std::ostringstream s;
  s << v;
  return s.str();
}

void require(bool ok, const char* key, const std::string& expected, double value) {
  if (!ok) throw std::invalid_argument(std::string(key) + ": expected " + expected + ", got " + show(value));
}

}  // namespace

const std::array<AssessmentSettingKey, 7> kAssessmentSettingKeys = {{
    {"force_threshold", &AssessmentSettings::forceThreshold},
    {"movement_speed_start", &AssessmentSettings::movementSpeedStart},
    {"movement_speed_stop", &AssessmentSettings::movementSpeedStop},
    {"movement_min_pause", &AssessmentSettings::movementMinPause},
    {"resample_rate", &AssessmentSettings::resampleRate},
    {"smoothing_time", &AssessmentSettings::smoothingTime},
    {"max_gap", &AssessmentSettings::maxGap},
}};

void AssessmentSettings::validate() const {
  auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  require(positive(forceThreshold), "force_threshold", "a positive force (N)", forceThreshold);
  require(positive(movementSpeedStart), "movement_speed_start", "a positive speed (m/s)",
          movementSpeedStart);
  require(positive(movementSpeedStop) && movementSpeedStop <= movementSpeedStart,
          "movement_speed_stop", "a positive speed (m/s) <= movement_speed_start",
          movementSpeedStop);
  require(std::isfinite(movementMinPause) && movementMinPause >= 0.0, "movement_min_pause",
          "a time >= 0 s", movementMinPause);
  require(positive(resampleRate) && resampleRate <= 10000.0, "resample_rate",
          "a rate in (0, 10000] Hz", resampleRate);
  require(std::isfinite(smoothingTime) && smoothingTime >= 0.0, "smoothing_time",
          "a time >= 0 s (0: no smoothing)", smoothingTime);
  require(std::isfinite(maxGap) && maxGap >= 2.0 / resampleRate, "max_gap",
          "a time (s) of at least two resampling steps (2 / resample_rate)", maxGap);
}

AssessmentSettings loadAssessmentSettings(const std::string& yamlFile) {
  const YAML::Node root = loadYamlFile(yamlFile, "assessment settings file");
  const YamlEntry top(root, "", &yamlFile);
  // output_dir, summary_rate and reference_bands belong to the node; the file is shared with it.
  top.expectMap({"force_threshold", "movement_speed_start", "movement_speed_stop",
                 "movement_min_pause", "resample_rate", "smoothing_time", "max_gap",
                 "output_dir", "summary_rate", "reference_bands"});
  AssessmentSettings s;
  for (const AssessmentSettingKey& k : kAssessmentSettingKeys)
    s.*k.value = top.number(k.key, s.*k.value);
  try {
    s.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(yamlFile, 0, e.what());
  }
  return s;
}

}  // namespace tt
