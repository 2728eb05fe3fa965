// Instrument-tissue contact (tissue_trainer_contact, Bullet): penalty forces of a sphere and
// a capsule pressed into the top of a box grid, the contact stiffness against a finite
// difference, no contact, grasp and release, Newton's third law; the tool shapes' penetration
// depth and normal; the contact per unit area against the pressure integral at two
// resolutions and two sample spacings, and against a tool thinner than the triangles.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <string>

#include "tissue_trainer/core/contact/tissue_contact.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace tt {
namespace {

// A 4 cm x 2 cm x 4 cm block (3 x 3 x 3 nodes, 2 cm cells); its top face is y = 0.02.
System block() {
  Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d(0.04, 0.02, 0.04), TetSplit::kFiveMirrored);
  return System(std::move(mesh), {Material::transverselyIsotropic(3e3, 0.4, 3e3, 0.4, 1000)});
}

// Incentre of a top-face triangle (all three nodes on y = top) away from the block's edges.
Eigen::Vector3d topIncentre(const System& s, double top) {
  for (const Triangle& t : s.mesh.surface) {
    Eigen::Vector3d p[3];
    bool onTop = true;
    for (int k = 0; k < 3; ++k) {
      p[k] = s.mesh.rest.col(t[k]);
      onTop = onTop && std::abs(p[k].y() - top) < 1e-12;
    }
    if (!onTop) continue;
    const double a = (p[1] - p[2]).norm(), b = (p[2] - p[0]).norm(), c = (p[0] - p[1]).norm();
    return (a * p[0] + b * p[1] + c * p[2]) / (a + b + c);
  }
  ADD_FAILURE() << "no top triangle";
  return Eigen::Vector3d::Zero();
}

ToolShape sphere(double r) {
  ToolShape s;
  s.type = ToolShape::Type::kSphere;
  s.radius = r;
  s.link = "tip";
  return s;
}

Eigen::Isometry3d at(const Eigen::Vector3d& p) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = p;
  return pose;
}

ContactSettings settings(double k = 300.0) {
  ContactSettings c;
  c.stiffness = k;
  c.graspStiffness = 150.0;
  return c;
}

// A capsule, a cylinder and a box (each 2 cm long, 3 mm radius or 1 x 0.4 cm across) and a
// rotated, shifted pose to test them at.
struct PosedShapes {
  ToolShape capsule, cylinder, box;
  Eigen::Isometry3d pose;
};

PosedShapes posedShapes() {
  PosedShapes s;
  s.capsule.type = ToolShape::Type::kCapsule, s.capsule.radius = 0.003, s.capsule.length = 0.02;
  s.cylinder.type = ToolShape::Type::kCylinder, s.cylinder.radius = 0.003, s.cylinder.length = 0.02;
  s.box.type = ToolShape::Type::kBox, s.box.size = Eigen::Vector3d(0.01, 0.004, 0.02);
  s.pose = Eigen::Isometry3d::Identity();
  s.pose.rotate(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
  s.pose.translation() = Eigen::Vector3d(0.01, -0.02, 0.03);
  return s;
}

TEST(Contact, SpherePressedIntoTheTopGivesNormalDepthAndForce) {
  System s = block();
  TissueContact contact(s, settings(), {sphere(0.005)});
  const Eigen::Vector3d centre = topIncentre(s, 0.02);
  const double depth = 0.001;
  const Eigen::Vector3d tip = centre + Eigen::Vector3d(0, 0.005 - depth, 0);
  contact.setTool(at(tip), {at(tip)}, 1.0, 0.0);
  const ContactResult& r = contact.update();
  ASSERT_TRUE(r.inContact);
  ASSERT_EQ(r.points.size(), 1u);
  EXPECT_NEAR(r.points[0].normal.y(), 1.0, 1e-6);
  EXPECT_NEAR(r.points[0].depth, depth, 1e-6);
  EXPECT_LT((r.points[0].tissuePoint - centre).norm(), 1e-6);
  EXPECT_LT((r.f0 - Eigen::Vector3d(0, 300.0 * depth, 0)).norm(), 1e-3 * 300.0 * depth);
  Eigen::Matrix3d expectedK = Eigen::Matrix3d::Zero();
  expectedK(1, 1) = 300.0;
  EXPECT_LT((r.K - expectedK).norm(), 1e-3);
  EXPECT_LT((r.x0 - tip).norm(), 1e-15);
}

// The depth falls by the distance moved along the outward normal: its gradient is -outward.
// Points well inside, away from the ridges where the nearest surface changes.
TEST(ToolShapePenetration, DepthAndNormalOfEachShapeAgreeWithAFiniteDifference) {
  const auto [capsule, cylinder, box, pose] = posedShapes();
  struct Case {
    ToolShape shape;
    Eigen::Vector3d local;  // the point in the shape's frame
    double depth;
    Eigen::Vector3d outward;  // in the shape's frame
  };
  const Case cases[] = {
      {sphere(0.005), {0.001, 0.002, -0.001}, 0.005 - std::sqrt(6e-6), Eigen::Vector3d(1, 2, -1).normalized()},
      {capsule, {0.001, 0.0, 0.004}, 0.002, Eigen::Vector3d::UnitX()},             // beside the axis
      {capsule, {0.0, 0.001, 0.0105}, 0.003 - std::hypot(0.001, 0.0005), Eigen::Vector3d(0, 2, 1).normalized()},  // in a cap
      {cylinder, {0.0, -0.002, 0.001}, 0.001, -Eigen::Vector3d::UnitY()},          // nearer the side
      {cylinder, {0.0005, 0.0, -0.0095}, 0.0005, -Eigen::Vector3d::UnitZ()},       // nearer an end
      {box, {0.001, 0.0015, -0.002}, 0.0005, Eigen::Vector3d::UnitY()},            // the thin axis
  };
  for (const Case& c : cases) {
    const Eigen::Vector3d p = pose * c.local;
    double depth = 0.0;
    Eigen::Vector3d outward;
    ASSERT_TRUE(penetration(c.shape, pose, p, depth, outward)) << c.local.transpose();
    EXPECT_NEAR(depth, c.depth, 1e-12) << c.local.transpose();
    EXPECT_LT((outward - pose.linear() * c.outward).norm(), 1e-12) << c.local.transpose();
    const double h = 1e-7;
    for (int axis = 0; axis < 3; ++axis) {
      double ahead = 0.0, behind = 0.0;
      Eigen::Vector3d unused;
      ASSERT_TRUE(penetration(c.shape, pose, p + h * Eigen::Vector3d::Unit(axis), ahead, unused));
      ASSERT_TRUE(penetration(c.shape, pose, p - h * Eigen::Vector3d::Unit(axis), behind, unused));
      EXPECT_NEAR((behind - ahead) / (2 * h), outward[axis], 1e-6) << c.local.transpose();
    }
    double outside = 0.0;
    Eigen::Vector3d unused;
    EXPECT_FALSE(penetration(c.shape, pose, p + (depth + 1e-6) * outward, outside, unused))
        << c.local.transpose();
  }
}

// The exit distance along a direction: the point moved that far lies on the surface (inside
// just before, outside just after), and two cases worked by hand.
TEST(ToolShapeExit, TheRayLeavesEachShapeAtTheExitDistance) {
  const auto [capsule, cylinder, box, pose] = posedShapes();
  const ToolShape shapes[] = {sphere(0.005), capsule, cylinder, box};
  const Eigen::Vector3d directions[] = {Eigen::Vector3d::UnitX(), -Eigen::Vector3d::UnitY(),
                                        Eigen::Vector3d(1, -2, 3).normalized(),
                                        Eigen::Vector3d(0.1, 0.2, -1).normalized()};
  for (const ToolShape& shape : shapes)
    for (const Eigen::Vector3d& local : {Eigen::Vector3d(0.001, 0.001, 0.0),
                                         Eigen::Vector3d(-0.0005, 0.0002, 0.0095)}) {
      const Eigen::Vector3d p = pose * local;
      double depth = 0.0;
      Eigen::Vector3d unused;
      if (!penetration(shape, pose, p, depth, unused)) continue;  // the sphere's far point
      for (const Eigen::Vector3d& u : directions) {
        double s = 0.0;
        ASSERT_TRUE(exitDistance(shape, pose, p, u, s)) << local.transpose();
        EXPECT_GE(s, depth - 1e-12) << "never shorter than the nearest way out";
        EXPECT_TRUE(penetration(shape, pose, p + (s - 1e-9) * u, depth, unused)) << local.transpose();
        EXPECT_FALSE(penetration(shape, pose, p + (s + 1e-9) * u, depth, unused)) << local.transpose();
      }
    }
  double s = 0.0;
  ASSERT_TRUE(exitDistance(box, pose, pose * Eigen::Vector3d(0.001, 0.0015, -0.002),
                           pose.linear() * -Eigen::Vector3d::UnitY(), s));
  EXPECT_NEAR(s, 0.0035, 1e-15);
  ASSERT_TRUE(exitDistance(capsule, pose, pose * Eigen::Vector3d(0, 0, 0.009),
                           pose.linear() * Eigen::Vector3d::UnitZ(), s));
  EXPECT_NEAR(s, 0.004, 1e-15);  // through the end cap: 1 mm to the cap's centre, then its radius
  EXPECT_FALSE(exitDistance(box, pose, pose * Eigen::Vector3d(0.006, 0, 0), Eigen::Vector3d::UnitX(), s));
}

// A sphere of radius R pressed d into a flat face, the tissue held at rest: a pressure k_A
// times the depth of the sphere below each point of the face pushes the tool up by k_A times
// the volume of the cap below the face, pi d^2 (3 R - d) / 3, which the samples on the surface
// triangles integrate, at two mesh resolutions and two sample spacings; the finer spacing is
// the closer.
TEST(Contact, PerAreaContactSumsThePressureOverTheContactPatch) {
  const double R = 0.008, d = 0.003, kA = 2e6;
  const double expected = kA * M_PI * d * d * (3 * R - d) / 3;
  for (int nodesAcross : {17, 33}) {
    double coarseError = HUGE_VAL;
    for (double spacing : {1e-3, 2.5e-4}) {
      ContactSettings c = settings();
      c.stiffnessPerArea = kA;
      c.sampleSpacing = spacing;
      Mesh mesh = boxGrid(nodesAcross, 3, nodesAcross, Eigen::Vector3d(0.04, 0.02, 0.04),
                          TetSplit::kFiveMirrored);
      System s(std::move(mesh), {Material::isotropic(3e3, 0.4, 1000)});
      TissueContact contact(s, c, {sphere(R)});
      const Eigen::Vector3d tip(0.0203, 0.02 + R - d, 0.0197);  // off the grid's symmetry lines
      contact.setTool(at(tip), {at(tip)}, 1.0, 0.0);
      const ContactResult& r = contact.update();
      ASSERT_TRUE(r.inContact);
      const std::string label = std::to_string(nodesAcross) + " nodes across, spacing " +
                                std::to_string(spacing) + " m: " + std::to_string(r.f0.y()) + " N";
      const double error = std::abs(r.f0.y() - expected);
      EXPECT_LT(error, (spacing > 5e-4 ? 0.02 : 0.005) * expected) << label;
      if (spacing < 5e-4) EXPECT_LT(error, coarseError) << label;
      coarseError = error;
      EXPECT_LT(std::hypot(r.f0.x(), r.f0.z()), 0.01 * r.f0.y()) << label;
      for (const ContactPoint& p : r.points) {  // the sphere's depth below the point
        const double rho = std::hypot(p.tissuePoint.x() - tip.x(), p.tissuePoint.z() - tip.z());
        EXPECT_NEAR(p.depth, std::sqrt(R * R - rho * rho) - (R - d), 1e-12);
        EXPECT_NEAR(p.normal.y(), 1.0, 1e-12);
      }
      // The force on the tissue is minus the force on the tool; K is the sum of k n n^T.
      Eigen::VectorXd f = Eigen::VectorXd::Zero(s.numDofs());
      contact.model().addForce(s.state.x, s.state.v, f);
      Eigen::Vector3d onTissue = Eigen::Vector3d::Zero();
      for (int a = 0; a < s.numNodes(); ++a) onTissue += f.segment<3>(3 * a);
      EXPECT_LT((onTissue + r.f0).norm(), 1e-9 * r.f0.norm());
      EXPECT_GT(r.K(1, 1), 0.0);
    }
  }
}

// Closed jaws (a 4 x 3.2 mm box end on) pressed 1 mm into the middle of a 2 cm surface triangle,
// no node under them: the contact per unit area still meets the surface, with k_A times the
// volume of the box below the face (the footprint sampled, so within 5 % at the automatic
// spacing and 1 % at a tenth of a millimetre), straight up. A second identical box at the same pose adds
// nothing: each sample counts once, for the deepest shape.
TEST(Contact, PerAreaContactMeetsAToolThinnerThanTheTriangles) {
  const double kA = 1e7, d = 0.001;
  ToolShape jaws;
  jaws.type = ToolShape::Type::kBox;
  jaws.size = Eigen::Vector3d(0.004, 0.01, 0.0032);
  jaws.link = "jaws";
  const double expected = kA * 0.004 * 0.0032 * d;
  System s = block();
  const Eigen::Vector3d centre = topIncentre(s, 0.02);
  const Eigen::Vector3d tip = centre + Eigen::Vector3d(0, 0.005 - d, 0);
  for (const double spacing : {0.0, 1e-4}) {
    ContactSettings c = settings();
    c.stiffnessPerArea = kA;
    c.sampleSpacing = spacing;
    for (const size_t copies : {1u, 2u}) {
      TissueContact contact(s, c, std::vector<ToolShape>(copies, jaws));
      contact.setTool(at(tip), std::vector<Eigen::Isometry3d>(copies, at(tip)), 1.0, 0.0);
      const ContactResult& r = contact.update();
      const std::string label = "spacing " + std::to_string(spacing) + " m, " +
                                std::to_string(copies) + " boxes: " + std::to_string(r.f0.y()) + " N";
      ASSERT_TRUE(r.inContact) << label;
      if (copies == 1)
        std::printf("[ measured ] closed jaws 1 mm into a 2 cm triangle, spacing %s: %.4f N (k_A x volume %.4f N)\n",
                    spacing == 0.0 ? "automatic" : "0.1 mm", r.f0.y(), expected);
      EXPECT_NEAR(r.f0.y(), expected, (spacing == 0.0 ? 0.05 : 0.01) * expected) << label;
      EXPECT_LT(std::hypot(r.f0.x(), r.f0.z()), 1e-9 * r.f0.y()) << label;
      for (const ContactPoint& p : r.points) EXPECT_NEAR(p.depth, d, 1e-12) << label;
    }
  }
}

TEST(Contact, CapsuleAcrossTheTopPushesStraightUp) {
  System s = block();
  ToolShape capsule;
  capsule.type = ToolShape::Type::kCapsule;
  capsule.radius = 0.004;
  capsule.length = 0.02;
  capsule.link = "shaft";
  TissueContact contact(s, settings(), {capsule});
  // Lying along x over the middle of the top face, 1.5 mm deep.
  Eigen::Isometry3d pose = at(Eigen::Vector3d(0.02, 0.02 + 0.004 - 0.0015, 0.013));
  pose.linear() = Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  contact.setTool(pose, {pose}, 1.0, 0.0);
  const ContactResult& r = contact.update();
  ASSERT_TRUE(r.inContact);
  ASSERT_GE(r.points.size(), 2u);
  double deepest = 0.0;
  for (const ContactPoint& p : r.points) {
    EXPECT_NEAR(p.normal.y(), 1.0, 1e-4);
    EXPECT_LE(p.depth, 0.0015 + 1e-5);
    deepest = std::max(deepest, p.depth);
  }
  EXPECT_NEAR(deepest, 0.0015, 1e-5);
  EXPECT_GT(r.f0.y(), 300.0 * 0.0015 - 1e-9);
  EXPECT_LT(std::hypot(r.f0.x(), r.f0.z()), 1e-6 * r.f0.y());
}

TEST(Contact, StiffnessMatchesAFiniteDifferenceOfTheToolForce) {
  System s = block();
  TissueContact contact(s, settings(), {sphere(0.005)});
  // Off the incentres: the sphere overlaps several top triangles.
  const Eigen::Vector3d tip(0.031, 0.02 + 0.005 - 0.0008, 0.021);
  auto forceAt = [&](const Eigen::Vector3d& p) {
    contact.setTool(at(p), {at(p)}, 1.0, 0.0);
    return contact.update();
  };
  const ContactResult r = forceAt(tip);
  ASSERT_TRUE(r.inContact);
  const double h = 1e-6;
  Eigen::Matrix3d fd;
  for (int j = 0; j < 3; ++j) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(j);
    fd.col(j) = -(forceAt(tip + e).f0 - forceAt(tip - e).f0) / (2 * h);
  }
  EXPECT_LT((fd - r.K).norm(), 2e-2 * r.K.norm()) << "K\n" << r.K << "\nfd\n" << fd;
  EXPECT_LT((r.K - r.K.transpose()).norm(), 1e-12);
  EXPECT_GE(Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(r.K).eigenvalues().minCoeff(), -1e-9);
}

TEST(Contact, NoContactGivesZeroForceAndStiffness) {
  System s = block();
  TissueContact contact(s, settings(), {sphere(0.005)});
  const Eigen::Vector3d tip(0.02, 0.02 + 0.0051, 0.02);
  contact.setTool(at(tip), {at(tip)}, 1.0, 0.0);
  const ContactResult& r = contact.update();
  EXPECT_FALSE(r.inContact);
  EXPECT_TRUE(r.points.empty());
  EXPECT_EQ(r.f0, Eigen::Vector3d::Zero());
  EXPECT_EQ(r.K, Eigen::Matrix3d::Zero());
  Eigen::VectorXd f = Eigen::VectorXd::Zero(s.numDofs());
  contact.model().addForce(s.state.x, s.state.v, f);
  EXPECT_EQ(f.cwiseAbs().maxCoeff(), 0.0);

  // Without a tool: no contact either.
  contact.clearTool();
  EXPECT_FALSE(contact.update().inContact);
}

// Far from the tissue the Bullet query is skipped (the boxes do not meet); a tissue that
// moved meanwhile is met where it is now, not where the last query saw it.
TEST(Contact, TissueThatMovedWhileTheToolWasFarIsMetWhereItIsNow) {
  System s = block();
  TissueContact contact(s, settings(), {sphere(0.005)});
  const Eigen::Vector3d centre = topIncentre(s, 0.02);
  const Eigen::Vector3d far = centre + Eigen::Vector3d(0, 0.1, 0);
  contact.setTool(at(far), {at(far)}, 1.0, 0.0);
  EXPECT_FALSE(contact.update().inContact);
  const double lift = 0.003;
  for (int a = 0; a < s.numNodes(); ++a) s.state.x[3 * a + 1] += lift;
  EXPECT_FALSE(contact.update().inContact);
  const double depth = 0.001;
  const Eigen::Vector3d tip = centre + Eigen::Vector3d(0, lift + 0.005 - depth, 0);
  contact.setTool(at(tip), {at(tip)}, 1.0, 0.1);
  const ContactResult& r = contact.update();
  ASSERT_TRUE(r.inContact);
  ASSERT_EQ(r.points.size(), 1u);
  EXPECT_NEAR(r.points[0].depth, depth, 1e-6);
  EXPECT_NEAR(r.f0.y(), 300.0 * depth, 1e-3 * 300.0 * depth);
}

TEST(Contact, ForceOnTissueIsMinusForceOnTool) {
  System s = block();
  ContactSettings c = settings();
  c.damping = 0.5;
  TissueContact contact(s, c, {sphere(0.006)});
  s.state.v.setRandom();
  s.state.v *= 0.01;
  contact.setTool(at(Eigen::Vector3d(0.012, 0.0245, 0.017)), {at(Eigen::Vector3d(0.012, 0.0245, 0.017))}, 1.0, 0.0);
  contact.update();
  contact.setTool(at(Eigen::Vector3d(0.012, 0.024, 0.017)), {at(Eigen::Vector3d(0.012, 0.024, 0.017))}, 1.0, 0.01);
  const ContactResult& r = contact.update();
  ASSERT_TRUE(r.inContact);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(s.numDofs());
  contact.model().addForce(s.state.x, s.state.v, f);
  Eigen::Vector3d onTissue = Eigen::Vector3d::Zero();
  for (int a = 0; a < s.numNodes(); ++a) onTissue += f.segment<3>(3 * a);
  EXPECT_LT((onTissue + r.f0).norm(), 1e-12 * (1.0 + r.f0.norm()));
  EXPECT_GT(r.f0.y(), 0.0);
}

TEST(Contact, TissueStiffnessIsTheDerivativeOfTheTissueForce) {
  System s = block();
  TissueContact contact(s, settings(), {sphere(0.006)});
  const Eigen::Vector3d tip(0.012, 0.024, 0.017);
  contact.setTool(at(tip), {at(tip)}, 1.0, 0.0);
  ASSERT_TRUE(contact.update().inContact);
  SparseMatrix K = s.pattern.zeroMatrix();
  contact.model().addStiffness(s.state.x, 1.0, s.pattern, K);
  const Eigen::MatrixXd dense = Eigen::MatrixXd(K);
  const double h = 1e-7;
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(s.numDofs());
  for (int dof = 0; dof < s.numDofs(); ++dof) {
    Eigen::VectorXd xp = s.state.x, xm = s.state.x, fp = v, fm = v;
    xp[dof] += h;
    xm[dof] -= h;
    contact.model().addForce(xp, v, fp);
    contact.model().addForce(xm, v, fm);
    EXPECT_LT(((fp - fm) / (2 * h) - dense.col(dof)).norm(), 1e-5) << "dof " << dof;
  }
}

TEST(Contact, GraspAttachesWhenTheJawClosesAndReleasesWhenItOpens) {
  System s = block();
  ContactSettings c = settings();
  c.graspRadius = 0.004;
  ToolShape jaw = sphere(0.002);
  jaw.jaw = true;
  TissueContact contact(s, c, {jaw});
  // A top corner node of the middle (free) x-z cell: node (2, 2, 1) is at (0.04, 0.02, 0.02).
  const Eigen::Vector3d node(0.02, 0.02, 0.02);
  const Eigen::Vector3d tip = node + Eigen::Vector3d(0, 0.0025, 0);
  contact.setTool(at(tip), {at(tip)}, 0.5, 0.0);  // open: nothing held, no penetration
  EXPECT_FALSE(contact.update().inContact);
  contact.setTool(at(tip), {at(tip)}, 0.0, 0.01);  // closed
  const ContactResult grasped = contact.update();
  ASSERT_TRUE(grasped.grasping);
  ASSERT_EQ(grasped.graspedNodes.size(), 1u);
  EXPECT_LT((s.mesh.rest.col(grasped.graspedNodes[0]) - node).norm(), 1e-12);
  EXPECT_LT(grasped.f0.norm(), 1e-12);  // anchors start where the nodes are

  // Pulling up 1 cm: the spring pulls the tool back down with k_g * 1 cm; K = k_g I.
  const Eigen::Vector3d pulled = tip + Eigen::Vector3d(0, 0.01, 0);
  contact.setTool(at(pulled), {at(pulled)}, 0.0, 0.02);
  const ContactResult pulling = contact.update();
  ASSERT_TRUE(pulling.grasping);
  EXPECT_LT((pulling.f0 - Eigen::Vector3d(0, -150.0 * 0.01, 0)).norm(), 1e-9);
  EXPECT_LT((pulling.K - 150.0 * Eigen::Matrix3d::Identity()).norm(), 1e-9);

  // Stepping the tissue: the grasped node follows the tip upward.
  s.models.insert(s.models.begin(),
                  std::make_unique<EdgeLengthModel>(s.mesh, s.materials));
  for (int a = 0; a < s.numNodes(); ++a)
    if (s.mesh.rest(1, a) < 1e-12) s.mesh.nodeTags[a] = kFixedAll;
  s.updateConstraints();
  BackwardEulerIntegrator integrator;
  for (int step = 0; step < 20; ++step) {
    contact.setTool(at(pulled), {at(pulled)}, 0.0, 0.02 + 0.01 * step);
    contact.update();
    ASSERT_TRUE(integrator.advance(s, 0.01).ok);
  }
  const int held = grasped.graspedNodes[0];
  EXPECT_GT(s.state.x[3 * held + 1], node.y() + 0.002);

  // Opening releases: no force, nothing held.
  contact.setTool(at(pulled), {at(pulled)}, 0.5, 1.0);
  const ContactResult released = contact.update();
  EXPECT_FALSE(released.grasping);
  EXPECT_FALSE(released.inContact);
  EXPECT_EQ(released.f0, Eigen::Vector3d::Zero());
}

TEST(Contact, NonFiniteToolPoseIsRejected) {
  System s = block();
  TissueContact contact(s, settings(), {sphere(0.005)});
  Eigen::Isometry3d bad = at(Eigen::Vector3d(0.02, 0.024, 0.02));
  bad.translation().x() = std::nan("");
  try {
    contact.setTool(bad, {at(Eigen::Vector3d::Zero())}, 0.0, 0.0);
    FAIL() << "accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tip pose is not finite"), std::string::npos);
  }
  EXPECT_THROW(contact.setTool(at(Eigen::Vector3d::Zero()), {bad}, 0.0, 0.0), std::invalid_argument);
  EXPECT_THROW(contact.setTool(at(Eigen::Vector3d::Zero()), {at(Eigen::Vector3d::Zero())},
                               std::numeric_limits<double>::infinity(), 0.0),
               std::invalid_argument);
  EXPECT_FALSE(contact.update().inContact);
}

TEST(Contact, PressingWithImplicitStepsStaysFiniteAndPushesTheSurfaceDown) {
  System s = block();
  s.models.push_back(std::make_unique<EdgeLengthModel>(s.mesh, s.materials));
  for (int a = 0; a < s.numNodes(); ++a)
    if (s.mesh.rest(1, a) < 1e-12) s.mesh.nodeTags[a] = kFixedAll;
  s.updateConstraints();
  s.damping = 2.0 * s.mass;
  TissueContact contact(s, settings(2000.0), {sphere(0.005)});
  BackwardEulerIntegrator integrator;
  const Eigen::Vector3d start(0.02, 0.0255, 0.02);
  double lastForce = 0.0;
  for (int step = 0; step < 100; ++step) {
    const Eigen::Vector3d tip = start - Eigen::Vector3d(0, 0.00005 * std::min(step, 60), 0);
    contact.setTool(at(tip), {at(tip)}, 1.0, 0.01 * step);
    const ContactResult& r = contact.update();
    ASSERT_TRUE(r.f0.allFinite() && r.K.allFinite());
    lastForce = r.f0.y();
    ASSERT_TRUE(integrator.advance(s, 0.01).ok) << "step " << step;
  }
  EXPECT_GT(lastForce, 0.0);
  EXPECT_LT(s.state.x.segment<3>(3 * (1 + 3 * (2 + 3 * 1))).y(), 0.02 - 0.001);
}

// The block of edge-length springs (Young's modulus E), its bottom fixed, with a sphere pressed
// 1 mm into the top; the tissue settled at each tool position (the contact re-queried until
// the penalties stop changing the state). Returns the contact at the settled state.
struct SettledPress {
  System system;
  TissueContact contact;
  SettledPress(double E, bool tissueInSeries)
      : system(boxGrid(3, 3, 3, Eigen::Vector3d(0.04, 0.02, 0.04), TetSplit::kFiveMirrored),
               {Material::transverselyIsotropic(E, 0.4, E, 0.4, 1000)}),
        contact(prepared(system), withSeries(tissueInSeries), {sphere(0.005)}) {}
  static System& prepared(System& s) {
    s.models.push_back(std::make_unique<EdgeLengthModel>(s.mesh, s.materials));
    for (int a = 0; a < s.numNodes(); ++a)
      if (s.mesh.rest(1, a) < 1e-12) s.mesh.nodeTags[a] = kFixedAll;
    s.updateConstraints();
    return s;
  }
  static ContactSettings withSeries(bool on) {
    ContactSettings c = settings(300.0);
    c.tissueInSeries = on;
    return c;
  }
  ContactResult at(const Eigen::Vector3d& tip) {
    for (int query = 0; query < 6; ++query) {
      contact.setTool(tt::at(tip), {tt::at(tip)}, 1.0, 0.0);
      contact.update();
      EXPECT_TRUE(solveEquilibrium(system).converged());
    }
    contact.setTool(tt::at(tip), {tt::at(tip)}, 1.0, 0.0);
    return contact.update();
  }
};

// With the tissue in series, the felt stiffness lies between what the hand feels pressing
// quasi-static tissue (a finite difference of the settled tool force) and the penalty alone;
// it rises with the tissue's stiffness, and without the option K is the penalty's.
TEST(Contact, FeltStiffnessInSeriesLiesBetweenTheSettledTissuesAndThePenaltys) {
  const double step = 2e-5;
  SettledPress soft(3e3, true);
  // One contact point: the sphere over a top triangle's incentre.
  const Eigen::Vector3d tip = topIncentre(soft.system, 0.02) + Eigen::Vector3d(0, 0.005 - 0.001, 0);
  const ContactResult pressed = soft.at(tip);
  const ContactResult deeper = soft.at(tip - Eigen::Vector3d(0, step, 0));
  ASSERT_TRUE(pressed.inContact && deeper.inContact);
  ASSERT_EQ(pressed.points.size(), 1u);
  const double settled = (deeper.f0.y() - pressed.f0.y()) / step;
  const double felt = pressed.K(1, 1);
  const double penalty = 300.0 * std::pow(pressed.points[0].normal.y(), 2);
  std::printf("[ measured ] settled tissue %.1f N/m, felt %.1f N/m, penalty %.1f N/m\n", settled,
              felt, penalty);
  EXPECT_GT(settled, 0.0);
  EXPECT_GT(felt, settled);
  EXPECT_LT(felt, 0.9 * penalty);
  EXPECT_LT((pressed.K - pressed.K.transpose()).norm(), 1e-12);

  SettledPress stiff(3e4, true);
  EXPECT_GT(stiff.at(tip).K(1, 1), felt * 1.5);
  SettledPress penaltyOnly(3e3, false);
  const ContactResult alone = penaltyOnly.at(tip);
  ASSERT_EQ(alone.points.size(), 1u);
  EXPECT_NEAR(alone.K(1, 1), 300.0 * std::pow(alone.points[0].normal.y(), 2), 1e-9);
}

}  // namespace
}  // namespace tt
