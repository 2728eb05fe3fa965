// The element types on their own: rest volume, shape-function gradients at the quadrature
// points (the element-level patch test: the gradient of a linear field is exact at every
// point), the deformation gradient of an affine motion, outward faces and positive tet splits.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "tissue_trainer/core/element/hex8.h"
#include "tissue_trainer/core/element/tet4.h"
#include "tissue_trainer/core/mesh/quality.h"

namespace tt {
namespace {

Eigen::Matrix3Xd unitCube() {
  Eigen::Matrix3Xd X(3, 8);
  for (int p = 0; p < 8; ++p)
    for (int i = 0; i < 3; ++i) X(i, p) = 0.5 * (Hex8::corner[p][i] + 1);
  return X;
}

const Hex kHex{0, 1, 2, 3, 4, 5, 6, 7};

Eigen::Matrix3d randomAffine(std::mt19937& rng, double size) {
  std::uniform_real_distribution<double> u(-size, size);
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) A(i, j) += u(rng);
  return A;
}

TEST(Hex8, UnitCubeRestData) {
  const Hex8::Rest r = Hex8::rest(unitCube(), kHex);
  EXPECT_NEAR(r.volume, 1.0, 1e-14);
  for (int q = 0; q < Hex8::kPoints; ++q) {
    EXPECT_NEAR(r.weight[q], 0.125, 1e-14);
    EXPECT_LT(r.grad[q].rowwise().sum().norm(), 1e-14) << "partition of unity at point " << q;
  }
  EXPECT_NEAR(hexVolume(unitCube(), kHex), 1.0, 1e-14);
}

TEST(Hex8, ShapeFunctionsInterpolateNodes) {
  for (int p = 0; p < 8; ++p) {
    const Eigen::Vector3d xi(Hex8::corner[p][0], Hex8::corner[p][1], Hex8::corner[p][2]);
    const Eigen::Matrix<double, 8, 1> N = Hex8::shape(xi);
    for (int a = 0; a < 8; ++a) EXPECT_DOUBLE_EQ(N[a], a == p ? 1.0 : 0.0);
  }
  // Reference gradients against central differences of the shape functions.
  const Eigen::Vector3d xi(0.3, -0.2, 0.7);
  const Hex8::Gradients dN = Hex8::referenceGradients(xi);
  const double h = 1e-6;
  for (int k = 0; k < 3; ++k) {
    const Eigen::Vector3d e = h * Eigen::Vector3d::Unit(k);
    const Eigen::Matrix<double, 8, 1> fd = (Hex8::shape(xi + e) - Hex8::shape(xi - e)) / (2 * h);
    EXPECT_LT((fd.transpose() - dN.row(k)).norm(), 1e-9);
  }
}

// An affine image A X + b of the cube (sheared, stretched, rotated): volume det A, and at
// every Gauss point the gradients reproduce a linear field exactly and F of a second affine
// motion x = B X + c is B.
TEST(Hex8, AffineHexPatchTestAtEveryGaussPoint) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 10; ++trial) {
    const Eigen::Matrix3d A = 0.02 * randomAffine(rng, 0.4);
    if (A.determinant() <= 0) continue;
    const Eigen::Vector3d b(0.3, -0.1, 0.2);
    const Eigen::Matrix3Xd X = (A * unitCube()).colwise() + b;
    const Hex8::Rest r = Hex8::rest(X, kHex);
    EXPECT_NEAR(r.volume, A.determinant(), 1e-12 * A.determinant());
    EXPECT_NEAR(hexVolume(X, kHex), A.determinant(), 1e-12 * A.determinant());
    double split = 0.0;
    for (int k = 0; k < 6; ++k) split += tetVolume(X, Hex8::sixTet(kHex, k));
    EXPECT_NEAR(split, A.determinant(), 1e-12 * A.determinant());

    const Eigen::Matrix3d B = randomAffine(rng, 0.3);
    const Eigen::Vector3d c(1.0, 2.0, 3.0);
    const Eigen::Matrix3Xd x = (B * X).colwise() + c;
    const Eigen::VectorXd xv = Eigen::Map<const Eigen::VectorXd>(x.data(), 24);
    const NodeMatrix<8> xe = gatherNodes<8>(xv, kHex);
    for (int q = 0; q < Hex8::kPoints; ++q) {
      EXPECT_GT(r.weight[q], 0.0);
      EXPECT_LT((deformationGradient<8>(xe, r.grad[q]) - B).norm(), 1e-10 * B.norm())
          << "Gauss point " << q;
    }
  }
}

// A trilinear (non-affine) hex: the rest volume from the Gauss rule matches a fine midpoint
// integration of det J, and F of a rigid motion is a rotation at every point.
TEST(Hex8, DistortedHexVolumeAndRigidMotion) {
  Eigen::Matrix3Xd X = unitCube();
  X.col(6) += Eigen::Vector3d(0.2, 0.1, 0.3);  // non-planar faces
  X.col(1) += Eigen::Vector3d(0.1, -0.1, 0.0);
  const NodeMatrix<8> Xe = gatherNodes<8>(X, kHex);
  double reference = 0.0;
  const int n = 40;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      for (int k = 0; k < n; ++k) {
        const Eigen::Vector3d xi(-1 + (2 * i + 1.0) / n, -1 + (2 * j + 1.0) / n,
                                 -1 + (2 * k + 1.0) / n);
        const Eigen::Matrix3d J = Xe * Hex8::referenceGradients(xi).transpose();
        reference += J.determinant() * 8.0 / (n * n * n);
      }
  const Hex8::Rest r = Hex8::rest(X, kHex);
  EXPECT_NEAR(r.volume, reference, 1e-4 * reference);

  const Eigen::Matrix3d R =
      Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  const NodeMatrix<8> xe = R * Xe;
  for (int q = 0; q < Hex8::kPoints; ++q)
    EXPECT_LT((deformationGradient<8>(xe, r.grad[q]) - R).norm(), 1e-12);
}

TEST(Hex8, FacesOutwardAndTetSplitsPositive) {
  const Eigen::Matrix3Xd X = unitCube();
  const Eigen::Vector3d centre(0.5, 0.5, 0.5);
  double area = 0.0;
  for (const auto& f : Hex8::faces) {
    const Eigen::Vector3d a = X.col(f[0]), b = X.col(f[1]), c = X.col(f[2]), d = X.col(f[3]);
    const Eigen::Vector3d n = (b - a).cross(c - a) + (c - a).cross(d - a);  // twice the area
    EXPECT_GT(n.dot((a + b + c + d) / 4 - centre), 0.0);
    area += 0.5 * n.norm();
  }
  EXPECT_NEAR(area, 6.0, 1e-14);
  double six = 0.0, five = 0.0;
  for (const auto& t : Hex8::sixTets) {
    const double v = tetVolume(X, {t[0], t[1], t[2], t[3]});
    EXPECT_NEAR(v, 1.0 / 6.0, 1e-14);
    six += v;
  }
  for (const auto& t : Hex8::fiveTets) {
    const double v = tetVolume(X, {t[0], t[1], t[2], t[3]});
    EXPECT_GT(v, 0.0);
    five += v;
  }
  EXPECT_NEAR(six, 1.0, 1e-14);
  EXPECT_NEAR(five, 1.0, 1e-14);
}

TEST(Tet4, RestDataAndAffinePatch) {
  std::mt19937 rng(3);
  Eigen::Matrix3Xd X(3, 4);
  X << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  const Eigen::Matrix3d A = randomAffine(rng, 0.3);
  ASSERT_GT(A.determinant(), 0.0);
  X = A * X;
  const Tet t{0, 1, 2, 3};
  const Tet4::Rest r = Tet4::rest(X, t);
  EXPECT_NEAR(r.volume, A.determinant() / 6, 1e-14);
  EXPECT_DOUBLE_EQ(r.weight[0], r.volume);
  const Eigen::Matrix3d B = randomAffine(rng, 0.3);
  const NodeMatrix<4> xe = B * gatherNodes<4>(X, t);
  EXPECT_LT((deformationGradient<4>(xe, r.grad[0]) - B).norm(), 1e-12);
  for (const auto& f : Tet4::faces) {  // outward: the opposite node is behind the face
    int opposite = 6 - f[0] - f[1] - f[2];
    const Eigen::Vector3d n = (X.col(f[1]) - X.col(f[0])).cross(X.col(f[2]) - X.col(f[0]));
    EXPECT_LT(n.dot(X.col(opposite) - X.col(f[0])), 0.0);
  }
}

}  // namespace
}  // namespace tt
