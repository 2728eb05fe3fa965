// The finite-volume forces of M. Bao, "Derivation of Quasistatics and Landmark Optimization for
// Muscles", Sec. 4.4 (tet4_finite_volume.h: b_i from the area-weighted normals of the rest faces
// touching node i, g_i = P b_i) against the element form f = -V P Dm^-T (nodes 1-3; node 0 the
// negative sum) and against Tet4's shape-function gradients, on random tets of either
// orientation, slivers among them, with the muscle law's stress at a random deformation.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <cmath>
#include <cstdio>
#include <random>

#include "tissue_trainer/core/element/tet4.h"
#include "tissue_trainer/core/element/tet4_finite_volume.h"
#include "tissue_trainer/core/material/teran_muscle.h"

namespace tt {
namespace {

using FiniteVolume = Tet4FiniteVolume;
using Nodes = FiniteVolume::Nodes;

constexpr double kTolerance = 1e-12;  // relative, max norm

double relative(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / b.lpNorm<Eigen::Infinity>();
}

// A jittered corner tet scaled by 1e-3 to 1 m; odd trials swap nodes 1 and 2 (negative
// orientation), every fourth brings node 3 within 1e-3 of its size of the opposite face.
Nodes randomTet(std::mt19937& rng, int trial) {
  std::uniform_real_distribution<double> jitter(-0.25, 0.25), unit(0.0, 1.0);
  Nodes X;
  X << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  for (int i = 0; i < 12; ++i) X.data()[i] += jitter(rng);
  if (trial % 4 == 3) {
    const Eigen::Vector3d n = (X.col(1) - X.col(0)).cross(X.col(2) - X.col(0)).normalized();
    X.col(3) -= (n.dot(X.col(3) - X.col(0)) - 1e-3) * n;
  }
  if (trial % 2) X.col(1).swap(X.col(2));
  return std::pow(10.0, -3.0 + 3.0 * unit(rng)) * X;
}

Eigen::Matrix3d restEdges(const Nodes& X) { return X.rightCols<3>().colwise() - X.col(0); }

// The muscle law's P at F = I + 0.2 (random), with J > 0.
Eigen::Matrix3d randomStress(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(-0.2, 0.2);
  Eigen::Matrix3d F;
  do {
    F.setIdentity();
    for (int i = 0; i < 9; ++i) F.data()[i] += u(rng);
  } while (!(F.determinant() > 0.0));
  TeranMuscleLaw::Parameters p;
  p.k.activation = 0.5;
  const double y = u(rng), x = u(rng);  // g++'s order (random_draws.h)
  p.a0 = Eigen::Vector3d(x, y, 1.0).normalized();
  return TeranMuscleLaw::stress(p, F);
}

constexpr int kTets = 400;

TEST(Tet4FiniteVolume, NodeVectorsAreMinusVolumeTimesDmInverseTransposed) {
  std::mt19937 rng(3001);
  double worstBm = 0.0, worstIdentity = 0.0, worstOpposite = 0.0, worstRegular = 0.0;
  for (int trial = 0; trial < kTets; ++trial) {
    const Nodes X = randomTet(rng, trial);
    const Eigen::Matrix3d Dm = restEdges(X);
    const double V = std::abs(Dm.determinant()) / 6.0;
    const Nodes b = FiniteVolume::nodeVectors(X);
    // [b_1 b_2 b_3] from the faces = -V Dm^-T, and Dm^T B_m = -V I.
    const double eBm = relative(b.rightCols<3>(), Eigen::Matrix3d(-V * Dm.inverse().transpose()));
    const double eClosedForm = relative(FiniteVolume::Bm(X), Eigen::Matrix3d(b.rightCols<3>()));
    const double eIdentity =
        relative(Dm.transpose() * b.rightCols<3>(), Eigen::Matrix3d(-V * Eigen::Matrix3d::Identity()));
    // b_i is also 1/3 of the outward A N of the face opposite node i (the normals sum to zero).
    const double eOpposite = relative(b, Nodes(FiniteVolume::areaWeightedNormals(X) / 3.0));
    worstBm = std::max({worstBm, eBm, eClosedForm});
    worstIdentity = std::max(worstIdentity, eIdentity);
    worstOpposite = std::max(worstOpposite, eOpposite);
    if (trial % 4 != 3) worstRegular = std::max({worstRegular, eBm, eClosedForm, eIdentity});
    EXPECT_LT(eBm, kTolerance) << "trial " << trial;
    EXPECT_LT(eClosedForm, kTolerance) << "trial " << trial;
    EXPECT_LT(eIdentity, kTolerance) << "trial " << trial;
    EXPECT_LT(eOpposite, kTolerance) << "trial " << trial;
  }
  std::printf("Sec. 4.4 over %d tets: B_m from the faces vs -V Dm^-T %.2g; Dm^T B_m vs -V I "
              "%.2g (both %.2g without the slivers); b_i vs A_i N_i / 3 %.2g\n", kTets, worstBm,
              worstIdentity, worstRegular, worstOpposite);
}

TEST(Tet4FiniteVolume, ForcesAreTheElementForces) {
  std::mt19937 rng(3002);
  double worst = 0.0, worstTet4 = 0.0, worstSum = 0.0;
  int positive = 0;
  for (int trial = 0; trial < kTets; ++trial) {
    const Nodes X = randomTet(rng, trial);
    const Eigen::Matrix3d P = randomStress(rng);
    const Eigen::Matrix3d Dm = restEdges(X);
    const double V = std::abs(Dm.determinant()) / 6.0;
    // The element form: nodes 1-3 the columns of -V P Dm^-T, node 0 their negative sum.
    Nodes element;
    element.rightCols<3>() = -V * P * Dm.inverse().transpose();
    element.col(0) = -element.rightCols<3>().rowwise().sum();
    const Nodes g = FiniteVolume::forces(P, X);
    const double e = relative(g, element);
    // g_0 = P b_0 from its own faces is -(g_1 + g_2 + g_3), as the paper states.
    const double eSum = relative(g.col(0), Eigen::Vector3d(-g.rightCols<3>().rowwise().sum()));
    worst = std::max(worst, e);
    worstSum = std::max(worstSum, eSum);
    EXPECT_LT(e, kTolerance) << "trial " << trial;
    EXPECT_LT(eSum, kTolerance) << "trial " << trial;
    // Tet4's element force -V0 P grad_p (positively oriented tets: its V0 is signed).
    if (Dm.determinant() > 0.0) {
      ++positive;
      const Tet4::Rest rest = Tet4::rest(Eigen::Matrix3Xd(X), {0, 1, 2, 3});
      const Nodes tet4 = -rest.weight[0] * P * rest.grad[0];
      const double eTet4 = relative(g, tet4);
      worstTet4 = std::max(worstTet4, eTet4);
      EXPECT_LT(eTet4, kTolerance) << "trial " << trial;
    }
  }
  EXPECT_EQ(positive, kTets / 2);
  std::printf("Sec. 4.4 forces over %d tets (half negatively oriented, a quarter slivers): vs "
              "-V P Dm^-T %.2g; g_0 vs -(g_1 + g_2 + g_3) %.2g; vs Tet4 (%d positive) %.2g\n",
              kTets, worst, worstSum, positive, worstTet4);
}

}  // namespace
}  // namespace tt
