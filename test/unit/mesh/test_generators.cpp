#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <map>
#include <set>

#include "tissue_trainer/core/mesh/generators.h"

namespace tt {
namespace {

constexpr double kPi = 3.14159265358979323846;

using FaceKey = std::array<int, 3>;

std::map<FaceKey, int> faceCounts(const Mesh& mesh) {
  std::map<FaceKey, int> counts;
  for (const Tet& t : mesh.tets)
    for (int skip = 0; skip < 4; ++skip) {
      FaceKey f;
      for (int i = 0, j = 0; i < 4; ++i)
        if (i != skip) f[j++] = t[i];
      std::sort(f.begin(), f.end());
      ++counts[f];
    }
  return counts;
}

// The axis whose coordinate is 0 or size on all three nodes (the box face the triangle lies
// in), with the sign of its outward normal; {-1, 0} when the triangle is inside the box.
std::pair<int, int> boxFaceOf(const Mesh& mesh, const FaceKey& f, const Eigen::Vector3d& size) {
  for (int axis = 0; axis < 3; ++axis)
    for (int side = 0; side < 2; ++side) {
      const double plane = side * size[axis];
      if (std::all_of(f.begin(), f.end(), [&](int n) { return mesh.rest(axis, n) == plane; }))
        return {axis, side ? 1 : -1};
    }
  return {-1, 0};
}

Eigen::Vector3d triangleAreaVector(const Eigen::Matrix3Xd& x, const Triangle& t) {
  return 0.5 * (x.col(t[1]) - x.col(t[0])).cross(x.col(t[2]) - x.col(t[0]));
}

struct ConformityReport {
  int interiorFaces = 0;      // shared by two tets
  int unmatchedInside = 0;    // belong to one tet but lie inside the box: a crack
  int overShared = 0;         // shared by more than two tets
};

ConformityReport conformity(const Mesh& mesh, const Eigen::Vector3d& size) {
  ConformityReport r;
  for (const auto& [face, count] : faceCounts(mesh)) {
    if (count == 2) ++r.interiorFaces;
    if (count > 2) ++r.overShared;
    if (count == 1 && boxFaceOf(mesh, face, size).first < 0) ++r.unmatchedInside;
  }
  return r;
}

const TetSplit kAllSplits[] = {TetSplit::kFive, TetSplit::kFiveMirrored, TetSplit::kSix,
                               TetSplit::kSixMirrored};

TEST(BoxGrid, FourCubedFiveSplitHas64NodesAnd135Tets) {
  // Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation",
  // Appendix E: a 4 x 4 x 4 grid of 64 nodes and 135 tetrahedra.
  const Mesh m = boxGrid(4, 4, 4, Eigen::Vector3d::Ones(), TetSplit::kFiveMirrored);
  EXPECT_EQ(m.numNodes(), 64);
  EXPECT_EQ(m.numTets(), 135);
  EXPECT_TRUE(m.hexes.empty());  // the split's tets are the elements, not both
  const Mesh hexes = boxGrid(4, 4, 4, Eigen::Vector3d::Ones(), TetSplit::kNone);
  EXPECT_EQ(hexes.hexes.size(), 27u);
  EXPECT_EQ(hexes.numTets(), 0);
  const Mesh six = boxGrid(4, 4, 4, Eigen::Vector3d::Ones(), TetSplit::kSix);
  EXPECT_EQ(six.numTets(), 162);
}

TEST(BoxGrid, TetsArePositiveAndFillEachHexWithTheAdamssVolumes) {
  const Eigen::Vector3d size(0.3, 0.2, 0.5);
  for (TetSplit split : kAllSplits) {
    const Mesh m = boxGrid(4, 3, 6, size, split);
    const std::vector<Hex> hexes = boxGrid(4, 3, 6, size, TetSplit::kNone).hexes;  // same nodes
    const int perHex = m.numTets() / static_cast<int>(hexes.size());
    ASSERT_EQ(perHex * static_cast<int>(hexes.size()), m.numTets());
    const double hexVolume = 0.1 * 0.1 * 0.1;
    double total = 0.0;
    for (size_t h = 0; h < hexes.size(); ++h) {
      std::vector<double> volumes;
      const std::set<int> hexNodes(hexes[h].begin(), hexes[h].end());
      for (int t = 0; t < perHex; ++t) {
        const Tet& tet = m.tets[h * perHex + t];
        for (int n : tet) EXPECT_TRUE(hexNodes.count(n)) << "tet leaves its hex";
        volumes.push_back(tetVolume(m.rest, tet));
        total += volumes.back();
      }
      std::sort(volumes.begin(), volumes.end());
      EXPECT_GT(volumes.front(), 0.0);
      // "Adamss: Advanced Anisotropic Mass-Spring System", Figs. 2.7-2.8: with five, one tet is
      // twice the others; with six, all equal.
      for (int t = 0; t < perHex; ++t) {
        const double expected = (perHex == 5 && t == 4) ? hexVolume / 3 : hexVolume / 6;
        EXPECT_NEAR(volumes[t], expected, 1e-15);
      }
    }
    EXPECT_NEAR(total, size.prod(), 1e-14);
  }
}

TEST(BoxGrid, HexesFollowVtkNodeOrder) {
  const Eigen::Vector3d size(2.0, 3.0, 4.0);
  const Mesh m = boxGrid(3, 4, 5, size, TetSplit::kNone);
  const Eigen::Vector3d cell(1.0, 1.0, 1.0);
  const int offsets[8][3] = {{0, 0, 0}, {1, 0, 0}, {1, 1, 0}, {0, 1, 0},
                             {0, 0, 1}, {1, 0, 1}, {1, 1, 1}, {0, 1, 1}};
  ASSERT_EQ(m.hexes.size(), 2u * 3u * 4u);
  for (const Hex& h : m.hexes)
    for (int c = 0; c < 8; ++c)
      for (int a = 0; a < 3; ++a)
        EXPECT_DOUBLE_EQ(m.rest(a, h[c]) - m.rest(a, h[0]), offsets[c][a] * cell[a]);
}

TEST(BoxGrid, ConformityOfEverySplit) {
  // Odd and even cell counts so the mirrored kernel is cut at the box's far faces.
  const Eigen::Vector3d size(0.3, 0.4, 0.5);
  for (TetSplit split : kAllSplits) {
    SCOPED_TRACE(static_cast<int>(split));
    const Mesh m = boxGrid(4, 5, 6, size, split);
    const ConformityReport r = conformity(m, size);
    EXPECT_EQ(r.overShared, 0);

    double surfaceArea = 0.0;
    for (const Triangle& t : m.surface) surfaceArea += triangleAreaVector(m.rest, t).norm();
    const double boxArea = 2.0 * (size.x() * size.y() + size.y() * size.z() + size.z() * size.x());

    if (split == TetSplit::kFive) {
      // Identical 5-tet cells put opposite diagonals on the two sides of every shared face:
      // the faces do not match, and the extracted "surface" includes the cracks.
      EXPECT_GT(r.unmatchedInside, 0);
      EXPECT_GT(surfaceArea, boxArea * 1.5);
      continue;
    }
    EXPECT_EQ(r.unmatchedInside, 0);
    EXPECT_NEAR(surfaceArea, boxArea, 1e-13);
    // Every surface triangle lies on the box face it should, with the outward normal.
    for (const Triangle& t : m.surface) {
      FaceKey key = t;
      std::sort(key.begin(), key.end());
      const auto [axis, sign] = boxFaceOf(m, key, size);
      ASSERT_GE(axis, 0);
      const Eigen::Vector3d n = triangleAreaVector(m.rest, t).normalized();
      EXPECT_NEAR(n[axis], sign, 1e-12);
    }
    // Faces: 4 per tet = 2 * interior + boundary.
    EXPECT_EQ(4 * m.numTets(), 2 * r.interiorFaces + static_cast<int>(m.surface.size()));
  }
}

TEST(BoxGrid, DefaultsAreFilled) {
  const Mesh m = boxGrid(3, 3, 3, Eigen::Vector3d::Ones(), TetSplit::kFiveMirrored);
  EXPECT_EQ(m.fibreFrame.size(), m.tets.size());
  EXPECT_EQ(m.material.size(), m.tets.size());
  EXPECT_EQ(m.nodeTags.size(), static_cast<size_t>(m.numNodes()));
}

TEST(CantileverBeam, FixedEndTaggedAndSectionCentred) {
  const Mesh m = cantileverBeam(1.0, 0.1, 10, 2);
  EXPECT_EQ(m.numNodes(), 11 * 3 * 3);
  int fixed = 0;
  for (int n = 0; n < m.numNodes(); ++n) {
    const bool atRoot = m.rest(0, n) == 0.0;
    EXPECT_EQ(m.nodeTags[n], atRoot ? kFixedAll : 0);
    fixed += atRoot;
  }
  EXPECT_EQ(fixed, 9);
  const Box box = boundingBox(m.rest);
  EXPECT_DOUBLE_EQ(box.min.y(), -0.05);
  EXPECT_DOUBLE_EQ(box.max.z(), 0.05);
  double volume = 0.0;
  for (const Tet& t : m.tets) volume += tetVolume(m.rest, t);
  EXPECT_NEAR(volume, 0.01, 1e-15);
}

// ---- spindle muscle --------------------------------------------------------------------

TEST(SpindleMuscle, DefaultCountsAreNearJeffreysDemo) {
  const Mesh m = spindleMuscle();
  std::printf("spindle muscle: %d nodes, %d tets, %zu surface triangles "
              "(Jeffrey's demo: 861 nodes, 2552 tets)\n",
              m.numNodes(), m.numTets(), m.surface.size());
  EXPECT_EQ(m.numNodes(), 861);
  EXPECT_EQ(m.numTets(), 2400);
  EXPECT_LT(std::abs(m.numTets() - 2552) / 2552.0, 0.07);
}

TEST(SpindleMuscle, PositiveTetsAndClosedSurface) {
  const SpindleShape shape;
  const Mesh m = spindleMuscle(shape);
  for (const Tet& t : m.tets) ASSERT_GT(tetVolume(m.rest, t), 0.0);
  // Closed and consistently oriented: every directed edge once, its reverse once.
  std::map<std::pair<int, int>, int> directed;
  std::set<int> vertices;
  for (const Triangle& t : m.surface)
    for (int i = 0; i < 3; ++i) {
      ++directed[{t[i], t[(i + 1) % 3]}];
      vertices.insert(t[i]);
    }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1);
    EXPECT_EQ(directed.count({edge.second, edge.first}), 1u);
  }
  const int edges = static_cast<int>(directed.size()) / 2;
  EXPECT_EQ(static_cast<int>(vertices.size()) - edges + static_cast<int>(m.surface.size()), 2);
  // Sides: 2 triangles per segment and layer gap; two end caps of `segments` triangles.
  EXPECT_EQ(m.surface.size(), static_cast<size_t>(2 * shape.segments * (shape.layers - 1) +
                                                  2 * shape.segments));
  // Outward: the enclosed volume from the divergence theorem is positive and equals the sum.
  double enclosed = 0.0, summed = 0.0;
  for (const Triangle& t : m.surface)
    enclosed += m.rest.col(t[0]).dot(m.rest.col(t[1]).cross(m.rest.col(t[2]))) / 6.0;
  for (const Tet& t : m.tets) summed += tetVolume(m.rest, t);
  EXPECT_NEAR(enclosed, summed, 1e-12 * summed);
}

TEST(SpindleMuscle, VolumeMatchesPolygonalFrustaAndTheSolidOfRevolution) {
  SpindleShape shape;
  const Mesh m = spindleMuscle(shape);
  double meshVolume = 0.0;
  for (const Tet& t : m.tets) meshVolume += tetVolume(m.rest, t);

  // The tets tile the stack of regular-polygon frusta exactly.
  const int n = shape.segments;
  const double polygonFactor = std::sin(2 * kPi / n) / (2 * kPi / n);  // n-gon / circle area
  const double h = shape.length / (shape.layers - 1);
  double frusta = 0.0;
  for (int l = 0; l + 1 < shape.layers; ++l) {
    const double r1 = spindleRadius(shape, l * h), r2 = spindleRadius(shape, (l + 1) * h);
    frusta += polygonFactor * kPi * h * (r1 * r1 + r1 * r2 + r2 * r2) / 3.0;
  }
  EXPECT_NEAR(meshVolume, frusta, 1e-12 * frusta);

  // Solid of revolution of r = a + b sin^2(pi z / L): V = pi L (a^2 + a b + 3 b^2 / 8).
  const double a = shape.tendonRadius, b = shape.maxRadius - shape.tendonRadius;
  const double exact = kPi * shape.length * (a * a + a * b + 3 * b * b / 8);
  // Error bound: the inscribed polygon loses (1 - polygonFactor); interpolating r linearly
  // between layers errs by at most h^2/8 max|r''| = h^2/8 * 2 pi^2 b / L^2 in radius, which
  // changes the area by at most 2 pi r_max times that.
  const double radiusError = h * h / 8 * 2 * kPi * kPi * b / (shape.length * shape.length);
  const double bound = (1 - polygonFactor) * exact +
                       polygonFactor * 2 * kPi * shape.maxRadius * radiusError * shape.length;
  std::printf("spindle volume: mesh %.6e, exact %.6e, relative error %.3e, bound %.3e\n",
              meshVolume, exact, (meshVolume - exact) / exact, bound / exact);
  EXPECT_LE(std::abs(meshVolume - exact), bound);
  EXPECT_LT(bound / exact, 0.025);  // the bound itself is informative

  // Refining the ring converges to the solid of revolution.
  shape.segments = 80;
  shape.layers = 161;
  const Mesh fine = spindleMuscle(shape);
  double fineVolume = 0.0;
  for (const Tet& t : fine.tets) fineVolume += tetVolume(fine.rest, t);
  EXPECT_LT(std::abs(fineVolume - exact), std::abs(meshVolume - exact) / 10);
}

TEST(SpindleMuscle, FibreFramesFollowTheMeridians) {
  const SpindleShape shape;
  const Mesh m = spindleMuscle(shape);
  ASSERT_EQ(m.fibreFrame.size(), m.tets.size());
  double maxTilt = 0.0;
  for (int t = 0; t < m.numTets(); ++t) {
    const Eigen::Matrix3d& frame = m.fibreFrame[t];
    EXPECT_LT((frame.transpose() * frame - Eigen::Matrix3d::Identity()).norm(), 1e-12);
    EXPECT_NEAR(frame.determinant(), 1.0, 1e-12);
    // Independent tangent: finite difference along the scaled meridian through the centroid.
    Eigen::Vector3d c = Eigen::Vector3d::Zero();
    for (int n : m.tets[t]) c += 0.25 * m.rest.col(n);
    const double rho = std::hypot(c.x(), c.y()), theta = std::atan2(c.y(), c.x());
    const double s = rho / spindleRadius(shape, c.z());
    const auto meridian = [&](double z) {
      const double r = s * spindleRadius(shape, z);
      return Eigen::Vector3d(r * std::cos(theta), r * std::sin(theta), z);
    };
    const double dz = 1e-6 * shape.length;
    const Eigen::Vector3d tangent = (meridian(c.z() + dz) - meridian(c.z() - dz)).normalized();
    EXPECT_LT((frame.col(0) - tangent).norm(), 1e-8);
    // Column 2 is circumferential: horizontal and perpendicular to the radial direction.
    EXPECT_NEAR(frame(2, 2), 0.0, 1e-12);
    EXPECT_NEAR(frame.col(2).dot(Eigen::Vector3d(c.x(), c.y(), 0).normalized()), 0.0, 1e-12);
    maxTilt = std::max(maxTilt, std::acos(std::min(1.0, frame(2, 0))));
  }
  // The fibres do tilt with the spindle (not all parallel to the axis).
  EXPECT_GT(maxTilt, 0.1);
}

TEST(SpindleMuscle, TendonEndsAreFixed) {
  const SpindleShape shape;
  const Mesh m = spindleMuscle(shape);
  const Box box = boundingBox(m.rest);
  EXPECT_NEAR(box.max.z(), shape.length, 1e-15);
  for (int n = 0; n < m.numNodes(); ++n) {
    const bool end = m.rest(2, n) == box.min.z() || m.rest(2, n) == box.max.z();
    EXPECT_EQ(m.nodeTags[n], end ? kFixedAll : 0);
  }
}

}  // namespace
}  // namespace tt
