#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <fstream>
#include <random>
#include <sstream>
#include <string>

#include "tissue_trainer/core/mesh/embedding.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "../random_draws.h"

namespace tt {
namespace {

Eigen::VectorXd flatten(const Eigen::Matrix3Xd& x) {
  return Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
}

// A box grid whose interior nodes are jittered, so the cells are not axis-aligned boxes.
Mesh jitteredGrid(std::mt19937& rng) {
  Mesh m = boxGrid(6, 5, 4, Eigen::Vector3d(1.0, 0.8, 0.6), TetSplit::kFiveMirrored);
  std::uniform_real_distribution<double> jitter(-0.04, 0.04);
  const Box box = boundingBox(m.rest);
  for (int n = 0; n < m.numNodes(); ++n) {
    const Eigen::Vector3d p = m.rest.col(n);
    const bool boundary = ((p - box.min).array() == 0).any() || ((p - box.max).array() == 0).any();
    if (!boundary) m.rest.col(n) += testutil::drawVector(jitter, rng);
  }
  for (const Tet& t : m.tets) EXPECT_GT(tetVolume(m.rest, t), 0.0);
  return m;
}

Eigen::Matrix3Xd randomPoints(std::mt19937& rng, int count, const Eigen::Vector3d& lo,
                              const Eigen::Vector3d& hi) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::Matrix3Xd p(3, count);
  for (int i = 0; i < count; ++i)
    for (int a = 0; a < 3; ++a) p(a, i) = lo[a] + u(rng) * (hi[a] - lo[a]);
  return p;
}

double distanceToTet(const Mesh& m, int t, const Eigen::Vector3d& p) {
  const Tet& n = m.tets[t];
  Eigen::Vector4d w;
  return std::sqrt(closestPointInTet(m.rest.col(n[0]), m.rest.col(n[1]), m.rest.col(n[2]),
                                     m.rest.col(n[3]), p, w));
}

TEST(Embedding, ClosestPointInTetSatisfiesTheOptimalityCondition) {
  std::mt19937 rng(7);
  std::normal_distribution<double> g(0.0, 1.0);
  for (int trial = 0; trial < 2000; ++trial) {
    Eigen::Vector3d v[4];
    for (auto& x : v) x = testutil::drawVector(g, rng);
    const Eigen::Vector3d p = 2.0 * testutil::drawVector(g, rng);
    Eigen::Vector4d w;
    const double d2 = closestPointInTet(v[0], v[1], v[2], v[3], p, w);
    ASSERT_GE(w.minCoeff(), 0.0);
    ASSERT_NEAR(w.sum(), 1.0, 1e-12);
    const Eigen::Vector3d q = w[0] * v[0] + w[1] * v[1] + w[2] * v[2] + w[3] * v[3];
    ASSERT_NEAR((p - q).squaredNorm(), d2, 1e-12);
    // q is the projection of p onto the convex hull iff (p - q).(v_i - q) <= 0 for all i.
    for (const auto& x : v) ASSERT_LE((p - q).dot(x - q), 1e-10);
    const Eigen::Vector4d b = barycentric(v[0], v[1], v[2], v[3], p);
    if (b.minCoeff() >= 0.0) ASSERT_EQ(d2, 0.0);
  }
}

TEST(Embedding, GridSearchAgreesWithBruteForce) {
  std::mt19937 rng(11);
  const Mesh m = jitteredGrid(rng);
  // Points inside the box and up to 0.3 outside it.
  const Eigen::Matrix3Xd points = randomPoints(rng, 600, Eigen::Vector3d::Constant(-0.3),
                                               Eigen::Vector3d(1.3, 1.1, 0.9));
  const Embedding e(m, points);
  int outside = 0;
  double maxDistance = 0.0;
  for (int i = 0; i < e.numPoints(); ++i) {
    const Eigen::Vector3d p = points.col(i);
    double nearest = std::numeric_limits<double>::infinity();
    for (int t = 0; t < m.numTets(); ++t) nearest = std::min(nearest, distanceToTet(m, t, p));
    ASSERT_NEAR(distanceToTet(m, e.tetOf(i), p), nearest, 1e-14) << "point " << i;
    ASSERT_NEAR(e.weights(i).sum(), 1.0, 1e-12);
    if (nearest > 0.0) {
      ++outside;
      maxDistance = std::max(maxDistance, nearest);
    }
  }
  EXPECT_EQ(e.numOutside(), outside);
  EXPECT_NEAR(e.maxOutsideDistance(), maxDistance, 1e-14);
  EXPECT_GT(outside, 100);
  EXPECT_LT(outside, 500);
  std::printf("jittered grid: %.1f of %d tets tested per point\n", e.meanTetsTested(),
              m.numTets());
  EXPECT_LT(e.meanTetsTested(), 0.5 * m.numTets());
}

TEST(Embedding, SearchCostPerPointDoesNotGrowWithTheMesh) {
  std::mt19937 rng(13);
  const Eigen::Matrix3Xd points =
      randomPoints(rng, 400, Eigen::Vector3d::Constant(-0.02), Eigen::Vector3d::Constant(1.02));
  const Mesh coarse = boxGrid(6, 6, 6, Eigen::Vector3d::Ones(), TetSplit::kSixMirrored);
  const Mesh fine = boxGrid(21, 21, 21, Eigen::Vector3d::Ones(), TetSplit::kSixMirrored);
  const Embedding a(coarse, points), b(fine, points);
  std::printf("tets tested per point: %.1f of %d (coarse), %.1f of %d (fine)\n",
              a.meanTetsTested(), coarse.numTets(), b.meanTetsTested(), fine.numTets());
  EXPECT_LT(b.meanTetsTested(), 2.0 * a.meanTetsTested());  // with 64 times the tets
}

// Any fixed weights summing to one make the embedded points follow an affine map exactly.
void expectAffine(const Mesh& m, const Embedding& e, std::mt19937& rng, double tolerance) {
  std::normal_distribution<double> g(0.0, 1.0);
  Eigen::Matrix3d A;
  for (int i = 0; i < 9; ++i) A(i) = (i % 4 == 0 ? 1.0 : 0.0) + 0.3 * g(rng);
  const Eigen::Vector3d b = testutil::drawVector(g, rng);
  const Eigen::Matrix3Xd deformed = (A * m.rest).colwise() + b;
  const Eigen::Matrix3Xd atRest = e.apply(flatten(m.rest));
  const Eigen::Matrix3Xd moved = e.apply(flatten(deformed));
  const Eigen::Matrix3Xd expected = (A * atRest).colwise() + b;
  const double scale = 1.0 + expected.cwiseAbs().maxCoeff();
  EXPECT_LT((moved - expected).cwiseAbs().maxCoeff(), tolerance * scale);
}

TEST(Embedding, AffineDeformationMovesEmbeddedPointsAffinely) {
  std::mt19937 rng(3);
  const Mesh m = jitteredGrid(rng);
  const Eigen::Matrix3Xd points = randomPoints(rng, 500, Eigen::Vector3d::Constant(-0.05),
                                               Eigen::Vector3d(1.05, 0.85, 0.65));
  for (OutsidePolicy policy : {OutsidePolicy::kClamp, OutsidePolicy::kExtrapolate}) {
    const Embedding e(m, points, policy);
    EXPECT_GT(e.numOutside(), 0);
    expectAffine(m, e, rng, 1e-12);
    // At rest: inside points and extrapolated ones come back exactly; clamped ones move onto
    // the mesh, by their distance to it.
    const Eigen::Matrix3Xd atRest = e.apply(flatten(m.rest));
    for (int i = 0; i < e.numPoints(); ++i) {
      const double moved = (atRest.col(i) - points.col(i)).norm();
      const double distance = distanceToTet(m, e.tetOf(i), points.col(i));
      if (policy == OutsidePolicy::kExtrapolate || distance == 0.0)
        EXPECT_LT(moved, 1e-12);
      else
        EXPECT_NEAR(moved, distance, 1e-12);
    }
  }
}

TEST(Embedding, WorksOnTheSpindle) {
  std::mt19937 rng(5);
  const Mesh m = spindleMuscle();
  const Box box = boundingBox(m.rest);
  const Eigen::Matrix3Xd points = randomPoints(rng, 400, box.min, box.max);
  const Embedding e(m, points, OutsidePolicy::kExtrapolate);
  for (int i = 0; i < e.numPoints(); ++i) {
    double nearest = std::numeric_limits<double>::infinity();
    for (int t = 0; t < m.numTets(); ++t)
      nearest = std::min(nearest, distanceToTet(m, t, points.col(i)));
    ASSERT_NEAR(distanceToTet(m, e.tetOf(i), points.col(i)), nearest, 1e-15);
  }
  expectAffine(m, e, rng, 1e-12);
}

// ---- liver: a tiny local reader for the two simple files, independent of mesh_io ----------

// Gmsh v1 ($NOD / $ELM), tets only (element type 4); other element types are skipped.
Mesh readGmshV1Tets(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  Mesh m;
  std::string token;
  std::vector<int> indexOf;  // file node number -> column
  while (in >> token) {
    if (token == "$NOD") {
      int count;
      in >> count;
      m.rest.resize(3, count);
      for (int i = 0; i < count; ++i) {
        int id;
        in >> id >> m.rest(0, i) >> m.rest(1, i) >> m.rest(2, i);
        if (id >= static_cast<int>(indexOf.size())) indexOf.resize(id + 1, -1);
        indexOf[id] = i;
      }
    } else if (token == "$ELM") {
      int count;
      in >> count;
      for (int i = 0; i < count; ++i) {
        int id, type, phys, elem, nodes;
        in >> id >> type >> phys >> elem >> nodes;
        std::vector<int> v(nodes);
        for (int& n : v) in >> n;
        if (type != 4) continue;
        Tet t{indexOf[v[0]], indexOf[v[1]], indexOf[v[2]], indexOf[v[3]]};
        if (tetVolume(m.rest, t) < 0) std::swap(t[2], t[3]);
        m.tets.push_back(t);
      }
    }
  }
  m.fillDefaults();
  return m;
}

Eigen::Matrix3Xd readObjVertices(const std::string& path) {
  std::ifstream in(path);
  EXPECT_TRUE(in.good()) << path;
  std::vector<Eigen::Vector3d> v;
  std::string line;
  while (std::getline(in, line)) {
    if (line.rfind("v ", 0) != 0) continue;
    std::istringstream s(line.substr(2));
    Eigen::Vector3d p;
    s >> p.x() >> p.y() >> p.z();
    v.push_back(p);
  }
  Eigen::Matrix3Xd x(3, v.size());
  for (size_t i = 0; i < v.size(); ++i) x.col(i) = v[i];
  return x;
}

TEST(Embedding, SmoothLiverSurfaceInCoarseLiverMesh) {
  const std::string dir = std::string(TT_SOURCE_DIR) + "/config/meshes/";
  const Mesh m = readGmshV1Tets(dir + "liver.msh");
  const Eigen::Matrix3Xd vertices = readObjVertices(dir + "liver-smooth.obj");
  ASSERT_EQ(m.numNodes(), 181);
  ASSERT_EQ(m.numTets(), 596);
  ASSERT_EQ(vertices.cols(), 2194);
  const Box box = boundingBox(m.rest);
  const double diagonal = (box.max - box.min).norm();

  const Embedding e(m, vertices);
  std::printf("liver-smooth.obj in liver.msh: %d of %d vertices outside, max distance %.4g "
              "(mesh bounding-box diagonal %.4g, file units); %.1f of %d tets tested per "
              "vertex\n",
              e.numOutside(), e.numPoints(), e.maxOutsideDistance(), diagonal,
              e.meanTetsTested(), m.numTets());
  EXPECT_LT(e.meanTetsTested(), 0.2 * m.numTets());
  EXPECT_LT(e.numOutside(), e.numPoints());
  EXPECT_LT(e.maxOutsideDistance(), 0.02 * diagonal);
  std::mt19937 rng(1);
  expectAffine(m, e, rng, 1e-12);
}

}  // namespace
}  // namespace tt
