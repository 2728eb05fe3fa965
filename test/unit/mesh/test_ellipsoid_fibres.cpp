// The fibres of the truncated ellipsoid ventricle (mesh/fibre_field.h EllipsoidFibres): the
// transmural coordinate of points built from the paper's prolate-spheroidal parametrisation,
// the wall normal against that parametrisation's tangents, the circumferential direction at
// points worked out by hand, orthonormal right-handed frames, and the fibre angle measured
// against the meridian and the parallel through the point.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "tissue_trainer/core/mesh/fibre_field.h"

namespace tt {
namespace {

constexpr double kFibrePi = 3.14159265358979323846;

EllipsoidFibres landFibres() {
  EllipsoidFibres f;  // EllipsoidShape's defaults: Land et al. 2015, Sec. 2c(ii)
  f.angleEndo = 60.0 * kFibrePi / 180.0;
  f.angleEpi = -60.0 * kFibrePi / 180.0;
  return f;
}

// x = r_s sin u cos v, y = r_s sin u sin v, z = r_l cos u with r_s, r_l at t (written out
// here, not taken from the generator).
struct SpheroidParametrisation {
  double rs, rl;
  explicit SpheroidParametrisation(double t) : rs(0.007 + 0.003 * t), rl(0.017 + 0.003 * t) {}
  Eigen::Vector3d point(double u, double v) const {
    return {rs * std::sin(u) * std::cos(v), rs * std::sin(u) * std::sin(v), rl * std::cos(u)};
  }
  // d/du: along the meridian, towards the base as u grows from -pi.
  Eigen::Vector3d alongMeridian(double u, double v) const {
    return Eigen::Vector3d(rs * std::cos(u) * std::cos(v), rs * std::cos(u) * std::sin(v),
                           -rl * std::sin(u))
        .normalized();
  }
  // d/dv: along the parallel.
  Eigen::Vector3d alongParallel(double u, double v) const {
    return Eigen::Vector3d(-rs * std::sin(u) * std::sin(v), rs * std::sin(u) * std::cos(v), 0.0)
        .normalized();
  }
};

TEST(EllipsoidFibres, TransmuralCoordinateOfPointsOnTheSpheroids) {
  const EllipsoidFibres f = landFibres();
  for (double t : {0.0, 0.2, 0.5, 0.75, 1.0})
    for (double u : {-3.0, -2.2, -kFibrePi / 2, -1.3})
      for (double v : {0.0, 1.0, 2.5, 4.0}) {
        const Eigen::Vector3d p = SpheroidParametrisation(t).point(u, v);
        EXPECT_NEAR(f.transmuralAt(p), t, 1e-12) << "t " << t << " u " << u << " v " << v;
      }
  // Inside the cavity and outside the epicardium: held at the faces.
  EXPECT_EQ(f.transmuralAt(Eigen::Vector3d(0.001, 0.0, -0.005)), 0.0);
  EXPECT_EQ(f.transmuralAt(Eigen::Vector3d::Zero()), 0.0);
  EXPECT_EQ(f.transmuralAt(Eigen::Vector3d(0.012, 0.0, 0.0)), 1.0);
  EXPECT_EQ(f.transmuralAt(Eigen::Vector3d(0.0, 0.0, -0.021)), 1.0);
}

TEST(EllipsoidFibres, NormalIsOrthogonalToTheSpheroidAndPointsOut) {
  const EllipsoidFibres f = landFibres();
  for (double t : {0.0, 0.4, 1.0})
    for (double u : {-2.9, -2.0, -1.2})
      for (double v : {0.3, 2.0, 5.0}) {
        const SpheroidParametrisation s(t);
        const Eigen::Vector3d p = s.point(u, v);
        const Eigen::Vector3d n = f.normalAt(p, t);
        EXPECT_NEAR(n.norm(), 1.0, 1e-14);
        EXPECT_NEAR(n.dot(s.alongMeridian(u, v)), 0.0, 1e-14);
        EXPECT_NEAR(n.dot(s.alongParallel(u, v)), 0.0, 1e-14);
        EXPECT_GT(n.dot(p), 0.0);
      }
  // On the equator and at the apex by hand.
  EXPECT_TRUE(f.normalAt(Eigen::Vector3d(0.0, 0.0085, 0.0), 0.5).isApprox(Eigen::Vector3d::UnitY(), 1e-15));
  EXPECT_TRUE(f.normalAt(Eigen::Vector3d(0.0, 0.0, -0.0185), 0.5).isApprox(-Eigen::Vector3d::UnitZ(), 1e-15));
}

TEST(EllipsoidFibres, CircumferentialDirectionByHand) {
  const EllipsoidFibres f = landFibres();
  const auto circumferential = [&](const Eigen::Vector3d& p) {
    return f.circumferentialAt(p, f.normalAt(p, f.transmuralAt(p)));
  };
  EXPECT_TRUE(circumferential({0.008, 0.0, -0.003}).isApprox(Eigen::Vector3d(0, 1, 0), 1e-15));
  EXPECT_TRUE(circumferential({0.0, -0.008, 0.001}).isApprox(Eigen::Vector3d(1, 0, 0), 1e-15));
  EXPECT_TRUE(circumferential({-0.006, -0.006, -0.01})
                  .isApprox(Eigen::Vector3d(1, -1, 0) / std::sqrt(2.0), 1e-15));
  // On the long axis: any unit vector orthogonal to the normal (-z there).
  const Eigen::Vector3d apex(0.0, 0.0, -0.0185);
  const Eigen::Vector3d c = circumferential(apex);
  EXPECT_NEAR(c.norm(), 1.0, 1e-15);
  EXPECT_NEAR(c.z(), 0.0, 1e-15);
}

TEST(EllipsoidFibres, FramesAreOrthonormalAndRightHanded) {
  const EllipsoidFibres f = landFibres();
  std::mt19937 random(7);
  std::uniform_real_distribution<double> t(0.0, 1.0), u(-kFibrePi, -0.3), v(0.0, 2 * kFibrePi);
  for (int k = 0; k < 200; ++k) {
    const Eigen::Matrix3d B = f.frameAt(SpheroidParametrisation(t(random)).point(u(random), v(random)));
    EXPECT_TRUE((B.transpose() * B).isIdentity(1e-12)) << B;
    EXPECT_NEAR(B.determinant(), 1.0, 1e-12);
  }
  const Eigen::Matrix3d apex = f.frameAt(Eigen::Vector3d(0.0, 0.0, -0.0185));
  EXPECT_TRUE((apex.transpose() * apex).isIdentity(1e-12)) << apex;
}

// On the equator at +x: c = +y, l = +z, n = +x. The angle turns from +60 degrees at the
// endocardium through 0 mid-wall to -60 at the epicardium.
TEST(EllipsoidFibres, FibreOnTheEquatorByHand) {
  const EllipsoidFibres f = landFibres();
  const double s = std::sqrt(3.0) / 2.0;
  const Eigen::Matrix3d endo = f.frameAt({0.007, 0.0, 0.0});
  EXPECT_TRUE(endo.col(0).isApprox(Eigen::Vector3d(0.0, 0.5, s), 1e-12)) << endo;
  EXPECT_TRUE(endo.col(1).isApprox(Eigen::Vector3d::UnitX(), 1e-15));
  const Eigen::Matrix3d mid = f.frameAt({0.0085, 0.0, 0.0});
  EXPECT_TRUE(mid.col(0).isApprox(Eigen::Vector3d::UnitY(), 1e-12)) << mid;
  EXPECT_TRUE(mid.col(2).isApprox(-Eigen::Vector3d::UnitZ(), 1e-12)) << mid;
  const Eigen::Matrix3d epi = f.frameAt({0.010, 0.0, 0.0});
  EXPECT_TRUE(epi.col(0).isApprox(Eigen::Vector3d(0.0, 0.5, -s), 1e-12)) << epi;
}

// Elsewhere: the angle of the fibre from the parallel towards the meridian (both from the
// parametrisation) is linear in t; the sheet is the wall normal.
TEST(EllipsoidFibres, FibreAngleIsLinearThroughTheWall) {
  EllipsoidFibres f = landFibres();
  f.angleEndo = 80.0 * kFibrePi / 180.0;
  f.angleEpi = -40.0 * kFibrePi / 180.0;
  for (double t : {0.0, 0.3, 0.6, 1.0})
    for (double u : {-2.8, -2.1, -1.4})
      for (double v : {0.5, 3.0}) {
        const SpheroidParametrisation s(t);
        const Eigen::Matrix3d B = f.frameAt(s.point(u, v));
        const double angle =
            std::atan2(B.col(0).dot(s.alongMeridian(u, v)), B.col(0).dot(s.alongParallel(u, v)));
        EXPECT_NEAR(angle * 180.0 / kFibrePi, 80.0 - 120.0 * t, 1e-9) << "t " << t << " u " << u;
        EXPECT_NEAR(std::abs(B.col(1).dot(s.alongMeridian(u, v).cross(s.alongParallel(u, v)))), 1.0, 1e-12);
      }
}

}  // namespace
}  // namespace tt
