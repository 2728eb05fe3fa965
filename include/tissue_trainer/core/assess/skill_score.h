#pragma once
// Scores of an assessment against reference bands: for each scored metric an expert and a
// novice value (config/assessment_bands.yaml says where each comes from). The rule:
//   metric score = 100 * clamp((novice - value) / (novice - expert), 0, 1)
// (100 at the expert value or beyond it, 0 at the novice value or beyond it, linear between;
// the direction follows from which of the two is larger), and the overall score is the mean
// of the metric scores that have data, each metric weighing the same.
#include <string>
#include <vector>

#include "tissue_trainer/core/assess/session_assessor.h"

namespace tt {

struct ReferenceBand {
  std::string key;       // a metric key of the report
  double expert = 0.0;
  double novice = 0.0;   // != expert
};

struct ReferenceBands {
  std::string source;    // where the values come from (one line, shown in the report)
  std::vector<ReferenceBand> bands;
};

// Reads `source: TEXT` and `bands: {KEY: {expert: X, novice: Y}, ...}`; unknown keys,
// non-numbers, equal expert and novice values and metric keys the report does not have are
// errors: InputError "FILE:LINE: key: what was expected".
ReferenceBands loadReferenceBands(const std::string& yamlFile);

struct MetricScore {
  std::string key;
  double value = 0.0, expert = 0.0, novice = 0.0;
  double score = 0.0;    // 0..100
  bool hasData = false;  // the report had the metric
};

struct SkillScore {
  std::string source;
  std::vector<MetricScore> metrics;  // in the order of the bands
  double overall = 0.0;              // 0..100, mean of the metric scores with data
  bool hasData = false;
};

double bandScore(double value, double expert, double novice);
SkillScore scoreAssessment(const AssessmentReport& report, const ReferenceBands& bands);

// The metric keys a report has (for checking band files without a session).
std::vector<std::string> assessmentMetricKeys();

}  // namespace tt
