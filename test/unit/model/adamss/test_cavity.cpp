// The Adamss cavity (model/adamss/cavity.h): the enclosed volume against exact volumes, its
// invariance and sign, the closedness check, the pressure forces of Eq. 2.119, and force,
// stiffness and stiffness product against finite differences of the energy and the force.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <string>

#include "../../model_test_util.h"
#include "tissue_trainer/core/model/adamss/cavity.h"

namespace tt {
namespace {

using adamss::CavityFacet;
using adamss::CavityModel;
using adamss::CavityParameters;
using namespace testutil;

// The unit cube's corners (bit b of the index: coordinate b is 1) times `side`, plus `offset`.
Eigen::Matrix3Xd cubeNodes(double side, const Eigen::Vector3d& offset) {
  Eigen::Matrix3Xd x(3, 8);
  for (int c = 0; c < 8; ++c)
    x.col(c) = offset + side * Eigen::Vector3d(c & 1, (c >> 1) & 1, (c >> 2) & 1);
  return x;
}

// The six faces, counter-clockwise seen from outside.
std::vector<CavityFacet> cubeQuads() {
  return {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
}

std::vector<CavityFacet> split(const std::vector<CavityFacet>& quads) {
  std::vector<CavityFacet> triangles;
  for (const CavityFacet& q : quads) {
    triangles.push_back({q[0], q[1], q[2]});
    triangles.push_back({q[0], q[2], q[3]});
  }
  return triangles;
}

std::vector<CavityFacet> reversed(std::vector<CavityFacet> facets) {
  for (CavityFacet& f : facets) std::reverse(f.begin(), f.end());
  return facets;
}

// The regular icosahedron (0, +-1, +-phi) and its cyclic permutations, edge 2; its faces are
// the vertex triples at mutual distance 2, turned so their normals point outward.
struct Surface {
  Eigen::Matrix3Xd nodes;
  std::vector<CavityFacet> facets;
};
Surface icosahedron() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  Surface s;
  s.nodes.resize(3, 12);
  int n = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (double a : {-1.0, 1.0})
      for (double b : {-phi, phi}) {
        Eigen::Vector3d p = Eigen::Vector3d::Zero();
        p[(axis + 1) % 3] = a;
        p[(axis + 2) % 3] = b;
        s.nodes.col(n++) = p;
      }
  const auto edge = [&](int i, int j) {
    return std::abs((s.nodes.col(i) - s.nodes.col(j)).norm() - 2.0) < 1e-9;
  };
  for (int i = 0; i < 12; ++i)
    for (int j = i + 1; j < 12; ++j)
      for (int k = j + 1; k < 12; ++k)
        if (edge(i, j) && edge(j, k) && edge(i, k)) {
          const Eigen::Vector3d normal =
              (s.nodes.col(j) - s.nodes.col(i)).cross(s.nodes.col(k) - s.nodes.col(i));
          if (normal.dot(s.nodes.col(i)) > 0.0)
            s.facets.push_back({i, j, k});
          else
            s.facets.push_back({i, k, j});
        }
  return s;
}

Eigen::VectorXd flat(const Eigen::Matrix3Xd& x) {
  return Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
}

Eigen::Matrix3Xd columns(const Eigen::VectorXd& x) {
  return Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, x.size() / 3);
}

std::string refusal(const std::vector<CavityFacet>& facets, int numNodes) {
  try {
    adamss::checkClosedSurface(facets, numNodes);
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "";
}

TEST(AdamssCavity, CubeVolumeIsExactWithQuadsAndTriangles) {
  const Eigen::Matrix3Xd x = cubeNodes(0.03, Eigen::Vector3d(1.0, -2.0, 0.5));
  EXPECT_NEAR(adamss::enclosedVolume(cubeQuads(), x), 2.7e-5, 1e-12 * 2.7e-5);
  EXPECT_NEAR(adamss::enclosedVolume(split(cubeQuads()), x), 2.7e-5, 1e-12 * 2.7e-5);
  const CavityModel model(x, cubeQuads(), {1.0, 0.0, 1.0});
  EXPECT_NEAR(model.restVolume(), 2.7e-5, 1e-12 * 2.7e-5);
  EXPECT_EQ(model.nodes().size(), 8u);
}

// The icosahedron of edge a has volume 5 (3 + sqrt 5) a^3 / 12.
TEST(AdamssCavity, IcosahedronVolumeIsExact) {
  const Surface s = icosahedron();
  ASSERT_EQ(s.facets.size(), 20u);
  EXPECT_NO_THROW(adamss::checkClosedSurface(s.facets, 12));
  const double exact = 5.0 * (3.0 + std::sqrt(5.0)) * 8.0 / 12.0;
  EXPECT_NEAR(adamss::enclosedVolume(s.facets, s.nodes), exact, 1e-12 * exact);
}

TEST(AdamssCavity, VolumeIsInvariantUnderRigidMotionAndFlipsWithOrientation) {
  std::mt19937 rng(3);
  const Surface s = icosahedron();
  const Eigen::VectorXd x = flat(s.nodes) + 0.1 * Eigen::VectorXd::Random(36);
  const double v = adamss::enclosedVolume(s.facets, columns(x));
  for (int trial = 0; trial < 5; ++trial) {
    const Eigen::Matrix3d R = randomRotation(rng);
    const Eigen::Vector3d t = 10.0 * randomUnit(rng);
    const Eigen::VectorXd y = rigidMotion(x, R, t);
    EXPECT_NEAR(adamss::enclosedVolume(s.facets, columns(y)), v, 1e-12 * v);
    // The model's forces turn with the body.
    const CavityModel model(s.nodes, s.facets, {2.0, 5.0, 0.9});
    EXPECT_LT(relDiff(force(model, y), rotateVectors(force(model, x), R)), 1e-12);
  }
  EXPECT_NEAR(adamss::enclosedVolume(reversed(s.facets), columns(x)), -v, 1e-12 * v);
  // The model orients either way to a positive volume: the same forces.
  const CavityModel out(s.nodes, s.facets, {2.0, 0.0, 1.0});
  const CavityModel in(s.nodes, reversed(s.facets), {2.0, 0.0, 1.0});
  EXPECT_GT(in.restVolume(), 0.0);
  EXPECT_NEAR(in.volume(x), v, 1e-12 * v);
  EXPECT_LT(relDiff(force(in, x), force(out, x)), 1e-14);
}

// Eq. 2.119: on a triangle f_i = -(1/3) P A n_j (n_j into the cavity) from every face at i.
// On the cube at rest, a planar quad gives -(1/4) P A n_j.
TEST(AdamssCavity, PressureForcesAreThoseOfEquation2119) {
  const Surface s = icosahedron();
  const Eigen::VectorXd x = flat(s.nodes) + 0.2 * Eigen::VectorXd::Random(36);
  const double p = 1500.0;
  const CavityModel model(s.nodes, s.facets, {p, 0.0, 1.0});
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(36);
  for (const CavityFacet& f : s.facets) {
    const Eigen::Vector3d a = x.segment<3>(3 * f[0]), b = x.segment<3>(3 * f[1]),
                          c = x.segment<3>(3 * f[2]);
    const Eigen::Vector3d areaTimesInwardNormal = -0.5 * (b - a).cross(c - a);
    for (int node : f) expected.segment<3>(3 * node) += -p * areaTimesInwardNormal / 3.0;
  }
  EXPECT_LT(relDiff(force(model, x), expected), 1e-12);

  const Eigen::Matrix3Xd cube = cubeNodes(2.0, Eigen::Vector3d(0.3, 0.2, 0.1));
  const CavityModel box(cube, cubeQuads(), {p, 0.0, 1.0});
  Eigen::VectorXd quadForces = Eigen::VectorXd::Zero(24);
  for (const CavityFacet& q : cubeQuads()) {
    const Eigen::Vector3d outward =
        0.5 * (cube.col(q[2]) - cube.col(q[0])).cross(cube.col(q[3]) - cube.col(q[1]));
    for (int node : q) quadForces.segment<3>(3 * node) += p * outward / 4.0;
  }
  EXPECT_LT(relDiff(force(box, flat(cube)), quadForces), 1e-14);
}

// A pressure on a time curve is the curve's value at the step's start, with the forces of a
// constant pressure of that value; a repeated start gives the same.
TEST(AdamssCavity, PressureOnATimeCurveIsItsValueAtTheStepStart) {
  const Surface s = icosahedron();
  CavityParameters ramp{0.0, 20.0, 1.0};
  ramp.pressureFollowsCurve = true;
  ramp.pressureCurve = TimeCurve::piecewiseLinear({0.0, 0.2}, {0.0, 400.0});
  CavityModel model(s.nodes, s.facets, ramp);
  EXPECT_TRUE(model.needsStepUpdates());
  EXPECT_EQ(model.pressure(), 0.0);
  const Eigen::VectorXd x = flat(s.nodes) + 0.1 * Eigen::VectorXd::Random(36);
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(36);
  model.beginStep(0.05, x, v);
  EXPECT_DOUBLE_EQ(model.pressure(), 100.0);
  const CavityModel constant(s.nodes, s.facets, {100.0, 20.0, 1.0});
  EXPECT_FALSE(constant.needsStepUpdates());
  EXPECT_LT(relDiff(force(model, x), force(constant, x)), 1e-15);
  EXPECT_DOUBLE_EQ(model.energy(x), constant.energy(x));
  model.beginStep(0.3, x, v);
  EXPECT_DOUBLE_EQ(model.pressure(), 400.0);
  model.beginStep(0.05, x, v);
  EXPECT_DOUBLE_EQ(model.pressure(), 100.0);
}

TEST(AdamssCavity, NoForceAtTheTargetVolumeWithoutPressure) {
  const Surface s = icosahedron();
  const CavityModel model(s.nodes, s.facets, {0.0, 1e3, 1.0});
  EXPECT_LT(force(model, flat(s.nodes)).lpNorm<Eigen::Infinity>(), 1e-12);
  EXPECT_NEAR(model.energy(flat(s.nodes)), 0.0, 1e-20);
}

// Deformed, non-planar quads and triangles; pressure and a penalty away from its target.
TEST(AdamssCavity, ForceIsMinusTheEnergyGradientAndStiffnessItsJacobian) {
  std::srand(7);
  struct Case {
    Eigen::Matrix3Xd nodes;
    std::vector<CavityFacet> facets;
  };
  const Surface ico = icosahedron();
  const std::vector<Case> cases = {{cubeNodes(1.0, Eigen::Vector3d(0.1, 0.2, 0.3)), cubeQuads()},
                                   {ico.nodes, ico.facets}};
  for (const Case& c : cases) {
    const CavityModel model(c.nodes, c.facets, {3.0, 40.0, 1.1});
    const Eigen::VectorXd x = flat(c.nodes) + 0.15 * Eigen::VectorXd::Random(c.nodes.size());
    const Eigen::VectorXd f = force(model, x);
    EXPECT_LT(relDiff(f, Eigen::VectorXd(-fdGradient(model, x, 1e-6))), 1e-8);
    EXPECT_GT(f.norm(), 1.0);

    const SparsePattern pattern(static_cast<int>(c.nodes.cols()), {}, model.couplings());
    SparseMatrix K = pattern.zeroMatrix();
    model.addStiffness(x, 1.0, pattern, K);
    const Eigen::MatrixXd dense(K);
    const Eigen::MatrixXd fd = fdForceJacobian(model, x, 1e-6);
    EXPECT_LT(relDiff(dense, fd), 1e-7);
    // Pressure and penalty are conservative: the stiffness is symmetric.
    EXPECT_LT(relDiff(dense, Eigen::MatrixXd(dense.transpose())), 1e-13);

    const Eigen::VectorXd d = Eigen::VectorXd::Random(x.size());
    Eigen::VectorXd product = Eigen::VectorXd::Zero(x.size());
    model.addStiffnessTimes(x, d, 2.0, product);
    EXPECT_LT(relDiff(product, Eigen::VectorXd(2.0 * dense * d)), 1e-12);
  }
}

TEST(AdamssCavity, AnOpenOrInconsistentSurfaceIsRefusedNamingTheEdge) {
  std::vector<CavityFacet> open = cubeQuads();
  open.pop_back();  // the face {1, 3, 7, 5}
  EXPECT_EQ(refusal(open, 8),
            "adamss_cavity: edge (1, 3) belongs to 1 facets; a closed surface has every edge in "
            "exactly two");
  std::vector<CavityFacet> turned = cubeQuads();
  std::reverse(turned[0].begin(), turned[0].end());
  EXPECT_EQ(refusal(turned, 8),
            "adamss_cavity: the two facets at edge (0, 1) run along it the same way; orient the "
            "facets consistently");
  std::vector<CavityFacet> doubled = split(cubeQuads());
  doubled.push_back({0, 1, 2});
  doubled.push_back({0, 2, 1});
  EXPECT_NE(refusal(doubled, 8).find("edge (0, 1) belongs to 4 facets"), std::string::npos);
  EXPECT_EQ(refusal({{0, 1, 2, 3, 4}}, 8), "adamss_cavity: facet 0 has 5 nodes (expected 3 or 4)");
  EXPECT_EQ(refusal({{0, 1, 9}}, 8), "adamss_cavity: facet 0: node 9 is not in [0, 7]");
  EXPECT_EQ(refusal({{0, 1, 1}}, 8), "adamss_cavity: facet 0 repeats node 1");
  EXPECT_EQ(refusal(cubeQuads(), 8), "");
  // Closed but flat: two triangles back to back.
  const std::vector<CavityFacet> backToBack = {{0, 1, 2}, {0, 2, 1}};
  const CavityParameters pressure{1.0, 0.0, 1.0};
  EXPECT_THROW(CavityModel(cubeNodes(1.0, Eigen::Vector3d::Zero()), backToBack, pressure),
               std::invalid_argument);
}

}  // namespace
}  // namespace tt
