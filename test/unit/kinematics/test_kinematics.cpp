// The kinematic chain on the grasper's trocar geometry: forward kinematics against the hand
// computation, the Jacobian against finite differences, IK round trips and bad input.
#include <gtest/gtest.h>

#include <random>

#include "../kinematics_chain_util.h"
#include "tissue_trainer/core/kinematics/tip_ik.h"

namespace tt::kin {
namespace {

using test::grasperChain;
using test::kTrocar;
using test::shaftDirection;

Eigen::VectorXd joints(const Chain& c, double yaw, double pitch, double roll, double ins, double jaw) {
  Eigen::VectorXd q(c.numVariables());
  q[c.variableIndex("yaw")] = yaw;
  q[c.variableIndex("pitch")] = pitch;
  q[c.variableIndex("roll")] = roll;
  q[c.variableIndex("insertion")] = ins;
  q[c.variableIndex("jaw")] = jaw;
  return q;
}

TEST(KinematicChain, VariablesAreTheMovableNonMimicJoints) {
  const Chain c = grasperChain();
  ASSERT_EQ(c.numVariables(), 5);
  EXPECT_EQ(c.variables()[0].name, "yaw");
  EXPECT_EQ(c.variables()[4].name, "jaw");
  EXPECT_EQ(c.links()[0], "world");
  EXPECT_EQ(c.links().size(), 10u);  // world ... instrument_tip, jaw_actuator and two jaws
  EXPECT_EQ(c.links()[c.tipLink()], "instrument_tip");
}

TEST(KinematicChain, TipIsTrocarPlusInsertionAlongTheShaft) {
  const Chain c = grasperChain();
  // Zero joints: the shaft points along world -z.
  const Eigen::Isometry3d zero = c.tipPose(joints(c, 0, 0, 0, 0.1, 0));
  EXPECT_NEAR((zero.translation() - Eigen::Vector3d(-0.035, 0.075, 0.10)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((zero.linear().col(2) - Eigen::Vector3d(0, 0, -1)).norm(), 0.0, 1e-12);
  EXPECT_NEAR((zero.linear().col(1) - Eigen::Vector3d(0, 1, 0)).norm(), 0.0, 1e-12);
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> angle(-1.0, 1.0), ins(0.0, 0.25), roll(-3, 3);
  for (int k = 0; k < 50; ++k) {
    const double y = angle(rng), p = angle(rng), d = ins(rng), r = roll(rng);
    const Eigen::Isometry3d tip = c.tipPose(joints(c, y, p, r, d, 0.3));
    const Eigen::Vector3d expected = kTrocar + d * shaftDirection(y, p);
    EXPECT_NEAR((tip.translation() - expected).norm(), 0.0, 1e-12);
    EXPECT_NEAR((tip.linear().col(2) - shaftDirection(y, p)).norm(), 0.0, 1e-12);
    EXPECT_NEAR((tip.linear().transpose() * tip.linear() - Eigen::Matrix3d::Identity()).norm(), 0, 1e-12);
  }
}

TEST(KinematicChain, JawsMirrorEachOtherByHalfTheOpening) {
  const Chain c = grasperChain();
  std::vector<Eigen::Isometry3d> poses;
  c.forward(joints(c, 0.2, -0.1, 0.4, 0.12, 0.8), poses);
  const Eigen::Isometry3d& tip = poses[c.tipLink()];
  const Eigen::Vector3d up = tip.linear().transpose() * poses[c.linkIndex("jaw_upper")].linear().col(2);
  const Eigen::Vector3d down = tip.linear().transpose() * poses[c.linkIndex("jaw_lower")].linear().col(2);
  EXPECT_NEAR(up.y(), std::sin(0.4), 1e-12);   // opens toward the tip's +y
  EXPECT_NEAR(down.y(), -std::sin(0.4), 1e-12);
  EXPECT_NEAR(std::acos(up.dot(down)), 0.8, 1e-12);
  EXPECT_NEAR((poses[c.linkIndex("jaw_upper")].translation() - tip.translation()).norm(), 0, 1e-15);
}

TEST(KinematicChain, JacobianMatchesFiniteDifferences) {
  const Chain c = grasperChain();
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> u(-0.9, 0.9);
  const double h = 1e-6;
  for (int k = 0; k < 20; ++k) {
    double draws[5];  // the last joint's first, as g++ evaluated the former call's arguments
    for (int j = 4; j >= 0; --j) draws[j] = u(rng);
    const Eigen::VectorXd q =
        joints(c, draws[0], draws[1], 3 * draws[2], 0.12 + 0.1 * draws[3], 0.5 + 0.5 * draws[4]);
    const Jacobian jac = c.tipJacobian(q);
    for (int i = 0; i < c.numVariables(); ++i) {
      Eigen::VectorXd qp = q, qm = q;
      qp[i] += h;
      qm[i] -= h;
      const Eigen::Isometry3d tp = c.tipPose(qp), tm = c.tipPose(qm);
      const Eigen::Vector3d v = (tp.translation() - tm.translation()) / (2 * h);
      const Eigen::AngleAxisd rot(tp.linear() * tm.linear().transpose());
      const Eigen::Vector3d w = rot.axis() * rot.angle() / (2 * h);
      EXPECT_NEAR((jac.block<3, 1>(0, i) - v).norm(), 0.0, 1e-7) << "variable " << i;
      EXPECT_NEAR((jac.block<3, 1>(3, i) - w).norm(), 0.0, 1e-7) << "variable " << i;
    }
    // The jaw opens about the tip: it moves neither the tip nor its frame.
    EXPECT_EQ(jac.col(c.variableIndex("jaw")).norm(), 0.0);
  }
}

TEST(TipIk, RoundTripFromNearAndFarSeeds) {
  const Chain c = grasperChain();
  IkOptions options;
  options.variables = trocarPositionVariables(c);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> angle(-0.95, 0.95), ins(0.02, 0.24);
  for (int k = 0; k < 100; ++k) {
    const double insertion = ins(rng), pitch = angle(rng), yaw = angle(rng);  // g++'s order
    const Eigen::VectorXd truth = joints(c, yaw, pitch, 0.3, insertion, 0.2);
    const Eigen::Vector3d target = c.tipPose(truth).translation();
    for (const Eigen::VectorXd& seed :
         {Eigen::VectorXd(joints(c, 0, 0, 0.3, 0, 0.2)), Eigen::VectorXd(truth + 0.01 * Eigen::VectorXd::Ones(5))}) {
      const IkResult r = solveTipPosition(c, target, seed, options);
      ASSERT_TRUE(r.reached()) << "case " << k << " error " << r.error;
      EXPECT_LT((c.tipPose(r.q).translation() - target).norm(), 1e-6);
      for (int v : options.variables)  // unique: yaw and pitch within +-pi/2
        EXPECT_NEAR(r.q[v], truth[v], 1e-4) << "case " << k << " variable " << v;
      EXPECT_EQ(r.q[c.variableIndex("roll")], seed[c.variableIndex("roll")]);  // not moved
    }
  }
}

TEST(TipIk, UnreachableTargetsGiveTheClosestPose) {
  const Chain c = grasperChain();
  IkOptions options;
  options.variables = trocarPositionVariables(c);
  const Eigen::VectorXd seed = joints(c, 0, 0, 0, 0.1, 0);
  // Straight down the shaft but beyond full insertion: stops at 0.25 m, 0.05 m short.
  const IkResult deep = solveTipPosition(c, kTrocar + 0.30 * shaftDirection(0, 0), seed, options);
  EXPECT_EQ(deep.status, IkStatus::kUnreachable);
  EXPECT_NEAR(deep.q[c.variableIndex("insertion")], 0.25, 1e-9);
  EXPECT_NEAR(deep.error, 0.05, 1e-6);
  // Outside the yaw cone (yaw 1.4 rad > 1.0): yaw stops at its limit; the closest point on
  // that shaft line is the projection.
  const Eigen::Vector3d side = kTrocar + 0.1 * shaftDirection(1.4, 0.0);
  const IkResult wide = solveTipPosition(c, side, seed, options);
  EXPECT_EQ(wide.status, IkStatus::kUnreachable);
  EXPECT_NEAR(wide.q[c.variableIndex("yaw")], 1.0, 1e-6);
  EXPECT_NEAR(wide.error, 0.1 * std::sin(0.4), 1e-5);
  // Behind the trocar: insertion cannot go negative.
  const IkResult behind = solveTipPosition(c, kTrocar + Eigen::Vector3d(0, 0, 0.05), seed, options);
  EXPECT_EQ(behind.status, IkStatus::kUnreachable);
  EXPECT_TRUE(behind.q.allFinite());
  EXPECT_NEAR(behind.error, 0.05, 1e-6);
}

TEST(TipIk, BadInputNeverGivesNaN) {
  const Chain c = grasperChain();
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const Eigen::VectorXd seed = joints(c, 0.1, 0.1, 0, 0.1, 0);
  for (const Eigen::Vector3d& target : {Eigen::Vector3d(nan, 0, 0), Eigen::Vector3d(0, INFINITY, 0)}) {
    const IkResult r = solveTipPosition(c, target, seed);
    EXPECT_EQ(r.status, IkStatus::kInvalidInput);
    EXPECT_TRUE(r.q.allFinite());
    EXPECT_EQ(r.q, seed);
  }
  Eigen::VectorXd badSeed = seed;
  badSeed[1] = nan;
  const IkResult r = solveTipPosition(c, kTrocar, badSeed);
  EXPECT_EQ(r.status, IkStatus::kInvalidInput);
  EXPECT_TRUE(r.q.allFinite());
  EXPECT_EQ(solveTipPosition(c, kTrocar, Eigen::VectorXd::Zero(2)).status, IkStatus::kInvalidInput);
  // The target at the fulcrum itself (a singular pose) is reached by zero insertion.
  const IkResult fulcrum = solveTipPosition(c, kTrocar, seed);
  EXPECT_TRUE(fulcrum.reached());
  EXPECT_TRUE(fulcrum.q.allFinite());
  // Out-of-limit seeds are clamped first.
  const IkResult far = solveTipPosition(c, kTrocar + 0.1 * shaftDirection(0, 0), joints(c, 5, -5, 9, 3, 9));
  EXPECT_TRUE(far.reached());
  EXPECT_LE(far.q[c.variableIndex("jaw")], 1.2);
}

TEST(KinematicChain, RejectsMalformedJoints) {
  auto build = [](std::vector<JointSpec> joints, const char* tip = "b") {
    return [joints, tip] { Chain("a", joints, tip); };
  };
  JointSpec j;
  j.name = "j";
  j.parent = "a";
  j.child = "b";
  j.type = JointType::kRevolute;
  EXPECT_NO_THROW(build({j})());
  JointSpec bad = j;
  bad.parent = "nowhere";
  EXPECT_THROW(build({bad})(), std::invalid_argument);
  bad = j;
  bad.axis.setZero();
  EXPECT_THROW(build({bad})(), std::invalid_argument);
  bad = j;
  bad.axis.x() = NAN;
  EXPECT_THROW(build({bad})(), std::invalid_argument);
  bad = j;
  bad.lower = 1;
  bad.upper = 0;
  EXPECT_THROW(build({bad})(), std::invalid_argument);
  bad = j;
  bad.origin.translation().x() = INFINITY;
  EXPECT_THROW(build({bad})(), std::invalid_argument);
  bad = j;
  bad.mimic = "ghost";
  EXPECT_THROW(build({bad})(), std::invalid_argument);
  JointSpec twin = j;
  twin.name = "k";
  EXPECT_THROW(build({j, twin})(), std::invalid_argument);  // b with two parents
  JointSpec loop = j;
  loop.name = "k";
  loop.parent = "b";
  loop.child = "a";
  EXPECT_THROW(build({j, loop})(), std::invalid_argument);  // back to the root
  EXPECT_THROW(build({j}, "c")(), std::invalid_argument);
  try {
    build({bad})();
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("joint 'j'"), std::string::npos) << e.what();
  }
  const Chain c("a", {j}, "b");
  std::vector<Eigen::Isometry3d> poses;
  EXPECT_THROW(c.forward(Eigen::VectorXd::Zero(3), poses), std::invalid_argument);
}

}  // namespace
}  // namespace tt::kin
