#include "tissue_trainer/core/mesh/generators.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace tt {
namespace {

constexpr double kPi = 3.14159265358979323846;

// Hex corners are named by their bits (x | y << 1 | z << 2) in the unit cell.
// VTK hexahedron order: the bottom face counter-clockwise, then the top face.
constexpr int kVtkCornerBits[8] = {0b000, 0b001, 0b011, 0b010, 0b100, 0b101, 0b111, 0b110};

// Five tets: the central tet on the even corners (000, 011, 101, 110) and one corner tet at
// each odd corner with its three neighbours.
constexpr int kFiveTets[5][4] = {
    {0b000, 0b011, 0b101, 0b110},  // central, twice the volume of the others
    {0b001, 0b000, 0b011, 0b101},
    {0b010, 0b000, 0b011, 0b110},
    {0b100, 0b000, 0b101, 0b110},
    {0b111, 0b011, 0b101, 0b110},
};

// Six tets around the diagonal 000-111: one per order in which the three axes are crossed.
constexpr int kSixTets[6][4] = {
    {0b000, 0b001, 0b011, 0b111}, {0b000, 0b001, 0b101, 0b111},
    {0b000, 0b010, 0b011, 0b111}, {0b000, 0b010, 0b110, 0b111},
    {0b000, 0b100, 0b101, 0b111}, {0b000, 0b100, 0b110, 0b111},
};

void orientPositively(const Eigen::Matrix3Xd& x, Tet& t) {
  if (tetVolume(x, t) < 0.0) std::swap(t[2], t[3]);
}

void finish(Mesh& mesh) {
  mesh.surface = extractSurface(mesh);
  mesh.fillDefaults();
}

}  // namespace

Mesh boxGrid(int nodesX, int nodesY, int nodesZ, const Eigen::Vector3d& size, TetSplit split) {
  if (nodesX < 2 || nodesY < 2 || nodesZ < 2)
    throw std::invalid_argument("boxGrid: need at least 2 nodes along each axis");
  Mesh mesh;
  const auto index = [&](int i, int j, int k) { return i + nodesX * (j + nodesY * k); };
  mesh.rest.resize(3, nodesX * nodesY * nodesZ);
  for (int k = 0; k < nodesZ; ++k)
    for (int j = 0; j < nodesY; ++j)
      for (int i = 0; i < nodesX; ++i)
        mesh.rest.col(index(i, j, k)) =
            Eigen::Vector3d(size.x() * i / (nodesX - 1), size.y() * j / (nodesY - 1),
                            size.z() * k / (nodesZ - 1));

  const bool five = split == TetSplit::kFive || split == TetSplit::kFiveMirrored;
  const bool mirrored = split == TetSplit::kFiveMirrored || split == TetSplit::kSixMirrored;
  const bool hexes = split == TetSplit::kNone;
  const int perHex = hexes ? 0 : five ? 5 : 6;
  const int cells = (nodesX - 1) * (nodesY - 1) * (nodesZ - 1);
  if (hexes) mesh.hexes.reserve(cells);
  mesh.tets.reserve(static_cast<size_t>(cells) * perHex);

  for (int k = 0; k + 1 < nodesZ; ++k)
    for (int j = 0; j + 1 < nodesY; ++j)
      for (int i = 0; i + 1 < nodesX; ++i) {
        // Mirroring the cell along every axis whose index is odd gives the 2x2x2 kernel;
        // mirroring swaps bit `axis` of each corner name.
        const int flip = mirrored ? ((i & 1) | (j & 1) << 1 | (k & 1) << 2) : 0;
        const auto corner = [&](int bits, bool mirror) {
          const int b = mirror ? bits ^ flip : bits;
          return index(i + (b & 1), j + (b >> 1 & 1), k + (b >> 2 & 1));
        };
        if (hexes) {
          Hex hex;
          for (int c = 0; c < 8; ++c) hex[c] = corner(kVtkCornerBits[c], false);
          mesh.hexes.push_back(hex);
        }
        for (int t = 0; t < perHex; ++t) {
          const int* bits = five ? kFiveTets[t] : kSixTets[t];
          Tet tet{corner(bits[0], true), corner(bits[1], true), corner(bits[2], true),
                  corner(bits[3], true)};
          orientPositively(mesh.rest, tet);
          mesh.tets.push_back(tet);
        }
      }
  finish(mesh);
  return mesh;
}

Mesh cantileverBeam(double length, double width, int cellsAlong, int cellsAcross,
                    TetSplit split) {
  Mesh mesh = boxGrid(cellsAlong + 1, cellsAcross + 1, cellsAcross + 1,
                      Eigen::Vector3d(length, width, width), split);
  mesh.rest.row(1).array() -= 0.5 * width;
  mesh.rest.row(2).array() -= 0.5 * width;
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (mesh.rest(0, n) == 0.0) mesh.nodeTags[n] = kFixedAll;
  return mesh;
}

double spindleRadius(const SpindleShape& shape, double z) {
  const double s = std::sin(kPi * z / shape.length);
  return shape.tendonRadius + (shape.maxRadius - shape.tendonRadius) * s * s;
}

namespace {

double spindleRadiusSlope(const SpindleShape& shape, double z) {
  const double w = kPi / shape.length;
  return (shape.maxRadius - shape.tendonRadius) * w * std::sin(2.0 * w * z);
}

// Fibres follow the meridians scaled to pass through the point: rho(z) = s r(z).
Eigen::Matrix3d spindleFrame(const SpindleShape& shape, const Eigen::Vector3d& p) {
  const double rho = std::hypot(p.x(), p.y());
  const double theta = std::atan2(p.y(), p.x());
  const double s = rho / spindleRadius(shape, p.z());
  const double slope = s * spindleRadiusSlope(shape, p.z());
  const Eigen::Vector3d fibre =
      Eigen::Vector3d(slope * std::cos(theta), slope * std::sin(theta), 1.0).normalized();
  const Eigen::Vector3d around(-std::sin(theta), std::cos(theta), 0.0);
  Eigen::Matrix3d frame;
  frame << fibre, around.cross(fibre), around;
  return frame;
}

// The three tets of the wedge between triangle (a, b, c) and the same triangle `offset`
// node indices higher. Ordering the triangle by index makes every quad face split along the
// diagonal through its lowest-index node, which the neighbouring wedge chooses too.
void splitWedge(std::array<int, 3> tri, int offset, const Eigen::Matrix3Xd& x,
                std::vector<Tet>& tets) {
  std::sort(tri.begin(), tri.end());
  const int a = tri[0], b = tri[1], c = tri[2];
  Tet wedge[3] = {{a, b, c, c + offset},
                  {a, b, b + offset, c + offset},
                  {a, a + offset, b + offset, c + offset}};
  for (Tet& t : wedge) {
    orientPositively(x, t);
    tets.push_back(t);
  }
}

}  // namespace

Mesh spindleMuscle(const SpindleShape& shape) {
  if (shape.segments < 3 || shape.layers < 2 || shape.tendonRadius <= 0.0 ||
      shape.maxRadius < shape.tendonRadius || shape.length <= 0.0)
    throw std::invalid_argument("spindleMuscle: need segments >= 3, layers >= 2, "
                                "0 < tendonRadius <= maxRadius, length > 0");
  const int perLayer = shape.segments + 1;  // axis node first, then the ring
  Mesh mesh;
  mesh.rest.resize(3, perLayer * shape.layers);
  for (int l = 0; l < shape.layers; ++l) {
    const double z = shape.length * l / (shape.layers - 1);
    const double r = spindleRadius(shape, z);
    mesh.rest.col(l * perLayer) = Eigen::Vector3d(0.0, 0.0, z);
    for (int s = 0; s < shape.segments; ++s) {
      const double theta = 2.0 * kPi * s / shape.segments;
      mesh.rest.col(l * perLayer + 1 + s) =
          Eigen::Vector3d(r * std::cos(theta), r * std::sin(theta), z);
    }
  }
  mesh.tets.reserve(3 * static_cast<size_t>(shape.segments) * (shape.layers - 1));
  for (int l = 0; l + 1 < shape.layers; ++l) {
    const int axis = l * perLayer;
    for (int s = 0; s < shape.segments; ++s)
      splitWedge({axis, axis + 1 + s, axis + 1 + (s + 1) % shape.segments}, perLayer,
                 mesh.rest, mesh.tets);
  }
  mesh.fibreFrame.reserve(mesh.tets.size());
  for (const Tet& t : mesh.tets) {
    const Eigen::Vector3d centroid = 0.25 * (mesh.rest.col(t[0]) + mesh.rest.col(t[1]) +
                                             mesh.rest.col(t[2]) + mesh.rest.col(t[3]));
    mesh.fibreFrame.push_back(spindleFrame(shape, centroid));
  }
  finish(mesh);
  for (int n = 0; n < perLayer; ++n) {
    mesh.nodeTags[n] = kFixedAll;
    mesh.nodeTags[(shape.layers - 1) * perLayer + n] = kFixedAll;
  }
  return mesh;
}

Mesh spindleMuscle(double length, double maxRadius) {
  SpindleShape shape;
  shape.tendonRadius *= maxRadius / shape.maxRadius;
  shape.length = length;
  shape.maxRadius = maxRadius;
  return spindleMuscle(shape);
}

int ellipsoidNode(const EllipsoidShape& shape, int k, int i, int j) {
  if (i == 0) return k;
  const int c = shape.circumferential;
  return (shape.transmural + 1) + (k * shape.meridional + i - 1) * c + ((j % c) + c) % c;
}

namespace {

Eigen::Vector3d ellipsoidPoint(const EllipsoidShape& shape, double t, double s, double v) {
  const double rs = shape.shortRadiusAt(t), rl = shape.longRadiusAt(t);
  const double uBase = -std::acos(shape.baseZ / rl);
  const double u = -kPi + s * (uBase + kPi);
  return Eigen::Vector3d(rs * std::sin(u) * std::cos(v), rs * std::sin(u) * std::sin(v),
                         rl * std::cos(u));
}

// The node of cell (i, j, k)'s corner `bits` (bit 0: +i, bit 1: +j, bit 2: +k).
int ellipsoidCorner(const EllipsoidShape& shape, int i, int j, int k, int bits) {
  return ellipsoidNode(shape, k + (bits >> 2 & 1), i + (bits & 1), j + (bits >> 1 & 1));
}

bool hasRepeatedNode(const Tet& t) {
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b)
      if (t[a] == t[b]) return true;
  return false;
}

}  // namespace

Mesh truncatedEllipsoid(const EllipsoidShape& shape, TetSplit split) {
  if (shape.transmural < 1 || shape.meridional < 2 || shape.circumferential < 3 ||
      !(shape.endoShort > 0.0 && shape.epiShort > shape.endoShort &&
        shape.epiLong > shape.endoLong && shape.baseZ >= 0.0 && shape.baseZ < shape.endoLong))
    throw std::invalid_argument("truncatedEllipsoid: need transmural >= 1, meridional >= 2, "
                                "circumferential >= 3, 0 < endo < epi radii, 0 <= baseZ < endoLong");
  if (split != TetSplit::kNone && split != TetSplit::kSix)
    throw std::invalid_argument("truncatedEllipsoid: split none (hexes) or six (tets) only");
  const int nt = shape.transmural, nm = shape.meridional, nc = shape.circumferential;
  Mesh mesh;
  mesh.rest.resize(3, (nt + 1) * (1 + nm * nc));
  for (int k = 0; k <= nt; ++k)
    for (int i = 0; i <= nm; ++i)
      for (int j = 0; j < (i == 0 ? 1 : nc); ++j)
        mesh.rest.col(ellipsoidNode(shape, k, i, j)) = ellipsoidPoint(
            shape, static_cast<double>(k) / nt, static_cast<double>(i) / nm, 2.0 * kPi * j / nc);
  // Corner bit 1 (+j) mirrored when (i, j, k) is left-handed in space, so hexes are positive.
  const Eigen::Matrix3Xd& x = mesh.rest;
  const auto at = [&](int bits) { return x.col(ellipsoidCorner(shape, 1, 0, 0, bits)); };
  const double handedness =
      (at(1) - at(0)).dot((at(2) - at(0)).cross(at(4) - at(0)));
  const int mirror = handedness < 0.0 ? 0b010 : 0;
  for (int k = 0; k < nt; ++k)
    for (int i = 0; i < nm; ++i)
      for (int j = 0; j < nc; ++j) {
        const auto corner = [&](int bits) {
          return ellipsoidCorner(shape, i, j, k, (bits ^ mirror));
        };
        if (split == TetSplit::kNone) {
          Hex hex;
          for (int c = 0; c < 8; ++c) hex[c] = corner(kVtkCornerBits[c]);
          mesh.hexes.push_back(hex);
          continue;
        }
        for (const int* bits : kSixTets) {
          Tet tet{corner(bits[0]), corner(bits[1]), corner(bits[2]), corner(bits[3])};
          if (hasRepeatedNode(tet)) continue;  // a flat tet of an apex cell
          orientPositively(mesh.rest, tet);
          mesh.tets.push_back(tet);
        }
      }
  finish(mesh);
  // The collapsed apex quads of the hexes give each a triangle with a repeated node: no area.
  mesh.surface.erase(std::remove_if(mesh.surface.begin(), mesh.surface.end(),
                                    [](const Triangle& t) {
                                      return t[0] == t[1] || t[1] == t[2] || t[0] == t[2];
                                    }),
                     mesh.surface.end());
  for (int k = 0; k <= nt; ++k)
    for (int j = 0; j < nc; ++j) mesh.nodeTags[ellipsoidNode(shape, k, nm, j)] = kFixedAll;
  return mesh;
}

}  // namespace tt
