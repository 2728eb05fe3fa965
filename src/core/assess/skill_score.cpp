#include "tissue_trainer/core/assess/skill_score.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/registry/yaml_file.h"
#include "tissue_trainer/core/registry/yaml_reader.h"

namespace tt {

std::vector<std::string> assessmentMetricKeys() {
  std::vector<std::string> keys;
  for (const Metric& m : SessionAssessor{AssessmentSettings{}}.report().metrics) keys.push_back(m.key);
  return keys;
}

ReferenceBands loadReferenceBands(const std::string& yamlFile) {
  const YAML::Node root = loadYamlFile(yamlFile, "reference bands file");
  const YamlEntry top(root, "", &yamlFile);
  top.expectMap({"source", "bands"});
  ReferenceBands out;
  out.source = top["source"].text();
  const YamlEntry bands = top["bands"];
  if (!bands.node().IsMap() || bands.node().size() == 0) bands.fail("expected a map of metric keys to {expert, novice}");
  const std::vector<std::string> known = assessmentMetricKeys();
  for (const auto& item : bands.node()) {
    const std::string key = item.first.as<std::string>();
    const YamlEntry band = bands[key.c_str()];
    if (std::find(known.begin(), known.end(), key) == known.end())
      band.fail("expected a metric key of the assessment report (docs/assessment.md)");
    band.expectMap({"expert", "novice"});
    ReferenceBand b{key, band["expert"].number(), band["novice"].number()};
    if (!(b.expert != b.novice)) band.fail("expected different expert and novice values");
    out.bands.push_back(b);
  }
  return out;
}

double bandScore(double value, double expert, double novice) {
  const double s = (novice - value) / (novice - expert);
  return 100.0 * std::clamp(s, 0.0, 1.0);
}

SkillScore scoreAssessment(const AssessmentReport& report, const ReferenceBands& bands) {
  SkillScore out;
  out.source = bands.source;
  double sum = 0.0;
  int counted = 0;
  for (const ReferenceBand& b : bands.bands) {
    MetricScore s;
    s.key = b.key;
    s.expert = b.expert;
    s.novice = b.novice;
    const Metric* m = report.find(b.key);
    s.hasData = m && m->hasData;
    if (s.hasData) {
      s.value = m->value;
      s.score = bandScore(s.value, b.expert, b.novice);
      sum += s.score;
      ++counted;
    }
    out.metrics.push_back(s);
  }
  out.hasData = counted > 0;
  out.overall = counted > 0 ? sum / counted : 0.0;
  return out;
}

}  // namespace tt
