// Scores against reference bands: the rule on hand-made values, the band file reader, and the
// shipped expert and novice liver tasks (config/tasks/liver_{expert,novice}.yaml) played
// through the scripted operator's virtual hand against a spring-plane stand-in for the liver,
// scored with the shipped bands (config/assessment_bands.yaml, measured on the full
// simulation): the two must land far apart.
#include <gtest/gtest.h>

#include <yaml-cpp/yaml.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "tissue_trainer/core/assess/assessment_report.h"
#include "tissue_trainer/core/assess/skill_score.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/operator/task_script.h"
#include "tissue_trainer/core/operator/virtual_hand.h"

namespace tt {
namespace {

using Eigen::Vector3d;

const std::string kConfig = std::string(TT_SOURCE_DIR) + "/config/";

TEST(SkillScore, TheBandRule) {
  // Lower is better (expert 10, novice 30) and higher is better (expert -6, novice -12).
  EXPECT_DOUBLE_EQ(bandScore(10.0, 10.0, 30.0), 100.0);
  EXPECT_DOUBLE_EQ(bandScore(30.0, 10.0, 30.0), 0.0);
  EXPECT_DOUBLE_EQ(bandScore(25.0, 10.0, 30.0), 25.0);
  EXPECT_DOUBLE_EQ(bandScore(5.0, 10.0, 30.0), 100.0);   // better than the expert
  EXPECT_DOUBLE_EQ(bandScore(45.0, 10.0, 30.0), 0.0);    // worse than the novice
  EXPECT_DOUBLE_EQ(bandScore(-7.5, -6.0, -12.0), 75.0);
  EXPECT_DOUBLE_EQ(bandScore(-5.0, -6.0, -12.0), 100.0);
  EXPECT_DOUBLE_EQ(bandScore(-20.0, -6.0, -12.0), 0.0);
}

TEST(SkillScore, OverallIsTheMeanOfTheMetricsWithData) {
  SessionAssessor a{AssessmentSettings{}};
  for (int i = 0; i <= 100; ++i) a.addForce(i / 100.0, Vector3d(0, 2.0, 0), true);  // 1 s at 2 N
  const AssessmentReport r = a.report();
  ReferenceBands bands{"test", {{"peak_force", 1.0, 3.0},      // 2 N: 50
                                {"contact_time", 0.0, 5.0},    // 1 s: 80
                                {"task_time", 10.0, 20.0}}};   // no tip samples: no data
  const SkillScore s = scoreAssessment(r, bands);
  ASSERT_EQ(s.metrics.size(), 3u);
  EXPECT_DOUBLE_EQ(s.metrics[0].score, 50.0);
  EXPECT_DOUBLE_EQ(s.metrics[1].score, 80.0);
  EXPECT_FALSE(s.metrics[2].hasData);
  EXPECT_TRUE(s.hasData);
  EXPECT_DOUBLE_EQ(s.overall, 65.0);

  const std::string md = assessmentMarkdown(r, "x", &s);
  EXPECT_NE(md.find("**Overall score: 65 / 100**"), std::string::npos) << md;
  EXPECT_NE(md.find("| peak_force | 2 | 1 | 3 | 50 |"), std::string::npos) << md;
  const YAML::Node y = YAML::Load(assessmentYaml(r, "x", &s));
  EXPECT_DOUBLE_EQ(y["score"]["overall"].as<double>(), 65.0);
  EXPECT_DOUBLE_EQ(y["score"]["metrics"]["contact_time"]["score"].as<double>(), 80.0);
  EXPECT_FALSE(y["score"]["metrics"]["task_time"]["score"]);
  EXPECT_NE(y["score"]["rule"].as<std::string>().find("clamp"), std::string::npos);
}

TEST(SkillScore, BandFilesAreChecked) {
  const std::string file = testing::TempDir() + "bands.yaml";
  auto expectError = [&](const std::string& text, const std::string& what) {
    std::ofstream(file) << text;
    try {
      loadReferenceBands(file);
      ADD_FAILURE() << "no error for:\n" << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find(what), std::string::npos) << e.what();
    }
  };
  expectError("bands: {peak_force: {expert: 1, novice: 2}}\n", "source");
  expectError("source: s\nbands: {peak_forse: {expert: 1, novice: 2}}\n", "a metric key");
  expectError("source: s\nbands: {peak_force: {expert: 1, novice: 1}}\n", "different expert and novice");
  expectError("source: s\nbands: {peak_force: {expert: 1, novise: 2}}\n", "novise");
  expectError("source: s\nbands: {peak_force: {expert: one, novice: 2}}\n", "peak_force");
  expectError("source: s\nbands: {}\n", "bands");
  expectError("source: s\nbands: [\n", "not valid YAML");
  std::ofstream(file) << "source: s\nbands:\n  ldlj_median: {expert: -6, novice: -9.5}\n";
  const ReferenceBands b = loadReferenceBands(file);
  ASSERT_EQ(b.bands.size(), 1u);
  EXPECT_EQ(b.bands[0].key, "ldlj_median");
  EXPECT_EQ(b.bands[0].novice, -9.5);
  std::remove(file.c_str());
  try {
    loadReferenceBands(file);
    ADD_FAILURE() << "no error for a missing file";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), file + ": cannot open the reference bands file");
  }
  // The shipped file reads.
  EXPECT_GE(loadReferenceBands(kConfig + "assessment_bands.yaml").bands.size(), 6u);
}

// A task played as the operator node plays it (1 kHz, the virtual hand with the node's
// gains, starting after 1 s and holding 1 s after the end), against a spring plane standing
// in for the liver: the anterior face at site 1 (z = 0.0652) for x < -0.025 and at site 2
// (z = 0.0623) beyond, pushing back along +z with `stiffness` per metre of depth of the jaw
// tips (18 mm beyond the hand's tip along the shaft from the trocar). The contact model is
// sampled at 100 Hz as the simulation publishes it.
AssessmentReport playAgainstPlane(const std::string& taskFile, double stiffness) {
  const TaskScript task = TaskScript::load(taskFile);
  VirtualHand hand(HandGains{}, task.sample(0.0).tip);
  SessionAssessor a{AssessmentSettings{}};
  const double dt = 0.001, delay = 1.0;
  Vector3d force = Vector3d::Zero();
  for (int tick = 0; tick * dt <= task.duration() + 2 * delay; ++tick) {
    const double t = tick * dt;
    const TaskSample target = task.sample(t - delay);
    hand.step(target.tip, t >= delay ? target.tipVelocity : Vector3d::Zero(), force, dt);
    const Vector3d& x = hand.position();
    const Vector3d jawTips = x + 0.018 * (x - Vector3d(-0.035, 0.075, 0.20)).normalized();
    const double surface = jawTips.x() < -0.025 ? 0.0652 : 0.0623;
    const double depth = std::max(0.0, surface - jawTips.z());
    if (tick % 10 == 0) {
      force = Vector3d(0, 0, stiffness * depth);  // the haptic loop holds it until the next
      a.addForce(t, force, depth > 0.0);
    }
    a.addTip(t, x);
  }
  return a.report();
}

TEST(SkillScore, TheExpertAndNoviceTasksAreScoredApart) {
  const ReferenceBands bands = loadReferenceBands(kConfig + "assessment_bands.yaml");
  const double stiffness = 150.0;  // N/m: the expert's 1 cm press gives about 1.1 N
  const AssessmentReport expert = playAgainstPlane(kConfig + "tasks/liver_expert.yaml", stiffness);
  const AssessmentReport novice = playAgainstPlane(kConfig + "tasks/liver_novice.yaml", stiffness);
  const SkillScore e = scoreAssessment(expert, bands), n = scoreAssessment(novice, bands);
  for (std::size_t i = 0; i < e.metrics.size(); ++i)
    std::printf("[score] %-26s expert %10.4g (%3.0f)   novice %10.4g (%3.0f)   bands %g / %g\n",
                e.metrics[i].key.c_str(), e.metrics[i].value, e.metrics[i].score, n.metrics[i].value,
                n.metrics[i].score, e.metrics[i].expert, e.metrics[i].novice);
  std::printf("[score] overall: expert %.1f, novice %.1f\n", e.overall, n.overall);
  ASSERT_TRUE(e.hasData);
  ASSERT_TRUE(n.hasData);
  EXPECT_GE(e.overall, 75.0);
  EXPECT_LE(n.overall, 25.0);
  EXPECT_GE(e.overall - n.overall, 60.0);
  // The smoothness measure itself tells them apart, and the expert's reaches are within one of
  // the smoothest a rest-to-rest movement can be (-ln 360 = -5.89; the hand's lag and the
  // presses make them a little less smooth than the script).
  const double expertLdlj = expert.find("ldlj_median")->value, noviceLdlj = novice.find("ldlj_median")->value;
  EXPECT_GT(expertLdlj, -6.9);
  EXPECT_LT(expertLdlj, -5.6);
  EXPECT_LT(noviceLdlj, expertLdlj - 1.0);
  EXPECT_EQ(expert.find("excessive_force_events")->value, 0.0);
  EXPECT_GE(novice.find("excessive_force_events")->value, 2.0);
}

}  // namespace
}  // namespace tt
