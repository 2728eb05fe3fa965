#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/mesh/quality.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

std::string meshPath(const std::string& name) { return std::string(TT_SOURCE_DIR) + "/config/meshes/" + name; }

std::string meshIoTempDir() {
  const fs::path dir = fs::temp_directory_path() / "tt_test_mesh_io";
  fs::create_directories(dir);
  return dir.string();
}

std::string writeText(const std::string& name, const std::string& text) {
  const std::string path = meshIoTempDir() + "/" + name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

std::string readText(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// A grid of cells x cells x cells unit cubes, each split into the 6 tets around its main
// diagonal (Kuhn), with node positions perturbed by values that are not short decimals.
Mesh kuhnBox(int cells, bool withHexes = false) {
  const int n = cells + 1;
  Mesh m;
  m.rest.resize(3, n * n * n);
  auto id = [n](int i, int j, int k) { return i + n * (j + n * k); };
  for (int k = 0; k < n; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        m.rest.col(id(i, j, k)) = Eigen::Vector3d(i + 0.1 * std::sin(1.0 + i * j + k), j / 3.0 + 0.01 * k,
                                                  k * 0.7 + 1e-3 * std::cos(double(i + 2 * j)));
  const int axisPaths[6][3] = {{0, 1, 2}, {0, 2, 1}, {1, 0, 2}, {1, 2, 0}, {2, 0, 1}, {2, 1, 0}};
  for (int k = 0; k < cells; ++k)
    for (int j = 0; j < cells; ++j)
      for (int i = 0; i < cells; ++i) {
        for (const auto& path : axisPaths) {
          int p[3] = {i, j, k};
          Tet t;
          t[0] = id(p[0], p[1], p[2]);
          for (int s = 0; s < 3; ++s) {
            ++p[path[s]];
            t[s + 1] = id(p[0], p[1], p[2]);
          }
          if (tetVolume(m.rest, t) < 0) std::swap(t[1], t[2]);
          m.tets.push_back(t);
        }
        if (withHexes)
          m.hexes.push_back({id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                             id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)});
      }
  m.surface = extractSurface(m);
  m.fillDefaults();
  return m;
}

double totalTetVolume(const Mesh& m) {
  double v = 0;
  for (const Tet& t : m.tets) v += tetVolume(m.rest, t);
  return v;
}

// Closed, consistently oriented surface: every directed edge appears once and its reverse
// once. Returns sum over triangles of (centroid . normal * area) / 3.
double checkClosedSurface(const Eigen::Matrix3Xd& x, const std::vector<Triangle>& surface) {
  std::map<std::pair<int, int>, int> directed;
  double volume = 0;
  for (const Triangle& tri : surface) {
    for (int e = 0; e < 3; ++e) ++directed[{tri[e], tri[(e + 1) % 3]}];
    const Eigen::Vector3d a = x.col(tri[0]), b = x.col(tri[1]), c = x.col(tri[2]);
    const Eigen::Vector3d areaNormal = 0.5 * (b - a).cross(c - a);
    volume += ((a + b + c) / 3.0).dot(areaNormal) / 3.0;
  }
  for (const auto& [edge, count] : directed) {
    EXPECT_EQ(count, 1) << "edge " << edge.first << "-" << edge.second;
    const auto reverse = directed.find({edge.second, edge.first});
    EXPECT_TRUE(reverse != directed.end() && reverse->second == 1)
        << "edge " << edge.first << "-" << edge.second << " is not shared by exactly two triangles";
  }
  return volume;
}

void expectValidMesh(const Mesh& m) {
  for (const Tet& t : m.tets) {
    for (int v : t) {
      ASSERT_GE(v, 0);
      ASSERT_LT(v, m.numNodes());
    }
    EXPECT_GE(tetVolume(m.rest, t), 0.0);
  }
  EXPECT_EQ(m.fibreFrame.size(), m.tets.size());
  EXPECT_EQ(m.material.size(), m.tets.size());
  EXPECT_EQ(m.nodeTags.size(), static_cast<size_t>(m.numNodes()));
}

void expectSameMesh(const Mesh& a, const Mesh& b) {
  ASSERT_EQ(a.numNodes(), b.numNodes());
  EXPECT_TRUE(a.rest == b.rest) << "max difference " << (a.rest - b.rest).cwiseAbs().maxCoeff();
  EXPECT_EQ(a.tets, b.tets);
  EXPECT_EQ(a.hexes, b.hexes);
  EXPECT_EQ(a.surface.size(), b.surface.size());
}

bool hasNote(const ReadNotes& notes, const std::string& phrase) {
  for (const auto& line : notes.lines)
    if (line.find(phrase) != std::string::npos) return true;
  return false;
}

TEST(MeshIo, LiverGmshV1) {
  ReadNotes notes;
  const Mesh m = readMesh(meshPath("liver.msh"), &notes);
  EXPECT_EQ(m.numNodes(), 181);
  EXPECT_EQ(m.numTets(), 596);
  expectValidMesh(m);
  const double volume = totalTetVolume(m);
  EXPECT_GT(volume, 0.0);
  EXPECT_NEAR(checkClosedSurface(m.rest, m.surface), volume, 1e-10 * volume);
}

TEST(MeshIo, Liver2GmshV1MixedElementsAndSparseIds) {
  ReadNotes notes;
  const Mesh m = readGmsh(meshPath("liver2.msh"), &notes);
  EXPECT_EQ(m.numNodes(), 507);
  EXPECT_EQ(m.numTets(), 1493);
  expectValidMesh(m);
  ASSERT_FALSE(notes.lines.empty());
  EXPECT_TRUE(hasNote(notes, "ignored 860 triangles (type 2), 71 lines (type 1)")) << notes.lines[0];
  const double volume = totalTetVolume(m);
  EXPECT_NEAR(checkClosedSurface(m.rest, m.surface), volume, 1e-10 * volume);
}

TEST(MeshIo, TongueVtu) {
  ReadNotes notes;
  const Mesh m = readMesh(meshPath("volumetricTongue.vtu"), &notes);
  EXPECT_EQ(m.numNodes(), 2238);
  EXPECT_EQ(m.numTets(), 10980);
  expectValidMesh(m);
  const double volume = totalTetVolume(m);
  EXPECT_NEAR(checkClosedSurface(m.rest, m.surface), volume, 1e-10 * volume);
}

TEST(MeshIo, KuhnBoxSurfaceEnclosesItsVolume) {
  const Mesh m = kuhnBox(3);
  EXPECT_EQ(m.surface.size(), 6u * 9u * 2u);
  EXPECT_NEAR(checkClosedSurface(m.rest, m.surface), totalTetVolume(m), 1e-12);
}

TEST(MeshIo, RoundTripsAreExact) {
  const Mesh box = kuhnBox(2);
  const std::string dir = meshIoTempDir();
  writeGmsh2(dir + "/box_v2.msh", box);
  expectSameMesh(box, readMesh(dir + "/box_v2.msh"));
  writeGmsh4(dir + "/box_v4.msh", box);
  expectSameMesh(box, readMesh(dir + "/box_v4.msh"));
  writeTetgen(dir + "/box_tg", box);
  expectSameMesh(box, readMesh(dir + "/box_tg.node"));
  expectSameMesh(box, readTetgen(dir + "/box_tg.ele"));
  writeVtkLegacy(dir + "/box.vtk", box);
  expectSameMesh(box, readMesh(dir + "/box.vtk"));
  writeVtu(dir + "/box.vtu", box);
  expectSameMesh(box, readMesh(dir + "/box.vtu"));
  EXPECT_NE(readText(dir + "/box_v4.msh").find("4.1 0 8"), std::string::npos);
}

TEST(MeshIo, HexesRoundTrip) {
  const Mesh box = kuhnBox(2, true);
  ASSERT_EQ(box.hexes.size(), 8u);
  const std::string dir = meshIoTempDir();
  for (const std::string name : {"hex_v2.msh", "hex.vtk", "hex.vtu"}) {
    writeMesh(dir + "/" + name, box);
    expectSameMesh(box, readMesh(dir + "/" + name));
  }
  writeGmsh4(dir + "/hex_v4.msh", box);
  expectSameMesh(box, readMesh(dir + "/hex_v4.msh"));
  EXPECT_THROW(writeTetgen(dir + "/hex_tg", box), std::invalid_argument);
}

TEST(MeshIo, HandWrittenGmsh41WithBlocksParametricNodesAndTriangles) {
  // Two node blocks with sparse tags (one parametric on a surface), a triangle block and a
  // tet block; one tet is inverted in the file.
  const std::string text =
      "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n"
      "$Entities\n0 0 1 1\n1 0 0 0 1 1 0 0 0\n1 0 0 0 1 1 1 0 0\n$EndEntities\n"
      "$Nodes\n2 5 10 50\n"
      "2 1 1 3\n10\n20\n30\n0 0 0 0.1 0.2\n1 0 0 0.3 0.4\n0 1 0 0.5 0.6\n"
      "3 1 0 2\n40\n50\n0 0 1\n1 1 1\n"
      "$EndNodes\n"
      "$Elements\n2 3 1 3\n2 1 2 1\n1 10 20 30\n3 1 4 2\n2 10 20 30 40\n3 20 10 30 50\n$EndElements\n";
  ReadNotes notes;
  const Mesh m = readMesh(writeText("hand41.msh", text), &notes);
  ASSERT_EQ(m.numNodes(), 5);
  ASSERT_EQ(m.numTets(), 2);
  EXPECT_EQ(m.rest.col(3), Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(m.rest.col(4), Eigen::Vector3d(1, 1, 1));
  EXPECT_EQ(m.tets[0], (Tet{0, 1, 2, 3}));
  EXPECT_EQ(m.tets[1], (Tet{1, 2, 0, 4}));  // was 20 10 30 50 (negative), nodes 1 and 2 swapped
  EXPECT_TRUE(hasNote(notes, "ignored 1 triangles (type 2)"));
  EXPECT_TRUE(hasNote(notes, "reordered 1 inverted"));
  expectValidMesh(m);
}

TEST(MeshIo, HandWrittenGmsh40Layout) {
  const std::string text =
      "$MeshFormat\n4 0 8\n$EndMeshFormat\n"
      "$Nodes\n1 4\n1 3 0 4\n7 0 0 0\n8 1 0 0\n9 0 1 0\n12 0 0 1\n$EndNodes\n"
      "$Elements\n1 1\n1 3 4 1\n5 7 8 9 12\n$EndElements\n";
  const Mesh m = readMesh(writeText("hand40.msh", text));
  ASSERT_EQ(m.numTets(), 1);
  EXPECT_EQ(m.tets[0], (Tet{0, 1, 2, 3}));
  EXPECT_DOUBLE_EQ(tetVolume(m.rest, m.tets[0]), 1.0 / 6.0);
}

TEST(MeshIo, TetgenZeroBasedWithAttributesMarkersAndComments) {
  const std::string dir = meshIoTempDir();
  writeText("tg0.node",
            "# a comment line\n5 3 2 1\n0 0 0 0 7.5 1 0 # trailing comment\n1 1 0 0 1 2 1\n"
            "2 0 1 0 1 2 1\n\n3 0 0 1 1 2 1\n4 1 1 1 0.5 0.5 0\n");
  writeText("tg0.ele", "2 4 1\n0 0 1 2 3 1\n1 1 3 2 4 2\n");  // second tet inverted
  ReadNotes notes;
  const Mesh m = readTetgen(dir + "/tg0.node", &notes);
  ASSERT_EQ(m.numNodes(), 5);
  ASSERT_EQ(m.numTets(), 2);
  EXPECT_EQ(m.tets[0], (Tet{0, 1, 2, 3}));
  EXPECT_EQ(m.tets[1], (Tet{1, 2, 3, 4}));
  EXPECT_TRUE(hasNote(notes, "reordered 1"));
  EXPECT_TRUE(hasNote(notes, "2 attribute(s) per point"));
  expectValidMesh(m);
}

TEST(MeshIo, VtkLegacy51LayoutVoxelsAndIgnoredCells) {
  // 5.1 OFFSETS/CONNECTIVITY layout; a voxel (lexicographic corner order), a tet, a triangle.
  const std::string text =
      "# vtk DataFile Version 5.1\n\nASCII\nDATASET UNSTRUCTURED_GRID\n"
      "POINTS 9 float\n0 0 0 1 0 0 0 1 0 1 1 0\n0 0 1 1 0 1 0 1 1 1 1 1\n0 0 2\n"
      "CELLS 4 15\nOFFSETS vtktypeint64\n0 8 12 15\nCONNECTIVITY vtktypeint64\n"
      "0 1 2 3 4 5 6 7\n4 5 6 8\n0 1 2\n"
      "CELL_TYPES 3\n11 10 5\nPOINT_DATA 9\nSCALARS s float 1\n";
  ReadNotes notes;
  const Mesh m = readMesh(writeText("v51.vtk", text), &notes);
  ASSERT_EQ(m.hexes.size(), 1u);
  EXPECT_EQ(m.hexes[0], (Hex{0, 1, 3, 2, 4, 5, 7, 6}));
  EXPECT_NEAR(hexVolume(m.rest, m.hexes[0]), 1.0, 1e-14);
  ASSERT_EQ(m.numTets(), 1);
  EXPECT_TRUE(hasNote(notes, "ignored 1 triangles (VTK type 5)"));
  expectValidMesh(m);
}

TEST(MeshIo, ObjFacesForms) {
  const std::string text =
      "# square pyramid\nmtllib x.mtl\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvn 0 0 1\n"
      "v 0.5 0.5 1 1.0\ng side\nf 4/1/1 3/1/1 2/1/1 1/1/1\nf 1//1 2//1 5//1\nf -4 -3 -1\n"
      "f 3/1 4/1 5/1\nf 4 1 -1\n";
  const SurfaceMesh s = readObj(writeText("pyramid.obj", text));
  ASSERT_EQ(s.vertices.cols(), 5);
  ASSERT_EQ(s.triangles.size(), 6u);
  EXPECT_EQ(s.triangles[0], (Triangle{3, 2, 1}));
  EXPECT_EQ(s.triangles[1], (Triangle{3, 1, 0}));
  EXPECT_EQ(s.triangles[3], (Triangle{1, 2, 4}));
  // Closed and outward: enclosed volume of the pyramid is 1/3.
  EXPECT_NEAR(checkClosedSurface(s.vertices, s.triangles), 1.0 / 3.0, 1e-14);
}

TEST(MeshIo, ObjRoundTripOfTheLiverSurface) {
  const Mesh m = readMesh(meshPath("liver.msh"));
  const SurfaceMesh s{m.rest, m.surface};
  const std::string path = meshIoTempDir() + "/liver_surface.obj";
  writeObj(path, s);
  const SurfaceMesh back = readObj(path);
  EXPECT_TRUE(back.vertices == s.vertices);
  EXPECT_EQ(back.triangles, s.triangles);
}

TEST(MeshIo, RealObjFilesAreClosedOutwardSurfaces) {
  // Euler characteristic V - E + F = 2 with E = 3F/2 for a closed genus-0 surface.
  const SurfaceMesh s = readObj(meshPath("liver2.obj"));
  EXPECT_EQ(s.vertices.cols(), 1170);
  EXPECT_EQ(s.triangles.size(), 2336u);
  // Closed and outward, enclosing about the volume of the tets of the same organ.
  const double tetVolumeOfLiver2 = totalTetVolume(readMesh(meshPath("liver2.msh")));
  EXPECT_NEAR(checkClosedSurface(s.vertices, s.triangles), tetVolumeOfLiver2, 0.05 * tetVolumeOfLiver2);
  const SurfaceMesh smooth = readObj(meshPath("liver-smooth.obj"));
  EXPECT_EQ(smooth.vertices.cols(), 2194);
  EXPECT_EQ(smooth.triangles.size(), 4384u);
  EXPECT_GT(checkClosedSurface(smooth.vertices, smooth.triangles), 30.0);
}

// Extracts the values of the DataArray with the given Name from a written VTU text.
std::vector<double> vtuArray(const std::string& text, const std::string& name) {
  const std::size_t at = text.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const std::size_t begin = text.find('>', at) + 1;
  std::istringstream in(text.substr(begin, text.find("</DataArray>", begin) - begin));
  std::vector<double> values;
  for (double v; in >> v;) values.push_back(v);
  return values;
}

TEST(MeshIo, VtuCellFieldsForUniformStretchAndRotation) {
  Mesh m = kuhnBox(1);
  const int nt = m.numTets();
  for (auto& frame : m.fibreFrame) frame = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  m.material.assign(nt, 2);
  const Eigen::Vector3d a0 = m.fibreFrame[0].col(0);
  const std::string path = meshIoTempDir() + "/fields.vtu";

  // x = 2 X: det F = 8, E = 1.5 I so |E| = 1.5 sqrt(3), F a0 = 2 a0; displacement = X.
  Eigen::VectorXd x = 2.0 * Eigen::Map<const Eigen::VectorXd>(m.rest.data(), m.rest.size());
  Eigen::VectorXd v = Eigen::VectorXd::LinSpaced(x.size(), 0.0, 1.0);
  VtuFields fields;
  fields.positions = &x;
  fields.velocity = &v;
  writeVtu(path, m, fields);
  std::string text = readText(path);
  const auto ratio = vtuArray(text, "volume_ratio"), strain = vtuArray(text, "green_strain_norm"),
             fibre = vtuArray(text, "fibre_direction"), material = vtuArray(text, "material"),
             displacement = vtuArray(text, "displacement"), velocity = vtuArray(text, "velocity");
  ASSERT_EQ(ratio.size(), size_t(nt));
  ASSERT_EQ(fibre.size(), size_t(3 * nt));
  for (int t = 0; t < nt; ++t) {
    EXPECT_NEAR(ratio[t], 8.0, 1e-12);
    EXPECT_NEAR(strain[t], 1.5 * std::sqrt(3.0), 1e-12);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(fibre[3 * t + c], 2.0 * a0[c], 1e-12);
    EXPECT_EQ(material[t], 2.0);
  }
  ASSERT_EQ(displacement.size(), size_t(x.size()));
  for (int i = 0; i < x.size(); ++i) EXPECT_DOUBLE_EQ(displacement[i], m.rest.data()[i]);
  EXPECT_EQ(velocity.size(), size_t(x.size()));
  EXPECT_TRUE(vtuArray(text, "force").empty());
  const Mesh deformed = readVtu(path);
  EXPECT_TRUE(deformed.rest == 2.0 * m.rest);

  // Rigid rotation: det F = 1, E = 0, F a0 = R a0.
  const Eigen::Matrix3d R = Eigen::AngleAxisd(1.1, Eigen::Vector3d(1, 2, 3).normalized()).toRotationMatrix();
  Eigen::Matrix3Xd rotated = R * m.rest;
  Eigen::VectorXd xr = Eigen::Map<const Eigen::VectorXd>(rotated.data(), rotated.size());
  fields = VtuFields();
  fields.positions = &xr;
  writeVtu(path, m, fields);
  text = readText(path);
  const auto ratioR = vtuArray(text, "volume_ratio"), strainR = vtuArray(text, "green_strain_norm"),
             fibreR = vtuArray(text, "fibre_direction");
  const Eigen::Vector3d Ra0 = R * a0;
  for (int t = 0; t < nt; ++t) {
    EXPECT_NEAR(ratioR[t], 1.0, 1e-12);
    EXPECT_NEAR(strainR[t], 0.0, 1e-12);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(fibreR[3 * t + c], Ra0[c], 1e-12);
  }
  Eigen::VectorXd wrongSize(5);
  fields.force = &wrongSize;
  EXPECT_THROW(writeVtu(path, m, fields), std::invalid_argument);
}

TEST(MeshIo, VtuWriterHandlesHexCellFields) {
  Mesh m = kuhnBox(1, true);
  Eigen::Matrix3d A;
  A << 1.2, 0.1, 0, 0, 0.9, 0.2, 0.05, 0, 1.1;  // affine map: the same F in every cell
  Eigen::Matrix3Xd moved = A * m.rest;
  Eigen::VectorXd x = Eigen::Map<const Eigen::VectorXd>(moved.data(), moved.size());
  VtuFields fields;
  fields.positions = &x;
  const std::string path = meshIoTempDir() + "/hexfields.vtu";
  writeVtu(path, m, fields);
  const auto ratio = vtuArray(readText(path), "volume_ratio");
  ASSERT_EQ(ratio.size(), m.tets.size() + 1);
  for (double r : ratio) EXPECT_NEAR(r, A.determinant(), 1e-12);
}

TEST(MeshQuality, AspectRatioAndNormalisedVolumeOfKnownTets) {
  Eigen::Matrix3Xd x(3, 4);
  // Regular tet: alternate corners of a cube.
  x << 1, 1, -1, -1,
       1, -1, 1, -1,
       1, -1, -1, 1;
  Tet t{0, 1, 2, 3};
  if (tetVolume(x, t) < 0) std::swap(t[1], t[2]);
  EXPECT_NEAR(tetAspectRatio(x, t), 1.0, 1e-14);
  EXPECT_NEAR(tetNormalisedVolume(x, t), 1.0, 1e-14);
  // Corner tet of the unit cube: inradius 1/(3 + sqrt 3), longest edge sqrt 2.
  x << 0, 1, 0, 0,
       0, 0, 1, 0,
       0, 0, 0, 1;
  const double r = 1.0 / (3.0 + std::sqrt(3.0));
  EXPECT_NEAR(tetAspectRatio(x, {0, 1, 2, 3}), std::sqrt(2.0) / (2.0 * std::sqrt(6.0) * r), 1e-14);
  EXPECT_NEAR(tetNormalisedVolume(x, {0, 1, 2, 3}), 6.0 * std::sqrt(2.0) / 6.0 / (2.0 * std::sqrt(2.0)), 1e-14);
  // Flat tet.
  x(2, 3) = 0.0;
  x(0, 3) = 0.4;
  x(1, 3) = 0.3;
  EXPECT_TRUE(std::isinf(tetAspectRatio(x, {0, 1, 2, 3})));
  EXPECT_EQ(tetNormalisedVolume(x, {0, 1, 2, 3}), 0.0);
}

TEST(MeshQuality, HexVolumeIsExactForAffineAndTrilinearMaps) {
  Eigen::Matrix3Xd x(3, 8);
  x << 0, 1, 1, 0, 0, 1, 1, 0,
       0, 0, 1, 1, 0, 0, 1, 1,
       0, 0, 0, 0, 1, 1, 1, 1;
  const Hex h{0, 1, 2, 3, 4, 5, 6, 7};
  Eigen::Matrix3d A;
  A << 2, 0.3, 0.1, 0.2, 3, 0, 0, 0.4, 4;
  EXPECT_NEAR(hexVolume(A * x, h), A.determinant(), 1e-12);
  // Raise one top corner: the volume of a trilinear hex with top z = 1 + s*xi*eta (corner
  // (1,1,1) moved to z = 1 + s) is 1 + s/4 (integral of the height over the unit square).
  Eigen::Matrix3Xd y = x;
  y(2, 6) += 0.8;
  EXPECT_NEAR(hexVolume(y, h), 1.0 + 0.8 / 4.0, 1e-14);
}

TEST(MeshQuality, ReportCountsInvertedDegenerateDuplicateAndUnused) {
  Mesh m = kuhnBox(2);
  const int n = m.numNodes();
  const double tol = 1e-9 * (boundingBox(m.rest).max - boundingBox(m.rest).min).norm();
  // Three copies within the tolerance, one just outside, and a flat tet among them.
  m.rest.conservativeResize(3, n + 4);
  m.rest.col(n) = m.rest.col(0);
  m.rest.col(n + 1) = m.rest.col(5) + Eigen::Vector3d(0.3 * tol, 0, 0);
  m.rest.col(n + 2) = m.rest.col(7) + Eigen::Vector3d(0, 0, -0.5 * tol);
  m.rest.col(n + 3) = m.rest.col(9) + Eigen::Vector3d(0, 3 * tol, 0);
  std::swap(m.tets[0][1], m.tets[0][2]);
  std::swap(m.tets[3][0], m.tets[3][3]);
  m.fillDefaults();
  MeshQuality q = meshQuality(m);
  EXPECT_EQ(q.nodes, n + 4);
  EXPECT_EQ(q.tets, 48);
  EXPECT_EQ(q.inverted, 2);
  EXPECT_EQ(q.degenerate, 0);
  EXPECT_EQ(q.duplicateNodes, 3);
  EXPECT_EQ(q.unusedNodes, 4);
  EXPECT_GE(q.aspectMin, 1.0);
  EXPECT_LE(q.aspectMin, q.aspectMedian);
  EXPECT_LE(q.aspectMedian, q.aspectMax);

  EXPECT_EQ(repairInverted(m), 2);
  q = meshQuality(m);
  EXPECT_EQ(q.inverted, 0);
  EXPECT_NEAR(q.volumeTotal, totalTetVolume(kuhnBox(2)), 1e-12);
  EXPECT_GT(q.volumeMin, 0.0);

  // A sliver: four nearly coplanar nodes.
  m.rest.col(n) = Eigen::Vector3d(10, 0, 0);
  m.rest.col(n + 1) = Eigen::Vector3d(11, 0, 0);
  m.rest.col(n + 2) = Eigen::Vector3d(10, 1, 0);
  m.rest.col(n + 3) = Eigen::Vector3d(10.5, 0.5, 1e-5);
  m.tets.push_back({n, n + 1, n + 2, n + 3});
  m.fillDefaults();
  q = meshQuality(m);
  EXPECT_EQ(q.degenerate, 1);
  EXPECT_EQ(q.unusedNodes, 0);
  EXPECT_EQ(q.duplicateNodes, 0);
  EXPECT_TRUE(std::isinf(q.aspectMax) || q.aspectMax > 1e4);
}

TEST(MeshQuality, LiverReportAndFormatting) {
  const Mesh m = readMesh(meshPath("liver.msh"));
  const MeshQuality q = meshQuality(m);
  EXPECT_EQ(q.nodes, 181);
  EXPECT_EQ(q.tets, 596);
  EXPECT_EQ(q.surfaceTriangles, static_cast<int>(m.surface.size()));
  EXPECT_EQ(q.inverted, 0);
  EXPECT_NEAR(q.volumeTotal, checkClosedSurface(m.rest, m.surface), 1e-10 * q.volumeTotal);
  const std::string text = formatQuality(q);
  EXPECT_NE(text.find("nodes 181, tets 596"), std::string::npos) << text;
  EXPECT_NE(text.find("aspect ratio"), std::string::npos);
  EXPECT_EQ(std::count(text.begin(), text.end(), '\n'), 5);
}

}  // namespace
}  // namespace tt
