// config/scenes/beating_heart.yaml, the beating wall of the training graph: it loads with the
// Hunter law, the volume term and the twitch; a mid-wall node moves with every beat and is
// back at rest before the next one; the epicardial face rises as the wall thickens; a tool
// held on that face feels the beat through the contact model the simulation node publishes
// (TissueContact's f0) and the haptic bridge's pipeline; and the palpation task, played
// through the operator's virtual hand, is pushed back at every systole.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "tissue_trainer/core/contact/tissue_contact.h"
#include "tissue_trainer/core/haptics/haptic_pipeline.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/model/adamss/active_tension.h"
#include "tissue_trainer/core/operator/task_script.h"
#include "tissue_trainer/core/operator/virtual_hand.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

const std::string kHeart = std::string(TT_SOURCE_DIR) + "/config/scenes/beating_heart.yaml";

// The slab's rest geometry as the scene places it (m).
constexpr double kEpicardium = 0.055;
const Eigen::Vector3d kCentre(-0.035, 0.075, 0.05);  // mid-wall, under the trocar

int nearestNode(const Mesh& mesh, const Eigen::Vector3d& p) {
  Eigen::Index best = 0;
  (mesh.rest.colwise() - p).colwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}

Eigen::Vector3d displacement(const System& s, int node) {
  return s.state.x.segment<3>(3 * node) - s.mesh.rest.col(node);
}

struct Beats {
  std::vector<double> time, midWall, epicardialRise;
  int halvings = 0;
};

// Runs the scene frame by frame for `duration` s; every frame must pass at once.
Beats run(Scene& scene, double duration, int midWall, int epicardial) {
  Beats b;
  const int frames = static_cast<int>(std::lround(duration / scene.frameTime));
  for (int f = 0; f < frames; ++f) {
    const StepReport r = scene.integrator->advance(scene.system, scene.frameTime);
    EXPECT_TRUE(r.ok) << r.failure;
    b.halvings += guardOf(*scene.integrator)->lastFrame().halvings;
    b.time.push_back(scene.system.state.t);
    b.midWall.push_back(displacement(scene.system, midWall).norm());
    b.epicardialRise.push_back(displacement(scene.system, epicardial).z());
  }
  return b;
}

// The two closed jaws of config/instruments/grasper.urdf as one box, 4 x 3.2 x 18 mm, its long
// side along the shaft (its pose: the box centre, 9 mm beyond the jaw pivot).
ToolShape closedJaws() {
  ToolShape jaws;
  jaws.type = ToolShape::Type::kBox;
  jaws.size = Eigen::Vector3d(0.004, 0.0032, 0.018);
  jaws.link = "jaws";
  return jaws;
}

// The haptic bridge's per-tick pipeline with config/haptic_bridge.yaml's values (the option
// defaults, and its max_stiffness).
HapticPipeline bridgePipeline() {
  HapticPipelineOptions options;
  options.extrapolation.maxStiffness = 10000.0;
  return HapticPipeline(options);
}

// The contact model the simulation node publishes for a contact result, with the device at x0.
ContactModel publishedModel(const ContactResult& r, std::uint64_t sequence, double t,
                            const Eigen::Vector3d& x0) {
  ContactModel model;
  model.sequence = sequence;
  model.stamp = model.simTime = t;
  model.inContact = r.inContact;
  model.x0 = x0;
  model.f0 = r.f0;
  model.K = r.K;
  return model;
}

double maxOver(const Beats& b, const std::vector<double>& v, double t0, double t1) {
  double m = -INFINITY;
  for (size_t k = 0; k < v.size(); ++k)
    if (b.time[k] > t0 - 1e-9 && b.time[k] < t1 + 1e-9) m = std::max(m, v[k]);
  return m;
}

TEST(BeatingHeartScene, LoadsTheMyocardiumModels) {
  const Scene scene = loadScene(kHeart);
  ASSERT_EQ(scene.system.models.size(), 3u);
  EXPECT_STREQ(scene.system.models[0]->name(), "virtual_hexahedron");
  EXPECT_STREQ(scene.system.models[1]->name(), "virtual_hexahedron");
  EXPECT_NE(dynamic_cast<const adamss::ActiveTensionModel*>(scene.system.models[2].get()), nullptr);
  ASSERT_TRUE(scene.contact.has_value());
  EXPECT_NEAR(scene.frameTime, 0.01, 1e-12);
  // The fibre turns from +60 degrees at the endocardium to -60 at the epicardium, in the wall
  // plane (x circumferential, z through the wall).
  const Mesh& mesh = scene.system.mesh;
  double innermost = INFINITY, outermost = -INFINITY, inner = 0, outer = 0;
  for (int e = 0; e < mesh.numTets(); ++e) {
    double z = 0;
    for (int a : mesh.tets[e]) z += 0.25 * mesh.rest(2, a);
    const Eigen::Vector3d fibre = mesh.fibreFrame[e].col(0);
    EXPECT_NEAR(fibre.z(), 0.0, 1e-12);
    const double angle = std::atan2(fibre.y(), fibre.x()) * 180.0 / M_PI;
    if (z < innermost) innermost = z, inner = angle;
    if (z > outermost) outermost = z, outer = angle;
  }
  EXPECT_GT(inner, 30.0);
  EXPECT_LT(outer, -30.0);
}

// A mid-wall node: displaced by millimetres at systole, back below a tenth of that before the
// next twitch starts (t = 1 s), and moving again in the second beat as in the first.
TEST(BeatingHeartScene, TheWallBeatsOnceASecond) {
  Scene scene = loadScene(kHeart);
  const int mid = nearestNode(scene.system.mesh, kCentre);
  const int epi = nearestNode(scene.system.mesh, Eigen::Vector3d(kCentre.x(), kCentre.y(), kEpicardium));
  const Beats b = run(scene, 1.2, mid, epi);
  EXPECT_EQ(b.halvings, 0);
  const double systole = maxOver(b, b.midWall, 0.0, 0.5);
  const double diastole = maxOver(b, b.midWall, 0.85, 1.0);
  const double second = maxOver(b, b.midWall, 1.0, 1.2);
  const double firstSame = maxOver(b, b.midWall, 0.0, 0.2);
  const double rise = maxOver(b, b.epicardialRise, 0.0, 0.5);
  EXPECT_GT(systole, 0.5e-3);                           // 1.18 mm when written
  EXPECT_LT(diastole, 0.05 * systole);                   // 1e-7 m
  EXPECT_NEAR(second, firstSame, 0.05 * systole);        // the same beat again
  EXPECT_GT(second, 0.5 * systole);
  EXPECT_GT(rise, 0.5e-3);  // the wall thickens: the epicardium rises 1.6 mm toward the tool
}

// The closed jaws (one box of the two jaws' size, 4 x 3.2 x 18 mm, along the shaft) held 2 mm
// into the epicardium at the wall's centre (the task presses 1.5 mm). Each frame, as the
// simulation node does, the contact is queried before the step and its model (f0, K at the
// tip) goes to the haptic bridge's pipeline (ForceExtrapolator and SafetyFilter with the
// bridge's parameters, config/haptic_bridge.yaml), ticked at 1 kHz with the device where the
// tool is. The force the device gets is larger at systole than in diastole: the thickening
// wall pushes the jaws back. K is the contact penalty's (tissue held fixed); the beat reaches
// the hand through f0.
TEST(BeatingHeartScene, AToolHeldOnTheWallFeelsItBeat) {
  Scene scene = loadScene(kHeart);
  ASSERT_TRUE(scene.contact.has_value());
  const double depth = 0.002;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(kCentre.x(), kCentre.y(), kEpicardium - depth + 0.009);
  TissueContact contact(scene.system, *scene.contact, {closedJaws()});
  // The jaws close far from the wall (as the task starts), so they arrive closed and press
  // without grasping.
  Eigen::Isometry3d away = pose;
  away.translation().z() += 0.05;
  contact.setTool(away, {away}, 0.0, 0.0);
  ASSERT_FALSE(contact.update().inContact);

  HapticPipeline haptics = bridgePipeline();
  std::vector<double> time, force, stiffness, penaltyStiffness, feltTime, felt;
  double hapticTime = 0.0;
  for (int f = 0; f < 130; ++f) {
    // Lowered from 2 mm above the surface to the depth over the first 0.4 s, then held.
    const double lowered = std::min(1.0, scene.system.state.t / 0.4);
    Eigen::Isometry3d now = pose;
    now.translation().z() += (1.0 - lowered) * (depth + 0.002);
    contact.setTool(now, {now}, 0.0, scene.system.state.t);
    const ContactResult& r = contact.update();
    const ContactModel model = publishedModel(r, f + 1, scene.system.state.t, r.x0);
    EXPECT_EQ(haptics.submit(model, hapticTime, r.x0), ModelVerdict::kAccepted) << "frame " << f;
    for (int tick = 0; tick < 10; ++tick) {
      hapticTime += 0.001;
      feltTime.push_back(hapticTime);
      felt.push_back(haptics.tick(r.x0, hapticTime, true).z());
    }
    time.push_back(scene.system.state.t);
    force.push_back(r.f0.z());
    stiffness.push_back(r.K(2, 2));
    penaltyStiffness.push_back(contact.model().toolStiffness(scene.system.state.x)(2, 2));
    const StepReport report = scene.integrator->advance(scene.system, scene.frameTime);
    ASSERT_TRUE(report.ok) << report.failure;
    EXPECT_EQ(guardOf(*scene.integrator)->lastFrame().halvings, 0) << "frame " << f;
  }
  // Diastole: the wall at rest against the jaws (0.26 N when written); systole of the second
  // beat: the thickening wall pushes them back (1.35 N). The jaws never lose the wall while
  // held. The device gets the same through the bridge's blending and rate limit.
  // Smallest or largest of v over the samples at times in (t0, t1).
  const auto range = [](const std::vector<double>& at, const std::vector<double>& v, double t0,
                        double t1, bool largest) {
    double m = largest ? -INFINITY : INFINITY;
    for (size_t k = 0; k < v.size(); ++k)
      if (at[k] > t0 && at[k] < t1) m = largest ? std::max(m, v[k]) : std::min(m, v[k]);
    return m;
  };
  const double diastole = range(time, force, 0.85, 1.0, false);
  const double systole = range(time, force, 1.0, 1.3, true);
  EXPECT_GT(diastole, 0.1);
  EXPECT_GT(systole, 1.5 * diastole);
  EXPECT_GT(range(time, force, 0.45, 1.3, false), 0.1);
  const double feltDiastole = range(feltTime, felt, 0.85, 1.0, false);
  const double feltSystole = range(feltTime, felt, 1.0, 1.3, true);
  EXPECT_NEAR(feltDiastole, diastole, 0.05 * diastole);
  EXPECT_GT(feltSystole, 1.5 * feltDiastole);
  EXPECT_EQ(haptics.extrapolator().counters().malformed, 0u);
  // The felt stiffness (felt_stiffness: tissue_in_series) is the penalties' in series with the
  // wall: below the penalties' own in every frame in contact, well below it at rest.
  for (size_t k = 0; k < time.size(); ++k)
    EXPECT_LE(stiffness[k], penaltyStiffness[k] + 1e-9) << "t = " << time[k];
  std::vector<double> ratio(time.size());
  for (size_t k = 0; k < time.size(); ++k)
    ratio[k] = penaltyStiffness[k] > 0.0 ? stiffness[k] / penaltyStiffness[k] : 1.0;
  std::printf("[ measured ] felt stiffness %.1f N/m, penalties alone %.1f N/m at t = 0.95 s; "
              "ratio %.3f..%.3f over the second systole\n",
              range(time, stiffness, 0.94, 0.96, true), range(time, penaltyStiffness, 0.94, 0.96, true),
              range(time, ratio, 1.0, 1.3, false), range(time, ratio, 1.0, 1.3, true));
  EXPECT_LT(range(time, ratio, 0.85, 1.0, true), 0.9);
}

// The palpation task (config/tasks/beating_heart_palpation.yaml) played as the operator node
// plays it, without ROS: the virtual hand (config/operator.yaml's gains) follows the script and
// the force the bridge's pipeline sends; the closed jaws (one box along the shaft line from the
// trocar, 18 mm beyond the tip) are where the hand is; the scene steps at 100 Hz with the
// contact queried before each step. Through the first site's hold (t = 3 to 7 s; the beats
// starting at 4 and 5 s are checked) the wall pushes the hand back at every systole and lets
// it return in diastole (0.12 N in diastole, 0.8 to 1.2 N at systole, below the assessment's
// 1.5 N excessive-force threshold, the hand 0.8 mm up when written); no frame needs the guard.
TEST(BeatingHeartScene, ThePalpationTaskFeelsEveryBeat) {
  Scene scene = loadScene(kHeart);
  const TaskScript task =
      TaskScript::load(std::string(TT_SOURCE_DIR) + "/config/tasks/beating_heart_palpation.yaml");
  const Eigen::Vector3d trocar(-0.035, 0.075, 0.20);
  const auto jawsPose = [&](const Eigen::Vector3d& tip) {
    const Eigen::Vector3d along = (tip - trocar).normalized();  // into the wall
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), along).toRotationMatrix();
    pose.translation() = tip + 0.009 * along;
    return pose;
  };
  TissueContact contact(scene.system, *scene.contact, {closedJaws()});
  HapticPipeline haptics = bridgePipeline();
  VirtualHand hand(HandGains{}, task.sample(0.0).tip);
  std::vector<double> time, force, handZ;
  int halvings = 0;
  for (int f = 0; f < 600; ++f) {
    const double t = scene.system.state.t;
    const Eigen::Isometry3d pose = jawsPose(hand.position());
    contact.setTool(pose, {pose}, task.sample(t).jaw, t);
    const ContactResult& r = contact.update();
    const ContactModel model = publishedModel(r, f + 1, t, hand.position());
    ASSERT_EQ(haptics.submit(model, t, hand.position()), ModelVerdict::kAccepted) << "frame " << f;
    for (int tick = 1; tick <= 10; ++tick) {
      const double now = t + 0.001 * tick;
      const Eigen::Vector3d felt = haptics.tick(hand.position(), now, true);
      const TaskSample target = task.sample(now);
      hand.step(target.tip, target.tipVelocity, felt, 0.001);
    }
    time.push_back(t);
    force.push_back(r.f0.z());
    handZ.push_back(hand.position().z());
    const StepReport report = scene.integrator->advance(scene.system, scene.frameTime);
    ASSERT_TRUE(report.ok) << report.failure;
    halvings += guardOf(*scene.integrator)->lastFrame().halvings;
  }
  EXPECT_EQ(halvings, 0);
  // Each beat of the hold: the force in the first 0.4 s of the beat (systole) against the
  // force late in the beat (diastole, 0.8 to 1 s), and the hand pushed up with it.
  for (int beat = 4; beat < 6; ++beat) {
    double systole = 0.0, diastole = INFINITY, up = -INFINITY, rest = INFINITY;
    for (size_t k = 0; k < time.size(); ++k) {
      const double s = time[k] - beat;
      if (s >= 0.0 && s < 0.4) systole = std::max(systole, force[k]), up = std::max(up, handZ[k]);
      if (s > 0.8 && s < 1.0) diastole = std::min(diastole, force[k]), rest = std::min(rest, handZ[k]);
    }
    EXPECT_GT(diastole, 0.05) << "beat " << beat << ": the jaws rest on the wall";
    EXPECT_GT(systole, 1.5 * diastole) << "beat " << beat;
    EXPECT_GT(up - rest, 0.2e-3) << "beat " << beat << ": the hand is pushed back";
  }
}

}  // namespace
}  // namespace tt
