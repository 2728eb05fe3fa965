// config/scenes/beating_heart.yaml, the beating ventricle of the training graph: it loads with
// the Hunter law, the volume term and the twitch, the fibres turning through the wall; at every
// beat the wall thickens, the apex moves towards the base and the cavity empties, and all is
// back at rest before the next beat; a tool held on the epicardium feels the beat through the
// contact model the simulation node publishes (TissueContact's f0) and the haptic bridge's
// pipeline; and the palpation task, played through the operator's virtual hand, feels every
// beat.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "tissue_trainer/core/contact/tissue_contact.h"
#include "tissue_trainer/core/haptics/haptic_pipeline.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/active_tension.h"
#include "tissue_trainer/core/operator/task_script.h"
#include "tissue_trainer/core/operator/virtual_hand.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

const std::string kHeart = std::string(TT_SOURCE_DIR) + "/config/scenes/beating_heart.yaml";

// The scene's generator cells (through the wall, apex to base, around) and placement.
EllipsoidShape heartShape() {
  EllipsoidShape shape;
  shape.transmural = 2, shape.meridional = 6, shape.circumferential = 12;
  return shape;
}
const Eigen::Vector3d kLongAxis(-0.983255, 0.0, -0.182236);   // towards the base (world)
const Eigen::Vector3d kBaseCentre(-0.0600907, 0.075, 0.0265221);
// The epicardial node under the trocar, ring 4 of 6 from the apex on the column facing up.
constexpr int kSiteRing = 4, kSiteColumn = 6;
const Eigen::Vector3d kSite(-0.035, 0.075, 0.055);
constexpr double kEpicardium = 0.055;  // its height

int nearestNode(const Mesh& mesh, const Eigen::Vector3d& p) {
  Eigen::Index best = 0;
  (mesh.rest.colwise() - p).colwise().squaredNorm().minCoeff(&best);
  return static_cast<int>(best);
}

Eigen::Vector3d displacement(const System& s, int node) {
  return s.state.x.segment<3>(3 * node) - s.mesh.rest.col(node);
}

Eigen::Vector3d nodePosition(const System& s, int node) { return s.state.x.segment<3>(3 * node); }

// The volume the endocardium encloses with the plane of the base: the cone from the base
// centre over the endocardial triangles (the lid adds nothing, its apex being in its plane).
double heartCavityVolume(const System& s) {
  const EllipsoidShape shape = heartShape();
  const int first = shape.transmural + 1, perLayer = shape.meridional * shape.circumferential;
  const auto endocardial = [&](int n) { return n == 0 || (n >= first && n < first + perLayer); };
  double v = 0.0;
  for (const Triangle& t : s.mesh.surface)
    if (endocardial(t[0]) && endocardial(t[1]) && endocardial(t[2]))
      v += (nodePosition(s, t[0]) - kBaseCentre)
               .dot((nodePosition(s, t[1]) - kBaseCentre).cross(nodePosition(s, t[2]) - kBaseCentre)) / 6.0;
  return std::abs(v);
}

double heartWallVolume(const System& s) {
  double v = 0.0;
  const Eigen::Map<const Eigen::Matrix3Xd> x(s.state.x.data(), 3, s.numNodes());
  for (const Tet& t : s.mesh.tets) v += tetVolume(x, t);
  return v;
}

// The largest Green strain along the sheet axis (through the wall) over the tets: the Hunter
// law's pole there is at 0.429 (Table 2.1).
double largestSheetStrain(const System& s) {
  double largest = -INFINITY;
  for (int e = 0; e < s.mesh.numTets(); ++e) {
    const Tet& t = s.mesh.tets[e];
    Eigen::Matrix3d rest, now;
    for (int k = 0; k < 3; ++k) {
      rest.col(k) = s.mesh.rest.col(t[k + 1]) - s.mesh.rest.col(t[0]);
      now.col(k) = nodePosition(s, t[k + 1]) - nodePosition(s, t[0]);
    }
    const Eigen::Matrix3d F = now * rest.inverse();
    const Eigen::Vector3d sheet = s.mesh.fibreFrame[e].col(1);
    largest = std::max(largest, 0.5 * (sheet.dot(F.transpose() * F * sheet) - 1.0));
  }
  return largest;
}

struct Beats {
  std::vector<double> time, thickness, baseToApex, cavity, wall, epicardialRise, midWall, sheetStrain;
  int halvings = 0;
};

// Runs the scene frame by frame for `duration` s; every frame must pass at once.
Beats run(Scene& scene, double duration) {
  const EllipsoidShape shape = heartShape();
  const int epi = ellipsoidNode(shape, shape.transmural, kSiteRing, kSiteColumn);
  const int mid = ellipsoidNode(shape, 1, kSiteRing, kSiteColumn);
  const int endo = ellipsoidNode(shape, 0, kSiteRing, kSiteColumn);
  const int apex = ellipsoidNode(shape, shape.transmural, 0, 0);
  Beats b;
  const int frames = static_cast<int>(std::lround(duration / scene.frameTime));
  const System& s = scene.system;
  for (int f = 0; f <= frames; ++f) {
    if (f > 0) {
      const StepReport r = scene.integrator->advance(scene.system, scene.frameTime);
      EXPECT_TRUE(r.ok) << r.failure;
      b.halvings += guardOf(*scene.integrator)->lastFrame().halvings;
    }
    b.time.push_back(s.state.t);
    b.thickness.push_back((nodePosition(s, epi) - nodePosition(s, endo)).norm());
    b.baseToApex.push_back((nodePosition(s, apex) - kBaseCentre).dot(-kLongAxis));
    b.cavity.push_back(heartCavityVolume(s));
    b.wall.push_back(heartWallVolume(s));
    b.epicardialRise.push_back(displacement(s, epi).z());
    b.midWall.push_back(displacement(s, mid).norm());
    b.sheetStrain.push_back(largestSheetStrain(s));
  }
  return b;
}

double maxOver(const Beats& b, const std::vector<double>& v, double t0, double t1) {
  double m = -INFINITY;
  for (size_t k = 0; k < v.size(); ++k)
    if (b.time[k] > t0 - 1e-9 && b.time[k] < t1 + 1e-9) m = std::max(m, v[k]);
  return m;
}

double minOver(const Beats& b, const std::vector<double>& v, double t0, double t1) {
  double m = INFINITY;
  for (size_t k = 0; k < v.size(); ++k)
    if (b.time[k] > t0 - 1e-9 && b.time[k] < t1 + 1e-9) m = std::min(m, v[k]);
  return m;
}

TEST(BeatingHeartScene, LoadsTheVentricle) {
  const Scene scene = loadScene(kHeart);
  ASSERT_EQ(scene.system.models.size(), 3u);
  EXPECT_STREQ(scene.system.models[0]->name(), "virtual_hexahedron");
  EXPECT_STREQ(scene.system.models[1]->name(), "virtual_hexahedron");
  EXPECT_NE(dynamic_cast<const adamss::ActiveTensionModel*>(scene.system.models[2].get()), nullptr);
  ASSERT_TRUE(scene.contact.has_value());
  EXPECT_NEAR(scene.frameTime, 0.01, 1e-12);
  const Mesh& mesh = scene.system.mesh;
  const EllipsoidShape shape = heartShape();
  EXPECT_EQ(mesh.numNodes(), (shape.transmural + 1) * (1 + shape.meridional * shape.circumferential));
  // The epicardial node under the trocar; the apex 62.5 mm from the base; the base fixed.
  EXPECT_EQ(nearestNode(mesh, kSite), ellipsoidNode(shape, shape.transmural, kSiteRing, kSiteColumn));
  EXPECT_LT((mesh.rest.col(nearestNode(mesh, kSite)) - kSite).norm(), 1e-4);
  EXPECT_NEAR((mesh.rest.col(shape.transmural) - kBaseCentre).dot(-kLongAxis), 0.0625, 1e-6);
  EXPECT_EQ(scene.system.constrainedDofs.size(), 3u * (shape.transmural + 1) * shape.circumferential);
  // The fibre turns from +60 degrees at the endocardium to -60 at the epicardium, measured
  // from the circumferential direction (the long axis x the radius) towards the base, about
  // the sheet (the wall normal, outwards).
  const auto layerOf = [&](int node) {
    return node <= shape.transmural ? node
                                    : (node - shape.transmural - 1) / (shape.meridional * shape.circumferential);
  };
  double inner = 0, outer = 0;
  int innerCount = 0, outerCount = 0;
  for (int e = 0; e < mesh.numTets(); ++e) {
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    int highest = 0;
    for (int a : mesh.tets[e]) c += 0.25 * mesh.rest.col(a), highest = std::max(highest, layerOf(a));
    const Eigen::Vector3d radial = (c - kBaseCentre) - (c - kBaseCentre).dot(kLongAxis) * kLongAxis;
    const Eigen::Vector3d around = kLongAxis.cross(radial).normalized();
    const Eigen::Matrix3d& B = mesh.fibreFrame[e];
    EXPECT_NEAR(B.col(1).dot(around), 0.0, 1e-5) << "tet " << e;
    EXPECT_GT(B.col(1).dot(radial.normalized()), 0.0) << "tet " << e;
    const Eigen::Vector3d towardsBase = B.col(1).cross(around);
    const double angle = std::atan2(B.col(0).dot(towardsBase), B.col(0).dot(around)) * 180.0 / M_PI;
    if (highest <= 1) inner += angle, ++innerCount;
    else outer += angle, ++outerCount;
  }
  // The centroids of the outer layer lie deeper than those of the inner one: the faces are
  // chords of the spheroids (35.5 and -18.5 degrees when written).
  EXPECT_GT(inner / innerCount, 25.0);
  EXPECT_LT(outer / outerCount, -12.0);
}

// Every beat: the wall under the trocar thickens, well short of the Hunter law's sheet pole, the
// cavity empties while the wall keeps its volume, the long axis changes by less than 15 %; all
// back at rest before the next twitch starts (t = 1 s); the second beat as the first.
TEST(BeatingHeartScene, TheVentricleBeatsOnceASecond) {
  Scene scene = loadScene(kHeart);
  const Beats b = run(scene, 1.3);
  EXPECT_EQ(b.halvings, 0);
  const double thickening = maxOver(b, b.thickness, 0.0, 0.6) / b.thickness[0] - 1.0;
  const double shortening = b.baseToApex[0] - minOver(b, b.baseToApex, 0.0, 0.6);
  const double ejected = 1.0 - minOver(b, b.cavity, 0.0, 0.6) / b.cavity[0];
  const double wallChange = 1.0 - minOver(b, b.wall, 0.0, 0.6) / b.wall[0];
  const double systole = maxOver(b, b.midWall, 0.0, 0.6);
  const double diastole = maxOver(b, b.midWall, 0.9, 1.0);
  const double second = maxOver(b, b.midWall, 1.0, 1.3);
  const double firstSame = maxOver(b, b.midWall, 0.0, 0.3);
  const double sheetStrain = maxOver(b, b.sheetStrain, 0.0, 0.6);
  std::printf("[ measured ] wall under the trocar %.2f mm, thickens by %.1f %%; base to apex %.2f mm, "
              "shortens by %.2f mm (%.1f %%; longest %.2f mm); cavity %.2f ml, ejects %.1f %%; wall "
              "volume %.2f ml, loses at most %.2f %%; largest sheet Green strain %.3f; epicardium "
              "under the trocar moves %+.2f .. %+.2f mm in z; mid-wall node %.2f mm at systole, "
              "%.2g mm at t = 0.9 .. 1 s\n",
              1e3 * b.thickness[0], 100 * thickening, 1e3 * b.baseToApex[0], 1e3 * shortening,
              100 * shortening / b.baseToApex[0], 1e3 * maxOver(b, b.baseToApex, 0.0, 0.6),
              1e6 * b.cavity[0], 100 * ejected, 1e6 * b.wall[0], 100 * wallChange, sheetStrain,
              1e3 * minOver(b, b.epicardialRise, 0.0, 0.6),
              1e3 * maxOver(b, b.epicardialRise, 0.0, 0.6), 1e3 * systole, 1e3 * diastole);
  // 12.6 % thicker, the largest sheet strain 0.192 against the pole's 0.429, 31 % ejected, the
  // wall 3.3 % smaller, the long axis 5.6 mm longer when written (docs/adamss.md says why).
  EXPECT_GT(thickening, 0.08);
  EXPECT_LT(sheetStrain, 0.3);
  EXPECT_GT(ejected, 0.2);
  EXPECT_LT(wallChange, 0.05);
  const double lengthening = maxOver(b, b.baseToApex, 0.0, 0.6) - b.baseToApex[0];
  EXPECT_LT(std::max(shortening, lengthening), 0.15 * b.baseToApex[0]);
  EXPECT_GT(systole, 0.5e-3);
  EXPECT_LT(diastole, 0.05 * systole);
  EXPECT_NEAR(second, firstSame, 0.05 * systole);  // the same beat again
  EXPECT_GT(second, 0.5 * systole);
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

// The closed jaws (one box of the two jaws' size, 4 x 3.2 x 18 mm, along the shaft) held 2 mm
// into the epicardium under the trocar (the task presses 1.5 mm). Each frame, as the
// simulation node does, the contact is queried before the step and its model (f0, K at the
// tip) goes to the haptic bridge's pipeline (ForceExtrapolator and SafetyFilter with the
// bridge's parameters, config/haptic_bridge.yaml), ticked at 1 kHz with the device where the
// tool is. The empty ventricle is soft to the press (its wall gives way), and at systole it
// draws away from the held jaws: the force the device gets drops to zero in every systole and
// returns in diastole. The beat reaches the hand through f0.
TEST(BeatingHeartScene, AToolHeldOnTheWallFeelsItBeat) {
  Scene scene = loadScene(kHeart);
  ASSERT_TRUE(scene.contact.has_value());
  const double depth = 0.002;
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = Eigen::Vector3d(kSite.x(), kSite.y(), kEpicardium - depth + 0.009);
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
  const double systole = range(time, force, 1.1, 1.3, false);
  std::printf("[ measured ] held jaws: %.3f .. %.3f N at t = 0.85 .. 1 s (diastole); %.3f .. %.3f N "
              "over t = 1.1 .. 1.3 s (systole)\n",
              diastole, range(time, force, 0.85, 1.0, true), systole,
              range(time, force, 1.1, 1.3, true));
  EXPECT_GT(diastole, 0.005);          // 0.013 N when written
  EXPECT_LT(systole, 0.2 * diastole);  // the wall has left the jaws (0 N)
  const double feltDiastole = range(feltTime, felt, 0.90, 1.0, false);
  const double feltSystole = range(feltTime, felt, 1.1, 1.3, false);
  EXPECT_GT(feltDiastole, 0.5 * diastole);
  EXPECT_LT(feltSystole, 0.2 * feltDiastole);
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
// starting at 4 and 5 s are checked) the jaws rest on the wall in diastole and the wall draws
// away from them at every systole; no frame needs the guard.
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
  std::vector<double> time, force;
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
    const StepReport report = scene.integrator->advance(scene.system, scene.frameTime);
    ASSERT_TRUE(report.ok) << report.failure;
    halvings += guardOf(*scene.integrator)->lastFrame().halvings;
  }
  EXPECT_EQ(halvings, 0);
  // Each beat of the hold: the force late in the beat (diastole, 0.8 to 1 s) against the
  // force in systole (0.1 to 0.4 s into the beat), when the wall draws away from the jaws.
  for (int beat = 4; beat < 6; ++beat) {
    double systole = INFINITY, systoleLargest = 0.0, diastole = INFINITY;
    for (size_t k = 0; k < time.size(); ++k) {
      const double s = time[k] - beat;
      if (s >= 0.1 && s < 0.4) systole = std::min(systole, force[k]), systoleLargest = std::max(systoleLargest, force[k]);
      if (s > 0.8 && s < 1.0) diastole = std::min(diastole, force[k]);
    }
    std::printf("[ measured ] beat %d: at least %.3f N in diastole, %.3f .. %.3f N in systole\n",
                beat, diastole, systole, systoleLargest);
    EXPECT_GT(diastole, 0.005) << "beat " << beat << ": the jaws rest on the wall";
    EXPECT_LT(systole, 0.2 * diastole) << "beat " << beat << ": the wall draws away";
  }
}

}  // namespace
}  // namespace tt
