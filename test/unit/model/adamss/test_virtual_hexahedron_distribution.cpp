// The two distributions of the virtual hexahedron's point forces for the volume term
// p (det F - r)^2 ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.4.2.3): along the
// axes (Eq. 2.29 with the points' weights) and in equal shares to the nodes of each point's
// face. The equal shares, written out here from the point forces of Eq. 2.56; no energy but a
// stiffness that is the force's derivative; zero net force; the moment; rigid motion; the two
// distributions on a compressed element.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cstdio>
#include <random>

#include "../../model_test_util.h"
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"

namespace tt {
namespace adamss {
namespace {

using namespace testutil;
using Source = DeformationGradientSource;
using Distribution = PointForceDistribution;
using VolumeVH = VirtualHexahedronModel<VolumeLaw>;

const LawOptions kPlainOptions{};
const std::vector<VolumeLaw::Constants> kVolume = {{5000.0, 1.0}, {5000.0, 1.0}};

VolumeVH model(const Mesh& mesh, Distribution distribution) {
  return VolumeVH(mesh, kVolume, kPlainOptions, Source::kShapeFunctions, distribution);
}

// x = A X + a random motion of `amplitude` (m) per coordinate.
Eigen::VectorXd distributionDeformed(const Mesh& m, const Eigen::Matrix3d& A, double amplitude,
                         std::mt19937& rng) {
  Eigen::VectorXd x = perturbed(m, amplitude, rng);
  for (int n = 0; n < m.numNodes(); ++n)
    x.segment<3>(3 * n) += (A - Eigen::Matrix3d::Identity()) * m.rest.col(n);
  return x;
}

Eigen::Matrix3d compressionAndShear() {
  Eigen::Matrix3d A;
  A << 0.9, 0.05, -0.03, 0.02, 0.93, 0.04, -0.04, 0.03, 0.88;
  return A;
}

Eigen::Vector3d distributionNetForce(const Eigen::VectorXd& f) {
  return Eigen::Map<const Eigen::Matrix3Xd>(f.data(), 3, f.size() / 3).rowwise().sum();
}

Eigen::Vector3d moment(const Eigen::VectorXd& x, const Eigen::VectorXd& f) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (Eigen::Index i = 0; i < x.size() / 3; ++i)
    m += x.segment<3>(3 * i).cross(f.segment<3>(3 * i));
  return m;
}

// Typical size of the moments the forces could make: sum |x_p - centre| |f_p|.
double momentScale(const Eigen::VectorXd& x, const Eigen::VectorXd& f) {
  const Eigen::Map<const Eigen::Matrix3Xd> X(x.data(), 3, x.size() / 3);
  const Eigen::Vector3d centre = X.rowwise().mean();
  double s = 0.0;
  for (Eigen::Index i = 0; i < X.cols(); ++i) s += (X.col(i) - centre).norm() * f.segment<3>(3 * i).norm();
  return s;
}

// A 2 x 2 x 2 hex grid, nodes jittered, one oblique frame in every hex.
Mesh obliqueHexes(std::mt19937& rng) {
  Mesh m = boxGrid(3, 3, 3, Eigen::Vector3d(0.01, 0.012, 0.009), TetSplit::kNone);
  std::uniform_real_distribution<double> u(-0.1, 0.1);
  for (int n = 0; n < m.numNodes(); ++n)
    for (int i = 0; i < 3; ++i) m.rest(i, n) += 0.004 * u(rng);
  const Eigen::Matrix3d frame = randomRotation(rng);
  for (auto& B : m.hexFibreFrame) B = frame;
  return m;
}

// One tet: its intersection points' rest weights C (which node is off each point's face: the
// one of weight zero), the point forces of Eq. 2.56, f_2l = R_v A_l P n_l and f_2l+1 = -f_2l,
// with the box of edges zeta_l^0, and the restoring force of each point's equal shares,
// -(1/3) f_j on each node of its face.
TEST(VirtualHexahedronDistribution, VerticesGivesEachPointForceInThirdsToItsFaceNodes) {
  std::mt19937 rng(21);
  for (int trial = 0; trial < 5; ++trial) {
    const Mesh tet = randomTet(rng);
    const VolumeVH vertices = model(tet, Distribution::kVertices);
    const Eigen::VectorXd x = distributionDeformed(tet, compressionAndShear(), 3e-4, rng);

    const AxisRest<Tet4> axes = buildAxes(tet).tetRest[0];
    const NodeMatrix<4> X = gatherNodes<4>(tet.rest, tet.tets[0]);
    const NodeMatrix<4> xe = gatherNodes<4>(x, tet.tets[0]);
    const Eigen::Matrix3d dx = xe.rightCols<3>().colwise() - xe.col(0);
    const Eigen::Matrix3d dX = X.rightCols<3>().colwise() - X.col(0);
    const Eigen::Matrix3d F = dx * dX.inverse();
    const Eigen::Matrix3d P = VolumeLaw::stress(kVolume[0], F);
    Eigen::Matrix3d zeta0;  // zeta_l^0 = q_2l - q_2l+1 at rest (Eq. 2.5)
    for (int l = 0; l < 3; ++l) zeta0.col(l) = X * (axes.C.col(2 * l) - axes.C.col(2 * l + 1));
    const double V0 = tetVolume(tet.rest, tet.tets[0]);
    const double Rv = V0 / std::abs(zeta0.determinant());
    NodeMatrix<4> expected = NodeMatrix<4>::Zero();
    for (int l = 0; l < 3; ++l) {
      Eigen::Vector3d An = zeta0.col((l + 1) % 3).cross(zeta0.col((l + 2) % 3));
      if (An.dot(zeta0.col(l)) < 0) An = -An;
      const Eigen::Vector3d f2l = Rv * P * An;
      for (int j : {2 * l, 2 * l + 1}) {
        int off = 0;
        axes.C.col(j).cwiseAbs().minCoeff(&off);
        for (int p = 0; p < 4; ++p)
          if (p != off) expected.col(p) -= (j == 2 * l ? 1.0 : -1.0) * f2l / 3.0;
      }
    }
    Eigen::VectorXd want = Eigen::VectorXd::Zero(x.size());
    for (int p = 0; p < 4; ++p) want.segment<3>(3 * tet.tets[0][p]) = expected.col(p);
    EXPECT_LT(relDiff(force(vertices, x), want), 1e-12) << "trial " << trial;
  }
}

// No energy: the force is not the gradient of V0 p (J - r)^2 (that of `axes` on tets, the
// finite element), so the model reports none. The stiffness is still the force's derivative.
TEST(VirtualHexahedronDistribution, VerticesHasNoEnergyButItsStiffnessIsTheDerivative) {
  std::mt19937 rng(22);
  const Mesh mesh = boxMesh(2, 1, 1, 0.01, rng, 0.15);
  const VolumeVH axes = model(mesh, Distribution::kAxes);
  const VolumeVH vertices = model(mesh, Distribution::kVertices);
  EXPECT_TRUE(axes.hasEnergy());
  EXPECT_FALSE(vertices.hasEnergy());
  EXPECT_EQ(vertices.nonConservativeTets(), static_cast<int>(mesh.tets.size()));
  const Eigen::VectorXd x = distributionDeformed(mesh, compressionAndShear(), 2e-4, rng);
  EXPECT_EQ(vertices.energy(x), 0.0);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  EXPECT_EQ(vertices.addForce(x, x, f), 0.0);
  EXPECT_LT(relDiff(force(axes, x), Eigen::VectorXd(-fdGradient(axes, x, 1e-8))), 1e-6);
  EXPECT_GT(relDiff(force(vertices, x), Eigen::VectorXd(-fdGradient(axes, x, 1e-8))), 1e-2);

  const Eigen::MatrixXd K = denseStiffness(vertices, mesh, x);
  EXPECT_LT(relDiff(K, fdForceJacobian(vertices, x, 1e-8)), 1e-6);
  EXPECT_GT(relDiff(Eigen::MatrixXd(K.transpose()), K), 1e-3);  // not symmetric: no energy
  const Eigen::VectorXd d = perturbed(mesh, 1.0, rng) - restVector(mesh);
  Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
  vertices.addStiffnessTimes(x, d, 1.0, Kd);
  EXPECT_LT(relDiff(Kd, Eigen::VectorXd(K * d)), 1e-12);

  // Hexes with oblique axes: the same.
  const Mesh hexes = obliqueHexes(rng);
  const VolumeVH onHexes = model(hexes, Distribution::kVertices);
  EXPECT_FALSE(onHexes.hasEnergy());
  const Eigen::VectorXd y = distributionDeformed(hexes, compressionAndShear(), 2e-4, rng);
  EXPECT_LT(relDiff(denseStiffness(onHexes, hexes, y), fdForceJacobian(onHexes, y, 1e-8)), 1e-6);
}

// No net force, no force at rest, objective. The moment under an affine deformation: zero along
// the axes (Eq. 2.56 is a stress, and the current axes are F zeta^0), not zero with equal
// shares, whose point forces act at the faces' centroids. `amplitude`: the non-affine part.
void expectNetForceMomentAndRigidMotion(const Mesh& mesh, Distribution distribution,
                                        double amplitude, std::mt19937& rng) {
  const bool equal = distribution == Distribution::kVertices;
  SCOPED_TRACE(equal ? "vertices" : "axes");
  const VolumeVH vh = model(mesh, distribution);
  const Eigen::VectorXd x = distributionDeformed(mesh, compressionAndShear(), amplitude, rng);
  const Eigen::VectorXd f = force(vh, x);
  EXPECT_LT(force(vh, restVector(mesh)).lpNorm<Eigen::Infinity>(), 1e-12 * f.norm());
  EXPECT_LT(distributionNetForce(f).norm(), 1e-12 * f.norm());
  const double relativeMoment = moment(x, f).norm() / momentScale(x, f);
  std::printf("[ measured ] %s, %s: |moment| / sum |x_p - c| |f_p| = %.3g\n",
              mesh.hexes.empty() ? "tets" : "hexes", equal ? "vertices" : "axes",
              relativeMoment);
  if (equal) {
    EXPECT_GT(relativeMoment, 1e-3);
  } else {
    EXPECT_LT(relativeMoment, 1e-12);
  }
  const Eigen::Matrix3d R = randomRotation(rng);
  EXPECT_LT(relDiff(force(vh, rigidMotion(x, R, Eigen::Vector3d(0.2, 0.1, -0.3))),
                    rotateVectors(f, R)),
            1e-10);
}

TEST(VirtualHexahedronDistribution, NetForceMomentAndRigidMotion) {
  std::mt19937 rng(23);
  const Mesh tets = boxMesh(2, 2, 1, 0.01, rng, 0.15);  // random axes per tet
  const Mesh hexes = obliqueHexes(rng);
  for (Distribution distribution : {Distribution::kAxes, Distribution::kVertices}) {
    expectNetForceMomentAndRigidMotion(tets, distribution, 3e-4, rng);  // affine per tet anyway
    expectNetForceMomentAndRigidMotion(hexes, distribution, 0.0, rng);
  }
}

// A rectangular hex with the axes along its edges: every point is its face's centre, so the
// equal shares are the points' own weights and both distributions are the finite element's
// gradient, with energy.
TEST(VirtualHexahedronDistribution, BothAgreeWherePointsAreFaceCentres) {
  Mesh hex = boxGrid(2, 2, 2, Eigen::Vector3d(0.01, 0.012, 0.009), TetSplit::kNone);
  const VolumeVH axes = model(hex, Distribution::kAxes);
  const VolumeVH vertices = model(hex, Distribution::kVertices);
  EXPECT_TRUE(vertices.hasEnergy());
  std::mt19937 rng(24);
  const Eigen::VectorXd x = distributionDeformed(hex, compressionAndShear(), 2e-4, rng);
  EXPECT_LT(relDiff(force(vertices, x), force(axes, x)), 1e-14);
  EXPECT_LT(relDiff(force(vertices, x), Eigen::VectorXd(-fdGradient(vertices, x, 1e-8))), 1e-6);
}

// A tet compressed to 0.9^3 of its volume: both push its nodes outward, doing positive work
// on the volume (f . dV/dx > 0), and small steps x += s f along the force (a damped flow)
// restore the volume with either.
TEST(VirtualHexahedronDistribution, BothRestoreTheVolumeOfACompressedTet) {
  std::mt19937 rng(25);
  for (int trial = 0; trial < 5; ++trial) {
    const Mesh tet = randomTet(rng);
    const double V0 = tetVolume(tet.rest, tet.tets[0]);
    for (Distribution distribution : {Distribution::kAxes, Distribution::kVertices}) {
      SCOPED_TRACE(distribution == Distribution::kVertices ? "vertices" : "axes");
      const VolumeVH vh = model(tet, distribution);
      Eigen::VectorXd x = distributionDeformed(tet, 0.9 * Eigen::Matrix3d::Identity(), 0.0, rng);
      auto volume = [&](const Eigen::VectorXd& y) {
        return tetVolume(Eigen::Map<const Eigen::Matrix3Xd>(y.data(), 3, 4), tet.tets[0]);
      };
      const Eigen::VectorXd f = force(vh, x);
      Eigen::VectorXd dV(12);
      const double h = 1e-9;
      for (int k = 0; k < 12; ++k) {
        Eigen::VectorXd y = x;
        y[k] += h;
        dV[k] = (volume(y) - volume(x)) / h;
      }
      EXPECT_GT(f.dot(dV), 0.0) << "trial " << trial;
      // Small steps along the force (a damped flow) until the volume settles.
      const double step = 1e-3 * std::pow(V0, 2.0 / 3.0) / (kVolume[0].stiffness * V0);
      for (int k = 0; k < 20000; ++k) x += step * force(vh, x);
      EXPECT_NEAR(volume(x) / V0, 1.0, 1e-6) << "trial " << trial;
    }
  }
}

}  // namespace
}  // namespace adamss
}  // namespace tt
