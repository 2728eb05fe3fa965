// The anisotropy axes of the Adamss mass-spring system (model/adamss/axes.h): intersection
// points and the coefficient matrix C against hand-computed cases and against the thesis's own
// procedure written out here (plane intersection, Eqs. 2.9-2.12, with the area tests and
// coefficients of Eqs. 2.14-2.16 and 2.21-2.24); affine invariance of the ray casting; the
// identity C_p,2l - C_p,2l+1 = grad N_p . zeta_l^0 on linear tets (which the virtual
// hexahedron relies on) and where it stops holding on hexes; and the distribution of point
// forces to the nodes (Eq. 2.29) keeping resultant, moment and work.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>

#include "../../model_test_util.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/axes.h"
#include "../../random_draws.h"

namespace tt {
namespace adamss {
namespace {

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Vector3d v = testutil::drawVector(n, rng);  // then w: g++'s order
  Eigen::Quaterniond q(n(rng), v.x(), v.y(), v.z());
  return q.normalized().toRotationMatrix();
}

NodeMatrix<4> unitTet() {
  NodeMatrix<4> X;
  X << 0, 1, 0, 0,  //
      0, 0, 1, 0,   //
      0, 0, 0, 1;
  return X;
}

// A rectangular box of edges `size` in VTK order, turned by R and moved by t.
NodeMatrix<8> box(const Eigen::Vector3d& size, const Eigen::Matrix3d& R, const Eigen::Vector3d& t) {
  NodeMatrix<8> X;
  for (int p = 0; p < 8; ++p) {
    Eigen::Vector3d c;
    for (int i = 0; i < 3; ++i) c[i] = 0.5 * (Hex8::corner[p][i] + 1) * size[i];
    X.col(p) = R * c + t;
  }
  return X;
}

template <int N>
NodeMatrix<N> randomOffsets(std::mt19937& rng, double amplitude) {
  std::uniform_real_distribution<double> u(-amplitude, amplitude);
  NodeMatrix<N> d;
  for (int i = 0; i < d.size(); ++i) d.data()[i] = u(rng);
  return d;
}

NodeMatrix<4> axesRandomTet(std::mt19937& rng, double h) {
  for (;;) {
    NodeMatrix<4> X = h * (unitTet() + randomOffsets<4>(rng, 0.3));
    Eigen::Matrix3d Dm;
    Dm << X.col(1) - X.col(0), X.col(2) - X.col(0), X.col(3) - X.col(0);
    if (Dm.determinant() > 0.05 * h * h * h) return X;
  }
}

NodeMatrix<8> jitteredCube(std::mt19937& rng, double h, double jitter) {
  NodeMatrix<8> X = box(Eigen::Vector3d::Constant(h), Eigen::Matrix3d::Identity(),
                        Eigen::Vector3d(0.3, -0.2, 0.1));
  return X + h * randomOffsets<8>(rng, jitter);
}

double triangleArea(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c) {
  return 0.5 * ((a - b).cross(b - c)).norm();  // Eq. 2.14
}

// The thesis's procedure for one axis direction w of a tet (Sec. 2.3.1.2): for each face, the
// ray of Eq. 2.9 against the face's plane (normal Eq. 2.11, distance Eq. 2.12 with the unit
// axis), the inside test of Eq. 2.23 and the area coordinates of Eq. 2.24 (xi = N_2,
// eta = N_3 of Eq. 2.21). Returns the column of C.
Eigen::Vector4d thesisTetPoint(const NodeMatrix<4>& X, const Eigen::Vector3d& w) {
  const Eigen::Vector3d xb = X.rowwise().mean();  // Eq. 2.22
  for (const auto& f : Tet4::faces) {
    const Eigen::Vector3d x1 = X.col(f[0]), x2 = X.col(f[1]), x3 = X.col(f[2]);
    const Eigen::Vector3d n = ((x1 - x2).cross(x2 - x3)).normalized();
    const double d = (x1 - xb).dot(n) / w.dot(n);
    if (!(d > 0.0)) continue;
    const Eigen::Vector3d v = d * w + xb;
    const double S = triangleArea(x1, x2, x3);
    const double S12 = triangleArea(v, x1, x2), S13 = triangleArea(v, x1, x3),
                 S23 = triangleArea(v, x2, x3);
    if (std::abs(S12 + S13 + S23 - S) > 1e-9 * S) continue;
    const double xi = S13 / S, eta = S12 / S;
    Eigen::Vector4d column = Eigen::Vector4d::Zero();
    column[f[0]] = 1 - xi - eta;
    column[f[1]] = xi;
    column[f[2]] = eta;
    return column;
  }
  ADD_FAILURE() << "no face found by the reference procedure";
  return Eigen::Vector4d::Zero();
}

// The same for a rectangular hex (Sec. 2.3.1.1): plane by Eqs. 2.10-2.12, the rectangle test of
// Eq. 2.15 with S = |x1 - x2| |x1 - x4| (Eq. 2.13) and xi = 2 S_j14 / S, eta = 2 S_j12 / S
// (Eq. 2.16) for the bilinear functions of Eq. 2.7 (N_1 at x1 = (0, 0), N_3 at x3 = (1, 1)).
Eigen::Matrix<double, 8, 1> thesisHexPoint(const NodeMatrix<8>& X, const Eigen::Vector3d& w) {
  const Eigen::Vector3d xb = X.rowwise().mean();  // Eq. 2.8
  for (const auto& f : Hex8::faces) {
    const Eigen::Vector3d x1 = X.col(f[0]), x2 = X.col(f[1]), x3 = X.col(f[2]), x4 = X.col(f[3]);
    const Eigen::Vector3d n = ((x1 - x2).cross(x2 - x3)).normalized();  // Eq. 2.11
    const double d = (x1 - xb).dot(n) / w.dot(n);                      // Eq. 2.12
    if (!(d > 0.0)) continue;
    const Eigen::Vector3d v = d * w + xb;  // Eq. 2.9
    const double S = (x1 - x2).norm() * (x1 - x4).norm();
    const double S12 = triangleArea(v, x1, x2), S14 = triangleArea(v, x1, x4),
                 S23 = triangleArea(v, x2, x3), S34 = triangleArea(v, x3, x4);
    if (std::abs(S12 + S14 + S23 + S34 - S) > 1e-9 * S) continue;
    const double xi = 2 * S14 / S, eta = 2 * S12 / S;
    Eigen::Matrix<double, 8, 1> column = Eigen::Matrix<double, 8, 1>::Zero();
    column[f[0]] = (1 - xi) * (1 - eta);
    column[f[1]] = xi * (1 - eta);
    column[f[2]] = xi * eta;
    column[f[3]] = (1 - xi) * eta;
    return column;
  }
  ADD_FAILURE() << "no face found by the reference procedure";
  return Eigen::Matrix<double, 8, 1>::Zero();
}

// Every point lies on its ray from the barycentre (on the + side for q_2l, the - side for
// q_2l+1), its weights are in [0, 1], sum to 1 and sit on the nodes of its face only.
template <class Element>
void expectPointsOnRays(const NodeMatrix<Element::kNodes>& X, const AxisRest<Element>& r,
                        double h, const std::string& what) {
  const Eigen::Vector3d xb = X.rowwise().mean();
  const PointMatrix xq = intersectionPoints<Element::kNodes>(X, r.C);
  for (int j = 0; j < kAxisPoints; ++j) {
    const Eigen::Vector3d u = r.axes0.col(j / 2);
    const Eigen::Vector3d rel = xq.col(j) - xb;
    const double along = rel.dot(u) * (j % 2 == 0 ? 1.0 : -1.0);
    EXPECT_GT(along, 1e-4 * h) << what << " point " << j;
    EXPECT_LT((rel - rel.dot(u) * u).norm(), 1e-12 * h) << what << " point " << j << " off its ray";
    EXPECT_NEAR(r.C.col(j).sum(), 1.0, 1e-14) << what << " point " << j;
    const int* faceNodes = Element::faces[r.face[j]];
    for (int p = 0; p < Element::kNodes; ++p) {
      const bool onFace = std::find(faceNodes, faceNodes + Element::kFaceNodes, p) !=
                          faceNodes + Element::kFaceNodes;
      EXPECT_GE(r.C(p, j), 0.0) << what << " point " << j << " node " << p;
      EXPECT_LE(r.C(p, j), 1.0) << what << " point " << j << " node " << p;
      if (!onFace) EXPECT_EQ(r.C(p, j), 0.0) << what << " point " << j << " node " << p;
    }
  }
  // zeta_l^0 = x_2l - x_2l+1 has the rest length and the direction of axis l.
  const Eigen::Matrix3d zeta = axisVectors(xq);
  for (int l = 0; l < kAxes; ++l)
    EXPECT_LT((zeta.col(l) - r.length0[l] * r.axes0.col(l)).norm(), 1e-12 * h) << what;
}

TEST(AdamssAxes, UnitTetHandComputed) {
  AxisRest<Tet4> r;
  ASSERT_TRUE(tetAxisRest(unitTet(), Eigen::Matrix3d::Identity(), r));
  // The barycentre (1/4, 1/4, 1/4); along +x the ray meets x + y + z = 1 at (1/2, 1/4, 1/4),
  // along -x the face x = 0 at (0, 1/4, 1/4); the weights are the barycentric coordinates.
  PointCoefficients<4> expected;
  expected << 0, 0.5, 0, 0.5, 0, 0.5,  //
      0.5, 0, 0.25, 0.25, 0.25, 0.25,  //
      0.25, 0.25, 0.5, 0, 0.25, 0.25,  //
      0.25, 0.25, 0.25, 0.25, 0.5, 0;
  EXPECT_LT((r.C - expected).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((r.length0 - Eigen::Vector3d::Constant(0.5)).norm(), 1e-15);
  const std::array<int, 6> faces{0, 1, 0, 2, 0, 3};  // face k is opposite node k
  EXPECT_EQ(r.face, faces);
}

TEST(AdamssAxes, UnitCubeHandComputed) {
  AxisRest<Hex8> r;
  const NodeMatrix<8> X = box(Eigen::Vector3d::Ones(), Eigen::Matrix3d::Identity(),
                              Eigen::Vector3d::Zero());
  ASSERT_TRUE(hexAxisRest(X, Eigen::Matrix3d::Identity(), r));
  // Face centres: +x is Hex8 face 3 (nodes 1, 2, 6, 5), -x face 5, +y face 4, -y face 2,
  // +z face 1 (top), -z face 0 (bottom); a quarter on each of the face's nodes.
  const std::array<int, 6> faces{3, 5, 4, 2, 1, 0};
  EXPECT_EQ(r.face, faces);
  for (int j = 0; j < kAxisPoints; ++j)
    for (int k = 0; k < 4; ++k) EXPECT_NEAR(r.C(Hex8::faces[faces[j]][k], j), 0.25, 1e-15);
  EXPECT_LT((r.length0 - Eigen::Vector3d::Ones()).norm(), 1e-15);
}

TEST(AdamssAxes, RayThroughAVertexPutsTheWholeWeightThere) {
  // Cube: the diagonal axis leaves through node 6 (1, 1, 1) and node 0 (0, 0, 0).
  AxisRest<Hex8> hex;
  const NodeMatrix<8> X = box(Eigen::Vector3d::Ones(), Eigen::Matrix3d::Identity(),
                              Eigen::Vector3d::Zero());
  ASSERT_TRUE(hexAxisRest(X, testutil::frameFrom(Eigen::Vector3d::Ones()), hex));
  EXPECT_NEAR(hex.C(6, 0), 1.0, 1e-12);
  EXPECT_NEAR(hex.C(0, 1), 1.0, 1e-12);
  EXPECT_NEAR(hex.length0[0], std::sqrt(3.0), 1e-12);
  // Tet: the axis from the barycentre towards node 3 leaves through node 3.
  AxisRest<Tet4> tet;
  const NodeMatrix<4> T = unitTet();
  const Eigen::Vector3d towards3 = T.col(3) - T.rowwise().mean();
  ASSERT_TRUE(tetAxisRest(T, testutil::frameFrom(towards3), tet));
  EXPECT_NEAR(tet.C(3, 0), 1.0, 1e-14);
  expectPointsOnRays<Tet4>(T, tet, 1.0, "tet vertex ray");
}

TEST(AdamssAxes, TetsMatchTheThesisProcedure) {
  std::mt19937 rng(3);
  for (int trial = 0; trial < 200; ++trial) {
    const double h = 0.01;
    const NodeMatrix<4> X = axesRandomTet(rng, h) + NodeMatrix<4>::Constant(0.05);
    // Any three independent axes (the ray casting does not need them orthogonal).
    Eigen::Matrix3d axes = randomRotation(rng);
    if (trial % 2) axes += randomOffsets<3>(rng, 0.3);
    AxisRest<Tet4> r;
    ASSERT_TRUE(tetAxisRest(X, axes, r));
    for (int j = 0; j < kAxisPoints; ++j) {
      const Eigen::Vector3d w = (j % 2 == 0 ? 1.0 : -1.0) * axes.col(j / 2).normalized();
      const Eigen::Vector4d ref = thesisTetPoint(X, w);
      EXPECT_LT((r.C.col(j) - ref).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial << " point " << j;
    }
    expectPointsOnRays<Tet4>(X, r, h, "tet " + std::to_string(trial));
  }
}

TEST(AdamssAxes, RectangularHexesMatchTheThesisProcedure) {
  std::mt19937 rng(5);
  for (int trial = 0; trial < 100; ++trial) {
    const Eigen::Vector3d size(0.01, 0.02, 0.015);
    const NodeMatrix<8> X = box(size, randomRotation(rng), Eigen::Vector3d(0.1, 0.2, -0.3));
    const Eigen::Matrix3d axes = randomRotation(rng);
    AxisRest<Hex8> r;
    ASSERT_TRUE(hexAxisRest(X, axes, r));
    for (int j = 0; j < kAxisPoints; ++j) {
      const Eigen::Vector3d w = (j % 2 == 0 ? 1.0 : -1.0) * axes.col(j / 2);
      const Eigen::Matrix<double, 8, 1> ref = thesisHexPoint(X, w);
      EXPECT_LT((r.C.col(j) - ref).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial << " point " << j;
    }
    expectPointsOnRays<Hex8>(X, r, 0.01, "box " + std::to_string(trial));
  }
}

TEST(AdamssAxes, DistortedHexesHavePointsOnTheBilinearFaces) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 100; ++trial) {
    const double h = 0.01;
    const NodeMatrix<8> X = jitteredCube(rng, h, 0.15);
    AxisRest<Hex8> r;
    ASSERT_TRUE(hexAxisRest(X, randomRotation(rng), r));
    expectPointsOnRays<Hex8>(X, r, h, "distorted hex " + std::to_string(trial));
    // The weights are bilinear (Eq. 2.7: N_1 N_3 = N_2 N_4), so the point is on the face's
    // bilinear patch, and by the check above on the ray: the faces here are not planar.
    for (int j = 0; j < kAxisPoints; ++j) {
      const int* f = Hex8::faces[r.face[j]];
      EXPECT_NEAR(r.C(f[0], j) * r.C(f[2], j), r.C(f[1], j) * r.C(f[3], j), 1e-13);
    }
  }
}

// An affine map x = A X + b takes barycentres to barycentres, rays to rays and bilinear faces
// to bilinear faces with the same parameters: the element and its axes mapped together give the
// same C. This covers rigid motions and shows that the points follow the nodes under
// homogeneous deformation (Eqs. 2.25-2.27).
TEST(AdamssAxes, AffineImagesGiveTheSameCoefficients) {
  std::mt19937 rng(9);
  for (int trial = 0; trial < 50; ++trial) {
    const Eigen::Matrix3d offsets = randomOffsets<3>(rng, 0.3);  // first, as g++ drew them
    Eigen::Matrix3d A = randomRotation(rng) * (Eigen::Matrix3d::Identity() + offsets);
    if (A.determinant() < 0.2) continue;
    if (trial % 3 == 0) A = randomRotation(rng);  // rigid
    const Eigen::Vector3d b(1.0, -2.0, 3.0);
    const Eigen::Matrix3d axes = randomRotation(rng);

    const NodeMatrix<4> T = axesRandomTet(rng, 0.01);
    AxisRest<Tet4> tet, tetMapped;
    ASSERT_TRUE(tetAxisRest(T, axes, tet));
    ASSERT_TRUE(tetAxisRest((A * T).colwise() + b, A * axes, tetMapped));
    EXPECT_LT((tet.C - tetMapped.C).cwiseAbs().maxCoeff(), 1e-11) << "tet trial " << trial;
    EXPECT_EQ(tet.face, tetMapped.face);
    // The mapped points are the images of the rest points.
    const PointMatrix q = intersectionPoints<4>(T, tet.C);
    const PointMatrix qMapped = intersectionPoints<4>((A * T).colwise() + b, tet.C);
    EXPECT_LT((qMapped - ((A * q).colwise() + b)).cwiseAbs().maxCoeff(), 1e-12);

    const NodeMatrix<8> H = jitteredCube(rng, 0.01, 0.1);
    AxisRest<Hex8> hex, hexMapped;
    ASSERT_TRUE(hexAxisRest(H, axes, hex));
    ASSERT_TRUE(hexAxisRest((A * H).colwise() + b, A * axes, hexMapped));
    EXPECT_LT((hex.C - hexMapped.C).cwiseAbs().maxCoeff(), 1e-10) << "hex trial " << trial;
    EXPECT_EQ(hex.face, hexMapped.face);
  }
}

// On a linear tet the shape functions are affine, so C_p,2l - C_p,2l+1 = N_p(q_2l) - N_p(q_2l+1)
// = grad N_p . zeta_l^0 exactly. (This makes the virtual hexahedron's nodal forces those of the
// finite element with the same law.) On a hex it holds at the centre for axes along the edges of
// a rectangular box, and not for an oblique axis, where the trilinear functions' cubic term
// xi eta zeta enters.
TEST(AdamssAxes, PointDifferencesAreShapeFunctionGradientsOnTets) {
  std::mt19937 rng(11);
  for (int trial = 0; trial < 50; ++trial) {
    const NodeMatrix<4> X = axesRandomTet(rng, 0.01);
    AxisRest<Tet4> r;
    ASSERT_TRUE(tetAxisRest(X, randomRotation(rng), r));
    Eigen::Matrix<double, 3, 4> X3 = X;
    const Tet4::Rest rest = Tet4::rest(Eigen::Matrix3Xd(X3), Tet{0, 1, 2, 3});
    for (int l = 0; l < kAxes; ++l) {
      const Eigen::Vector4d difference = r.C.col(2 * l) - r.C.col(2 * l + 1);
      const Eigen::Vector4d gradient =
          rest.grad[0].transpose() * (r.length0[l] * r.axes0.col(l));
      EXPECT_LT((difference - gradient).cwiseAbs().maxCoeff(), 1e-12) << "trial " << trial;
    }
  }
  const NodeMatrix<8> X = box(Eigen::Vector3d(0.01, 0.02, 0.015), Eigen::Matrix3d::Identity(),
                              Eigen::Vector3d::Zero());
  const Hex8::Gradients centre = Hex8::gradientsAt(X, Eigen::Vector3d::Zero());
  AxisRest<Hex8> aligned, oblique;
  ASSERT_TRUE(hexAxisRest(X, Eigen::Matrix3d::Identity(), aligned));
  ASSERT_TRUE(hexAxisRest(X, testutil::frameFrom(Eigen::Vector3d(1.0, 0.7, 0.4)), oblique));
  double alignedError = 0.0, obliqueError = 0.0;
  for (int l = 0; l < kAxes; ++l) {
    const auto error = [&](const AxisRest<Hex8>& r) {
      const Eigen::Matrix<double, 8, 1> difference = r.C.col(2 * l) - r.C.col(2 * l + 1);
      const Eigen::Matrix<double, 8, 1> gradient =
          centre.transpose() * (r.length0[l] * r.axes0.col(l));
      return (difference - gradient).cwiseAbs().maxCoeff();
    };
    alignedError = std::max(alignedError, error(aligned));
    obliqueError = std::max(obliqueError, error(oblique));
  }
  EXPECT_LT(alignedError, 1e-14);
  EXPECT_GT(obliqueError, 1e-3);
}

// Eq. 2.29 is the transpose of Eqs. 2.26-2.27: point forces and their nodal forces have the same
// resultant and moment and do the same work on any nodal velocities.
TEST(AdamssAxes, DistributionKeepsResultantMomentAndWork) {
  std::mt19937 rng(13);
  const auto check = [&](auto X, const auto& r, const char* what) {
    constexpr int N = decltype(X)::ColsAtCompileTime;
    PointMatrix fq;
    for (int j = 0; j < kAxisPoints; ++j) fq.col(j) = randomOffsets<1>(rng, 1.0);
    const NodeMatrix<N> fe = distributeToNodes<N>(fq, r.C);
    const PointMatrix xq = intersectionPoints<N>(X, r.C);
    EXPECT_LT((fe.rowwise().sum() - fq.rowwise().sum()).norm(), 1e-14) << what;
    Eigen::Vector3d momentNodes = Eigen::Vector3d::Zero(), momentPoints = Eigen::Vector3d::Zero();
    for (int p = 0; p < N; ++p) momentNodes += X.col(p).cross(fe.col(p));
    for (int j = 0; j < kAxisPoints; ++j) momentPoints += xq.col(j).cross(fq.col(j));
    EXPECT_LT((momentNodes - momentPoints).norm(), 1e-14) << what;
    const NodeMatrix<N> v = randomOffsets<N>(rng, 1.0);
    const PointMatrix vq = intersectionPoints<N>(v, r.C);
    EXPECT_NEAR((fq.array() * vq.array()).sum(), (fe.array() * v.array()).sum(), 1e-14) << what;
  };
  for (int trial = 0; trial < 20; ++trial) {
    const NodeMatrix<4> T = axesRandomTet(rng, 0.5);
    AxisRest<Tet4> tet;
    ASSERT_TRUE(tetAxisRest(T, randomRotation(rng), tet));
    check(T, tet, "tet");
    const NodeMatrix<8> H = jitteredCube(rng, 0.5, 0.1);
    AxisRest<Hex8> hex;
    ASSERT_TRUE(hexAxisRest(H, randomRotation(rng), hex));
    check(H, hex, "hex");
  }
}

TEST(AdamssAxes, EveryBoxGridSplitBuilds) {
  std::mt19937 rng(17);
  for (TetSplit split : {TetSplit::kFive, TetSplit::kFiveMirrored, TetSplit::kSix,
                         TetSplit::kSixMirrored, TetSplit::kNone}) {
    Mesh mesh = boxGrid(3, 4, 3, Eigen::Vector3d(0.01, 0.015, 0.01), split);
    for (auto& frame : mesh.fibreFrame) frame = randomRotation(rng);
    for (auto& frame : mesh.hexFibreFrame) frame = randomRotation(rng);
    const AxisMesh axes = buildAxes(mesh);
    ASSERT_EQ(axes.tetRest.size(), mesh.tets.size());
    ASSERT_EQ(axes.hexRest.size(), mesh.hexes.size());
    const std::string what = "split " + std::to_string(static_cast<int>(split));
    for (std::size_t e = 0; e < mesh.tets.size(); ++e)
      expectPointsOnRays<Tet4>(gatherNodes<4>(mesh.rest, mesh.tets[e]), axes.tetRest[e], 0.001,
                               what + " tet " + std::to_string(e));
    for (std::size_t e = 0; e < mesh.hexes.size(); ++e)
      expectPointsOnRays<Hex8>(gatherNodes<8>(mesh.rest, mesh.hexes[e]), axes.hexRest[e], 0.005,
                               what + " hex " + std::to_string(e));
  }
}

TEST(AdamssAxes, FlatElementsAndZeroAxesAreRefusedByName) {
  Mesh mesh = boxGrid(2, 2, 2, Eigen::Vector3d::Constant(0.01), TetSplit::kSix);
  mesh.fibreFrame[3].col(1).setZero();
  try {
    buildAxes(mesh);
    ADD_FAILURE() << "a zero axis was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("tet 3"), std::string::npos) << e.what();
  }
  NodeMatrix<4> flat = unitTet();
  flat.col(3) = 0.5 * (flat.col(1) + flat.col(2));
  AxisRest<Tet4> tet;
  EXPECT_FALSE(tetAxisRest(flat, Eigen::Matrix3d::Identity(), tet));

  Mesh hexMesh = boxGrid(2, 2, 2, Eigen::Vector3d::Constant(0.01), TetSplit::kNone);
  hexMesh.rest.row(2).setZero();  // every node in the plane z = 0
  try {
    buildAxes(hexMesh);
    ADD_FAILURE() << "a flat hex was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("hex 0"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace adamss
}  // namespace tt
