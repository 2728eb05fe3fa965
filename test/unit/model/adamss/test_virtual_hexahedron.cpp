// The virtual hexahedron of the Adamss mass-spring system (model/adamss/virtual_hexahedron.h):
// on tets it is the finite element of the same law exactly; its nodal forces are the point
// forces of Eq. 2.56 (hexes) and of Eq. 2.74 corrected (tets), written out here from the
// intersection points and distributed by Eq. 2.29; force against energy and stiffness against
// force by finite differences where the method has an energy; invariance under rigid motion;
// no force for hourglass modes; the axis approximation of Eqs. 2.59-2.62, exact and
// approximate cases.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>
#include <stdexcept>

#include "../../model_test_util.h"
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/hunter_polynomial.h"
#include "tissue_trainer/core/material/neo_hookean.h"
#include "tissue_trainer/core/material/stvk.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"
#include "tissue_trainer/core/model/hyperelastic.h"

namespace tt {
namespace adamss {
namespace {

using namespace testutil;
using Source = DeformationGradientSource;

template <class Law>
using VH = VirtualHexahedronModel<Law>;

const LawOptions kPlain{};

std::vector<StvkLaw::Constants> stvkConstants() {
  std::vector<StvkLaw::Constants> c;
  for (const Material& m : testMaterials()) c.push_back(StvkLaw::constants(m));
  return c;
}

std::vector<HunterConstants> hunterConstants() {
  return {HunterConstants::table21(), HunterConstants::table21()};
}

// A hex grid (VTK hexes) with the same frame in every hex.
Mesh hexGrid(int cells, const Eigen::Matrix3d& frame, double jitter, std::mt19937& rng) {
  Mesh m = boxGrid(cells + 1, cells + 1, cells + 1, Eigen::Vector3d(0.01, 0.012, 0.009),
                   TetSplit::kNone);
  std::uniform_real_distribution<double> u(-jitter, jitter);
  for (int n = 0; n < m.numNodes(); ++n)
    for (int i = 0; i < 3; ++i) m.rest(i, n) += 0.01 * u(rng);
  for (auto& B : m.hexFibreFrame) B = frame;
  return m;
}

// x = A X + the random motion `amplitude` (m) per coordinate.
Eigen::VectorXd deformed(const Mesh& m, const Eigen::Matrix3d& A, double amplitude,
                         std::mt19937& rng) {
  Eigen::VectorXd x = perturbed(m, amplitude, rng);
  for (int n = 0; n < m.numNodes(); ++n)
    x.segment<3>(3 * n) += (A - Eigen::Matrix3d::Identity()) * m.rest.col(n);
  return x;
}

Eigen::Matrix3d stretchAndShear(double s) {
  Eigen::Matrix3d A;
  A << 1 + s, 0.3 * s, -0.2 * s, 0.1 * s, 1 - 0.5 * s, 0.4 * s, -0.3 * s, 0.2 * s, 1 + 0.7 * s;
  return A;
}

template <class Law>
void expectTetsEqualTheFiniteElement(const std::vector<typename Law::Constants>& constants,
                                     double strain, const LawOptions& options) {
  std::mt19937 rng(5);
  const Mesh mesh = boxMesh(3, 2, 2, 0.01, rng, 0.15);  // random frames per tet
  const HyperelasticModel<Law> fem(mesh, constants, options);
  const VH<Law> vh(mesh, constants, options, Source::kShapeFunctions);
  for (int trial = 0; trial < 3; ++trial) {
    const Eigen::VectorXd x = deformed(mesh, stretchAndShear(strain), 0.1 * strain * 0.01, rng);
    EXPECT_LT(relDiff(force(vh, x), force(fem, x)), 1e-12);
    EXPECT_NEAR(vh.energy(x), fem.energy(x), 1e-12 * std::abs(fem.energy(x)));
    const Eigen::MatrixXd K = denseStiffness(vh, mesh, x);
    EXPECT_LT(relDiff(K, denseStiffness(fem, mesh, x)), 1e-12);
  }
}

TEST(VirtualHexahedron, TetsEqualTheFiniteElementOfTheSameLaw) {
  expectTetsEqualTheFiniteElement<HunterLaw>(hunterConstants(), 0.1, kPlain);
  expectTetsEqualTheFiniteElement<StvkLaw>(stvkConstants(), 0.15, kPlain);
  std::vector<NeoHookeanLaw::Constants> neo;
  for (const Material& m : testMaterials()) neo.push_back(NeoHookeanLaw::constants(m));
  LawOptions inverting;
  inverting.inversionThreshold = 0.3;
  inverting.psdProjection = true;
  expectTetsEqualTheFiniteElement<NeoHookeanLaw>(neo, 0.15, inverting);
}

// Eq. 2.74 corrected, from the current intersection points: f_2l = -R_v A_l sum_k S_kl
// zeta_k / |zeta_k^0|, f_2l+1 = -f_2l, with S = B^T F^-1 P B in the element's frame and A_l,
// R_v of the box with edges zeta_l^0 (orthonormal axes: A_l = L_m L_n, V_h = L_0 L_1 L_2).
TEST(VirtualHexahedron, TetForcesArePointForcesOfCorrectedEq274) {
  std::mt19937 rng(8);
  const Mesh mesh = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const VH<HunterLaw> vh(mesh, hunterConstants(), kPlain, Source::kShapeFunctions);
  const AxisMesh axes = buildAxes(mesh);
  const Eigen::VectorXd x = deformed(mesh, stretchAndShear(0.1), 2e-4, rng);
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(x.size());
  for (std::size_t e = 0; e < mesh.tets.size(); ++e) {
    const AxisRest<Tet4>& a = axes.tetRest[e];
    const NodeMatrix<4> xe = gatherNodes<4>(x, mesh.tets[e]);
    const Tet4::Rest rest = Tet4::rest(mesh.rest, mesh.tets[e]);
    const Eigen::Matrix3d F = xe * rest.grad[0].transpose();
    const Eigen::Matrix3d& B = mesh.fibreFrame[e];
    const auto law = HunterLaw::parameters(HunterConstants::table21(), B);
    const Eigen::Matrix3d S = B.transpose() * F.inverse() * HunterLaw::stress(law, F) * B;
    const Eigen::Matrix3d zeta = axisVectors(intersectionPoints<4>(xe, a.C));
    const Eigen::Vector3d L = a.length0;
    const double Rv = rest.weight[0] / (L[0] * L[1] * L[2]);
    PointMatrix fq;
    for (int l = 0; l < 3; ++l) {
      Eigen::Vector3d sum = Eigen::Vector3d::Zero();
      for (int k = 0; k < 3; ++k) sum += S(k, l) * zeta.col(k) / L[k];
      fq.col(2 * l) = -Rv * L[(l + 1) % 3] * L[(l + 2) % 3] * sum;
      fq.col(2 * l + 1) = -fq.col(2 * l);
    }
    const NodeMatrix<4> fe = distributeToNodes<4>(fq, a.C);
    for (int p = 0; p < 4; ++p) expected.segment<3>(3 * mesh.tets[e][p]) += fe.col(p);
  }
  EXPECT_LT(relDiff(force(vh, x), expected), 1e-12);
}

// Eq. 2.56 with F at the hex centre and the box-face normals n_l = B e_l (orthonormal axes):
// f_2l = -R_v A_l P B e_l, f_2l+1 = -f_2l, distributed by Eq. 2.29.
TEST(VirtualHexahedron, HexForcesArePointForcesOfEq256) {
  std::mt19937 rng(9);
  const Mesh mesh = hexGrid(2, randomRotation(rng), 0.1, rng);
  const VH<StvkLaw> vh(mesh, stvkConstants(), kPlain, Source::kShapeFunctions);
  const AxisMesh axes = buildAxes(mesh);
  const Eigen::VectorXd x = deformed(mesh, stretchAndShear(0.1), 3e-4, rng);
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(x.size());
  for (std::size_t e = 0; e < mesh.hexes.size(); ++e) {
    const AxisRest<Hex8>& a = axes.hexRest[e];
    const NodeMatrix<8> Xe = gatherNodes<8>(mesh.rest, mesh.hexes[e]);
    const Eigen::Matrix3d F =
        gatherNodes<8>(x, mesh.hexes[e]) * Hex8::gradientsAt(Xe, Eigen::Vector3d::Zero()).transpose();
    const Eigen::Matrix3d& B = mesh.hexFibreFrame[e];
    const Eigen::Matrix3d P = StvkLaw::stress(
        StvkLaw::parameters(StvkLaw::constants(testMaterials()[mesh.hexMaterial[e]]), B), F);
    const Hex8::Rest rest = Hex8::rest(mesh.rest, mesh.hexes[e]);
    double V0 = 0.0;
    for (double w : rest.weight) V0 += w;
    const Eigen::Vector3d L = a.length0;
    const double Rv = V0 / (L[0] * L[1] * L[2]);
    PointMatrix fq;
    for (int l = 0; l < 3; ++l) {
      fq.col(2 * l) = -Rv * L[(l + 1) % 3] * L[(l + 2) % 3] * P * B.col(l);
      fq.col(2 * l + 1) = -fq.col(2 * l);
    }
    const NodeMatrix<8> fe = distributeToNodes<8>(fq, a.C);
    for (int p = 0; p < 8; ++p) expected.segment<3>(3 * mesh.hexes[e][p]) += fe.col(p);
  }
  EXPECT_LT(relDiff(force(vh, x), expected), 1e-12);
}

TEST(VirtualHexahedron, ForceIsTheEnergyGradientOnTetsAndAlignedRectangularHexes) {
  std::mt19937 rng(10);
  const Mesh tets = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const VH<HunterPolynomialLaw> onTets(tets, {{}, {}}, kPlain, Source::kShapeFunctions);
  Eigen::VectorXd x = deformed(tets, stretchAndShear(0.1), 2e-4, rng);
  EXPECT_LT(relDiff(force(onTets, x), Eigen::VectorXd(-fdGradient(onTets, x, 1e-8))), 1e-6);

  const Mesh aligned = hexGrid(2, Eigen::Matrix3d::Identity(), 0.0, rng);
  const VH<HunterPolynomialLaw> onHexes(aligned, {{}, {}}, kPlain, Source::kShapeFunctions);
  EXPECT_EQ(onHexes.nonConservativeHexes(), 0);
  x = deformed(aligned, stretchAndShear(0.1), 2e-4, rng);
  EXPECT_LT(relDiff(force(onHexes, x), Eigen::VectorXd(-fdGradient(onHexes, x, 1e-8))), 1e-6);
}

// Oblique axes in a hex: the lever is not the centre gradient, the force is not the gradient of
// the energy and the stiffness is not symmetric; the stiffness is still the force's derivative.
TEST(VirtualHexahedron, ObliqueAxesInHexesAreNotConservativeButTheStiffnessIsTheDerivative) {
  std::mt19937 rng(11);
  const Mesh mesh = hexGrid(2, randomRotation(rng), 0.1, rng);
  const VH<StvkLaw> vh(mesh, stvkConstants(), kPlain, Source::kShapeFunctions);
  EXPECT_EQ(vh.nonConservativeHexes(), static_cast<int>(mesh.hexes.size()));
  const Eigen::VectorXd x = deformed(mesh, stretchAndShear(0.1), 3e-4, rng);
  const Eigen::VectorXd f = force(vh, x);
  EXPECT_GT(relDiff(f, Eigen::VectorXd(-fdGradient(vh, x, 1e-8))), 1e-3);
  const Eigen::MatrixXd K = denseStiffness(vh, mesh, x);
  EXPECT_LT(relDiff(K, fdForceJacobian(vh, x, 1e-8)), 1e-6);
  EXPECT_GT(relDiff(Eigen::MatrixXd(K.transpose()), K), 1e-3);
  const Eigen::VectorXd d = perturbed(mesh, 1.0, rng) - restVector(mesh);
  Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
  vh.addStiffnessTimes(x, d, 1.0, Kd);
  EXPECT_LT(relDiff(Kd, Eigen::VectorXd(K * d)), 1e-12);
}

TEST(VirtualHexahedron, NoForceAtRestAndInvariantUnderRigidMotion) {
  std::mt19937 rng(12);
  const Mesh tets = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const Mesh hexes = hexGrid(2, randomRotation(rng), 0.1, rng);
  for (const Mesh* mesh : {&tets, &hexes})
    for (Source source : {Source::kShapeFunctions, Source::kAxisApproximation}) {
      SCOPED_TRACE(mesh->hexes.empty() ? "tets" : "hexes");
      const VH<StvkLaw> vh(*mesh, stvkConstants(), kPlain, source);
      const Eigen::VectorXd x = deformed(*mesh, stretchAndShear(0.1), 3e-4, rng);
      const Eigen::VectorXd f = force(vh, x);
      EXPECT_LT(force(vh, restVector(*mesh)).lpNorm<Eigen::Infinity>(),
                1e-10 * f.lpNorm<Eigen::Infinity>());
      const Eigen::Matrix3d R = randomRotation(rng);
      const Eigen::VectorXd y = rigidMotion(x, R, Eigen::Vector3d(0.3, -0.2, 0.1));
      EXPECT_LT(relDiff(force(vh, y), rotateVectors(f, R)), 1e-10);
      EXPECT_NEAR(vh.energy(y), vh.energy(x), 1e-10 * vh.energy(x));
    }
}

// The hourglass mode of a cube, u_p = s_p (xi eta zeta of node p) e_x, leaves F at the centre
// unchanged: no force and no energy (Sec. 2.9.1).
TEST(VirtualHexahedron, HourglassModesOfAHexHaveNoForce) {
  std::mt19937 rng(13);
  const Mesh cube = hexGrid(1, Eigen::Matrix3d::Identity(), 0.0, rng);
  const VH<StvkLaw> vh(cube, stvkConstants(), kPlain, Source::kShapeFunctions);
  Eigen::VectorXd x = restVector(cube);
  for (int p = 0; p < Hex8::kNodes; ++p) {
    const int* c = Hex8::corner[p];
    x[3 * cube.hexes[0][p]] += 1e-3 * c[0] * c[1] * c[2];
  }
  EXPECT_LT(force(vh, x).lpNorm<Eigen::Infinity>(), 1e-9);
  EXPECT_LT(std::abs(vh.energy(x)), 1e-15);
}

// Eqs. 2.59-2.62 give C = F^T F exactly for a stretch along the axes and for a symmetric shear
// with equal axis stretches, and not for a 30 % simple shear although axis 3 stays orthogonal
// to axes 1 and 2 (off by about 1e-2).
TEST(VirtualHexahedron, AxisApproximationIsExactOnlyInItsCases) {
  const Eigen::Vector3d L(0.002, 0.003, 0.0025);
  auto rightCauchyGreenError = [&](const Eigen::Matrix3d& F) {
    const Eigen::Matrix3d Fa = axisDeformationGradient(F * L.asDiagonal(), L);
    return ((Fa.transpose() * Fa) - F.transpose() * F).norm() / (F.transpose() * F).norm();
  };
  EXPECT_LT(rightCauchyGreenError(Eigen::Vector3d(1.2, 0.9, 1.05).asDiagonal()), 1e-15);
  Eigen::Matrix3d symmetric;
  symmetric << 1.1, 0.2, 0, 0.2, 1.1, 0, 0, 0, 0.95;
  EXPECT_LT(rightCauchyGreenError(symmetric), 1e-14);
  Eigen::Matrix3d simpleShear = Eigen::Matrix3d::Identity();
  simpleShear(0, 1) = 0.3;
  const double error = rightCauchyGreenError(simpleShear);
  EXPECT_GT(error, 1e-3);
  EXPECT_LT(error, 5e-2);
}

// Under a homogeneous stretch along the axes the approximation is exact, so the axis-mode
// forces (Eq. 2.74 corrected) equal the finite element's on tets.
TEST(VirtualHexahedron, AxisApproximationEqualsTheElementUnderStretchAlongTheAxes) {
  std::mt19937 rng(14);
  Mesh mesh = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const Eigen::Matrix3d B = randomRotation(rng);
  for (auto& frame : mesh.fibreFrame) frame = B;
  const std::vector<HunterConstants> c = hunterConstants();
  const VH<HunterLaw> approx(mesh, c, kPlain, Source::kAxisApproximation);
  const HyperelasticModel<HunterLaw> fem(mesh, c, kPlain);
  EXPECT_FALSE(approx.hasStiffness());
  const Eigen::Matrix3d A = B * Eigen::Vector3d(1.12, 0.95, 1.04).asDiagonal() * B.transpose();
  const Eigen::VectorXd x = deformed(mesh, A, 0.0, rng);
  EXPECT_LT(relDiff(force(approx, x), force(fem, x)), 1e-10);
  EXPECT_NEAR(approx.energy(x), fem.energy(x), 1e-10 * fem.energy(x));
  // A shear is approximated: the forces differ.
  const Eigen::VectorXd sheared = deformed(mesh, stretchAndShear(0.1), 0.0, rng);
  EXPECT_GT(relDiff(force(approx, sheared), force(fem, sheared)), 1e-4);
}

TEST(VirtualHexahedron, UnusableElementsAreRefusedByName) {
  std::mt19937 rng(15);
  Mesh flat = boxMesh(1, 1, 1, 0.01, rng, 0.0);
  flat.rest.col(flat.tets[2][3]) = flat.rest.col(flat.tets[2][0]);  // collapse tet 2
  try {
    VH<StvkLaw>(flat, stvkConstants(), kPlain, Source::kShapeFunctions);
    FAIL() << "a flat tet was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tet "), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace adamss
}  // namespace tt
