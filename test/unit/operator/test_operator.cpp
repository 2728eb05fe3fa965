// The scripted operator's core: task scripts (format, interpolation, strict validation),
// the virtual hand, and the shipped tasks against the real scene geometry.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "../kinematics_chain_util.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/kinematics/tip_ik.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/operator/task_script.h"
#include "tissue_trainer/core/operator/virtual_hand.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

const std::string kTasks = std::string(TT_SOURCE_DIR) + "/config/tasks/";

std::string writeTask(const std::string& text) {
  const fs::path path = fs::temp_directory_path() / "tt_task.yaml";
  std::ofstream(path) << text;
  return path.string();
}

std::string loadError(const std::string& text) {
  const std::string path = writeTask(text);
  try {
    TaskScript::load(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(TaskScript, InterpolatesWithMinimumJerk) {
  const TaskScript task({{0.0, "start", {0, 0, 0}, 0.0}, {2.0, "approach", {0.1, 0, 0}, 1.0}});
  EXPECT_DOUBLE_EQ(task.duration(), 2.0);
  EXPECT_EQ(task.sample(0.0).tip, Eigen::Vector3d(0, 0, 0));
  EXPECT_NEAR(task.sample(1.0).tip.x(), 0.05, 1e-15);  // symmetric profile
  EXPECT_NEAR(task.sample(1.0).jaw, 0.5, 1e-15);
  EXPECT_NEAR(task.sample(1.0).tipVelocity.x(), 0.1 * 1.875 / 2.0, 1e-12);  // peak 15/8 mean
  EXPECT_EQ(task.sample(2.0).tip, Eigen::Vector3d(0.1, 0, 0));
  EXPECT_TRUE(task.sample(2.0).finished);
  EXPECT_FALSE(task.sample(1.9).finished);
  EXPECT_EQ(*task.sample(1.0).phase, "approach");
  EXPECT_EQ(task.sample(-1.0).tip, Eigen::Vector3d(0, 0, 0));
  EXPECT_EQ(task.sample(5.0).tip, Eigen::Vector3d(0.1, 0, 0));
  EXPECT_EQ(task.sample(NAN).tip, Eigen::Vector3d(0, 0, 0));
  // Velocity is the derivative of position, and vanishes at the keyframes.
  for (double t : {0.3, 0.9, 1.6}) {
    const double h = 1e-6;
    const double fd = (task.sample(t + h).tip.x() - task.sample(t - h).tip.x()) / (2 * h);
    EXPECT_NEAR(task.sample(t).tipVelocity.x(), fd, 1e-8);
  }
  EXPECT_NEAR(task.sample(1e-9).tipVelocity.norm(), 0.0, 1e-12);
  EXPECT_NEAR(task.sample(2.0 - 1e-9).tipVelocity.norm(), 0.0, 1e-12);
}

TEST(TaskScript, RejectsBadKeyframesInCode) {
  using K = std::vector<Keyframe>;
  EXPECT_THROW(TaskScript(K{}), std::invalid_argument);
  EXPECT_THROW(TaskScript(K{{1.0, "start", {0, 0, 0}, 0}}), std::invalid_argument);
  EXPECT_THROW(TaskScript(K{{0.0, "start", {0, 0, 0}, 0}, {0.0, "hold", {0, 0, 0}, 0}}), std::invalid_argument);
  EXPECT_THROW(TaskScript(K{{0.0, "dance", {0, 0, 0}, 0}}), std::invalid_argument);
  EXPECT_THROW(TaskScript(K{{0.0, "start", {NAN, 0, 0}, 0}}), std::invalid_argument);
  EXPECT_THROW(TaskScript(K{{0.0, "start", {0, 0, 0}, -0.1}}), std::invalid_argument);
}

TEST(TaskScript, JawCarriesOverAndOptionalKeysAreRead) {
  const TaskScript task = TaskScript::load(writeTask(R"(
name: demo
keyframes:
  - {t: 0, phase: start, tip: [0, 0, 0.1], jaw: 0.5}
  - {t: 1, phase: grasp, tip: [0, 0, 0.1], note: "closing, slowly"}
)"));
  EXPECT_EQ(task.name(), "demo");
  EXPECT_EQ(task.keyframes()[1].jaw, 0.5);
  ASSERT_NE(task.find("grasp"), nullptr);
  EXPECT_EQ(task.find("palpate"), nullptr);
}

TEST(TaskScript, MalformedFilesGiveOneLineWithFileLineAndKey) {
  const std::string head = "keyframes:\n  - {t: 0, phase: start, tip: [0, 0, 0]}\n";
  struct Case {
    std::string text, expected;
  } cases[] = {
      {head + "  - {t: 0, phase: hold, tip: [0, 0, 0]}\n", ":3: keyframes[1].t: expected a time after"},
      {head + "  - {t: 1, phase: dance, tip: [0, 0, 0]}\n", ":3: keyframes[1].phase: expected one of: start,"},
      {head + "  - {t: 1, phase: hold, tip: [0, 0]}\n", ":3: keyframes[1].tip: expected a list of 3 numbers"},
      {head + "  - {t: 1, phase: hold, tip: [0, 0, .nan]}\n", ":3: keyframes[1].tip[2]: expected a finite number"},
      {head + "  - {t: 1, phase: hold, tip: [0, 0, 0], jaw: -1}\n", ":3: keyframes[1].jaw: expected an opening angle"},
      {head + "  - {t: 1, phase: hold, tip: [0, 0, 0], speed: 2}\n", ":3: keyframes[1].speed: unknown key 'speed'"},
      {head + "  - {t: one, phase: hold, tip: [0, 0, 0]}\n", ":3: keyframes[1].t: expected a finite number"},
      {head + "  - {phase: hold, tip: [0, 0, 0]}\n", ":3: keyframes[1]: missing required key 't'"},
      {"keyframes:\n  - {t: 0.5, phase: start, tip: [0, 0, 0]}\n", ":2: keyframes[0].t: expected 0"},
      {"keyframes: []\n", ":1: keyframes: expected at least one keyframe"},
      {"name: x\n", ":1: missing required key 'keyframes'"},
      {head + "frame: trocar\n", ":3: frame: expected 'world'"},
      {head + "keyframe: []\n", ":3: keyframe: unknown key"},
      {"keyframes: [\n", ": not valid YAML"},
  };
  for (const Case& c : cases) {
    const std::string error = loadError(c.text);
    EXPECT_NE(error.find(c.expected), std::string::npos) << c.text << "\n-> " << error;
    EXPECT_EQ(error.find('\n'), std::string::npos) << error;
    EXPECT_EQ(error.rfind(fs::temp_directory_path().string(), 0), 0u) << error;
  }
  EXPECT_NE(loadError("").find("expected a map"), std::string::npos);
  const std::string missing = "/nonexistent/task.yaml";
  EXPECT_THROW(TaskScript::load(missing), InputError);
}

TEST(VirtualHand, SettlesOnTheTargetWithoutForce) {
  VirtualHand hand(HandGains{}, {0, 0, 0});
  const Eigen::Vector3d target(0.01, -0.02, 0.03);
  for (int i = 0; i < 2000; ++i) hand.step(target, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 1e-3);
  EXPECT_LT((hand.position() - target).norm(), 1e-6);
  EXPECT_LT(hand.velocity().norm(), 1e-5);
}

TEST(VirtualHand, ConstantForceDisplacesItByForceOverStiffness) {
  HandGains gains;
  gains.stiffness = 250;
  VirtualHand hand(gains, {0, 0, 0});
  const Eigen::Vector3d force(0, 0, 1.5);
  for (int i = 0; i < 3000; ++i) hand.step(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), force, 1e-3);
  EXPECT_NEAR(hand.position().z(), 1.5 / 250, 1e-8);
  EXPECT_NEAR(hand.position().head<2>().norm(), 0.0, 1e-15);
}

TEST(VirtualHand, StaysBoundedForStiffGainsAndLongSteps) {
  HandGains gains{0.01, 1e6, 0.0};  // undamped, omega * dt = 10 at 1 kHz
  VirtualHand hand(gains, {0.1, 0, 0});
  double peak = 0;
  for (int i = 0; i < 1000; ++i) {
    hand.step(Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 1e-3);
    peak = std::max(peak, hand.position().norm());
  }
  EXPECT_LE(peak, 0.1);
  EXPECT_LT(hand.position().norm(), 0.1);
}

TEST(VirtualHand, TracksAMovingTargetAndIgnoresNonFiniteInput) {
  const TaskScript task({{0.0, "start", {0, 0, 0.14}, 0}, {2.0, "approach", {0, 0, 0.07}, 0}});
  VirtualHand hand(HandGains{}, task.sample(0).tip);
  double lag = 0;
  for (int i = 1; i <= 2000; ++i) {
    const TaskSample s = task.sample(i * 1e-3);
    hand.step(s.tip, s.tipVelocity, Eigen::Vector3d::Zero(), 1e-3);
    lag = std::max(lag, (hand.position() - s.tip).norm());
  }
  EXPECT_LT(lag, 1e-3);  // under 1 mm behind a 3.5 cm/s (peak 6.6 cm/s) scripted motion
  const Eigen::Vector3d before = hand.position();
  hand.step(Eigen::Vector3d(NAN, 0, 0), Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), 1e-3);
  EXPECT_EQ(hand.position(), before);
  hand.step(before, Eigen::Vector3d::Zero(), Eigen::Vector3d(INFINITY, 0, 0), 1e-3);
  hand.step(before, Eigen::Vector3d::Zero(), Eigen::Vector3d::Zero(), NAN);
  EXPECT_TRUE(hand.position().allFinite());
  EXPECT_THROW(VirtualHand(HandGains{0, 1, 1}, before), std::invalid_argument);
  EXPECT_THROW(VirtualHand(HandGains{1, -1, 1}, before), std::invalid_argument);
  EXPECT_THROW(VirtualHand(HandGains{1, 1, NAN}, before), std::invalid_argument);
  EXPECT_THROW(VirtualHand(HandGains{}, Eigen::Vector3d(NAN, 0, 0)), std::invalid_argument);
}

// --- the shipped tasks against the scene geometry -----------------------------------

// Distance along the ray o + s d (|d| = 1) to its first crossing of the mesh surface.
double firstSurfaceHit(const Mesh& mesh, const Eigen::Vector3d& o, const Eigen::Vector3d& d) {
  double best = INFINITY;
  for (const Triangle& t : mesh.surface) {
    const Eigen::Vector3d a = mesh.rest.col(t[0]), e1 = mesh.rest.col(t[1]) - a,
                          e2 = mesh.rest.col(t[2]) - a;
    const Eigen::Vector3d h = d.cross(e2);
    const double det = e1.dot(h);
    if (std::abs(det) < 1e-15) continue;
    const Eigen::Vector3d s = o - a;
    const double u = s.dot(h) / det;
    const Eigen::Vector3d q = s.cross(e1);
    const double v = d.dot(q) / det;
    const double dist = e2.dot(q) / det;
    if (u >= 0 && v >= 0 && u + v <= 1 && dist > 0) best = std::min(best, dist);
  }
  return best;
}

bool insideMesh(const Mesh& mesh, const Eigen::Vector3d& p) {
  for (const Tet& t : mesh.tets) {
    Eigen::Matrix3d m;
    for (int k = 0; k < 3; ++k) m.col(k) = mesh.rest.col(t[k + 1]) - mesh.rest.col(t[0]);
    const Eigen::Vector3d b = m.inverse() * (p - mesh.rest.col(t[0]));
    if ((b.array() >= 0).all() && b.sum() <= 1) return true;
  }
  return false;
}

// The liver tasks (config/tasks/liver_*.yaml) against the rest surface of their scene's mesh:
// every keyframe reachable through the trocar; the closed jaws, 18 mm beyond the tip along
// the shaft, stop 5 mm above the surface on approach and release and press `pressDepth` into
// it (the novice: between `pressDepth` - 5 mm and `pressDepth`, releases anywhere).
void checkLiverTask(const std::string& name, double pressDepth, bool exactApproach) {
  SCOPED_TRACE(name);
  const TaskScript task = TaskScript::load(kTasks + name);
  Mesh liver = readMesh(std::string(TT_SOURCE_DIR) + "/config/meshes/liver.msh");
  liver.rest *= 0.025;  // as config/scenes/liver_palpation.yaml
  const double jawLength = 0.018;
  const kin::Chain chain = kin::test::grasperChain();
  kin::IkOptions ik;
  ik.variables = kin::trocarPositionVariables(chain);
  int palpations = 0;
  for (size_t i = 0; i < task.keyframes().size(); ++i) {
    const Keyframe& k = task.keyframes()[i];
    const kin::IkResult r = kin::solveTipPosition(chain, k.tip, Eigen::VectorXd::Zero(5), ik);
    EXPECT_TRUE(r.reached()) << "keyframe " << i << " error " << r.error;
    const Eigen::Vector3d d = (k.tip - kin::test::kTrocar).normalized();
    const Eigen::Vector3d jawTips = k.tip + jawLength * d;
    const double jawInsertion = (jawTips - kin::test::kTrocar).norm();
    const double surface = firstSurfaceHit(liver, kin::test::kTrocar, d);
    ASSERT_TRUE(std::isfinite(surface)) << "keyframe " << i << ": the shaft line misses the liver";
    if (k.phase == "palpate") {
      ++palpations;
      EXPECT_TRUE(insideMesh(liver, jawTips)) << "keyframe " << i;
      if (exactApproach)
        EXPECT_NEAR(jawInsertion - surface, pressDepth, 0.001) << "keyframe " << i;
      else
        EXPECT_TRUE(jawInsertion - surface > pressDepth - 0.005 && jawInsertion - surface < pressDepth + 0.001)
            << "keyframe " << i << ": the jaw tips " << jawInsertion - surface << " m deep";
    } else if (k.phase == "approach" || k.phase == "release") {
      EXPECT_FALSE(insideMesh(liver, jawTips) && exactApproach) << "keyframe " << i;
      if (exactApproach) EXPECT_NEAR(surface - jawInsertion, 0.005, 0.001) << "keyframe " << i;
    } else if (k.phase != "hold") {
      EXPECT_GT(surface - jawInsertion, 0.03) << "keyframe " << i << " should be clear of the liver";
    }
  }
  EXPECT_GE(palpations, 2);
}

TEST(ShippedTasks, LiverTasksPressTheJawTipsIntoTheLiverAsTheySay) {
  checkLiverTask("liver_palpation.yaml", 0.010, true);
  checkLiverTask("liver_expert.yaml", 0.010, true);
  checkLiverTask("liver_novice.yaml", 0.020, false);
}

TEST(ShippedTasks, MuscleGraspClosesTheJawOnTheBellySurface) {
  const TaskScript task = TaskScript::load(kTasks + "muscle_grasp.yaml");
  const double belly = 0.04, radius = 0.015, jawLength = 0.018;
  const kin::Chain chain = kin::test::grasperChain();
  kin::IkOptions ik;
  ik.variables = kin::trocarPositionVariables(chain);
  for (const Keyframe& k : task.keyframes())
    EXPECT_TRUE(kin::solveTipPosition(chain, k.tip, Eigen::VectorXd::Zero(5), ik).reached()) << k.time;
  const Keyframe* grasp = task.find("grasp");
  ASSERT_NE(grasp, nullptr);
  EXPECT_EQ(grasp->jaw, 0.0);
  // Straight below the trocar; the jaw pivot is above the surface, the jaw tips below it.
  EXPECT_NEAR((grasp->tip.head<2>() - Eigen::Vector2d(-0.035, 0.075)).norm(), 0.0, 1e-12);
  EXPECT_GT(grasp->tip.z(), belly + radius);
  EXPECT_LT(grasp->tip.z() - jawLength, belly + radius);
  EXPECT_GT(grasp->tip.z() - jawLength, belly);
  // The jaw is open when it arrives at the grasp pose and when it lets go.
  const TaskSample arrive = task.sample(task.keyframes()[2].time);
  EXPECT_GT(arrive.jaw, 0.5);
  ASSERT_NE(task.find("retract"), nullptr);
  EXPECT_GT(task.find("retract")->tip.z(), grasp->tip.z());
  EXPECT_EQ(task.find("retract")->jaw, 0.0);
  ASSERT_NE(task.find("release"), nullptr);
  EXPECT_GT(task.find("release")->jaw, 0.5);
  EXPECT_GT(task.keyframes().back().tip.z() - jawLength, belly + radius + 0.05);
}

// The beating ventricle (config/scenes/beating_heart.yaml): the closed jaws, 18 mm beyond the tip
// along the shaft, stop 5 mm above the rest epicardium and press 1.5 mm into it.
TEST(ShippedTasks, BeatingHeartPalpationPressesTheJawTipsOneAndAHalfMillimetresIn) {
  const TaskScript task = TaskScript::load(kTasks + "beating_heart_palpation.yaml");
  const Mesh wall = loadScene(std::string(TT_SOURCE_DIR) + "/config/scenes/beating_heart.yaml").system.mesh;
  const double jawLength = 0.018;
  const kin::Chain chain = kin::test::grasperChain();
  kin::IkOptions ik;
  ik.variables = kin::trocarPositionVariables(chain);
  int palpations = 0;
  for (size_t i = 0; i < task.keyframes().size(); ++i) {
    const Keyframe& k = task.keyframes()[i];
    const kin::IkResult r = kin::solveTipPosition(chain, k.tip, Eigen::VectorXd::Zero(5), ik);
    EXPECT_TRUE(r.reached()) << "keyframe " << i << " error " << r.error;
    EXPECT_EQ(k.jaw, 0.0) << "keyframe " << i;
    const Eigen::Vector3d d = (k.tip - kin::test::kTrocar).normalized();
    const Eigen::Vector3d jawTips = k.tip + jawLength * d;
    const double jawInsertion = (jawTips - kin::test::kTrocar).norm();
    const double surface = firstSurfaceHit(wall, kin::test::kTrocar, d);
    ASSERT_TRUE(std::isfinite(surface)) << "keyframe " << i << ": the shaft line misses the wall";
    if (k.phase == "palpate" || k.phase == "hold") {
      palpations += k.phase == "palpate";
      EXPECT_TRUE(insideMesh(wall, jawTips)) << "keyframe " << i;
      EXPECT_NEAR(jawInsertion - surface, 0.0015, 1e-4) << "keyframe " << i;
    } else if (k.phase == "approach" || k.phase == "release") {
      EXPECT_NEAR(surface - jawInsertion, 0.005, 2e-4) << "keyframe " << i;
    } else {
      EXPECT_GT(surface - jawInsertion, 0.05) << "keyframe " << i << " should be clear of the wall";
    }
  }
  EXPECT_EQ(palpations, 2);
}

}  // namespace
}  // namespace tt
