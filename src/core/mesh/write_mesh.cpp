// Mesh writers (VTU for ParaView, Gmsh v2 and v4.1 ASCII, TetGen, legacy VTK) and the
// extension-based readMesh / writeMesh.
#include <Eigen/Dense>
#include <algorithm>
#include <cctype>
#include <cmath>

#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/mesh/tet_geometry.h"
#include "write_support.h"

namespace tt {

namespace {

using meshio::TextWriter;

std::string lowerExtension(const std::string& path) {
  const std::size_t dot = path.find_last_of('.');
  const std::size_t slash = path.find_last_of('/');
  if (dot == std::string::npos || (slash != std::string::npos && dot < slash)) return "";
  std::string ext = path.substr(dot);
  std::transform(ext.begin(), ext.end(), ext.begin(), [](unsigned char c) { return std::tolower(c); });
  return ext;
}

void writeNodeXyz(TextWriter& out, const Eigen::Matrix3Xd& x, int i) {
  out << x(0, i) << ' ' << x(1, i) << ' ' << x(2, i);
}

// Deformation gradient at the centre of a trilinear hex: F = (sum x_i dN_i^T) J^-1.
Eigen::Matrix3d hexCentreGradient(const Eigen::Matrix3Xd& rest, const Eigen::Matrix3Xd& x, const Hex& h) {
  static const double kCorner[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                       {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};
  Eigen::Matrix3d J = Eigen::Matrix3d::Zero(), G = Eigen::Matrix3d::Zero();
  for (int i = 0; i < 8; ++i) {
    const Eigen::Vector3d dN(kCorner[i][0] / 8.0, kCorner[i][1] / 8.0, kCorner[i][2] / 8.0);
    J += rest.col(h[i]) * dN.transpose();
    G += x.col(h[i]) * dN.transpose();
  }
  return G * J.inverse();
}

// Non-finite values (from a degenerate rest element) would stop VTK's ASCII parser.
double finiteOrZero(double v) { return std::isfinite(v) ? v : 0.0; }

struct CellKinematics {
  std::vector<double> volumeRatio, strainNorm;
  std::vector<Eigen::Vector3d> fibre;
};

CellKinematics cellKinematics(const Mesh& mesh, const Eigen::Matrix3Xd& x) {
  CellKinematics k;
  const Eigen::VectorXd xv = Eigen::Map<const Eigen::VectorXd>(x.data(), x.size());
  auto add = [&](const Eigen::Matrix3d& F, const Eigen::Vector3d& a0) {
    const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
    k.volumeRatio.push_back(finiteOrZero(F.determinant()));
    k.strainNorm.push_back(finiteOrZero(E.norm()));
    Eigen::Vector3d f = F * a0;
    for (int c = 0; c < 3; ++c) f[c] = finiteOrZero(f[c]);
    k.fibre.push_back(f);
  };
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const Eigen::Vector3d a0 = t < mesh.fibreFrame.size() ? Eigen::Vector3d(mesh.fibreFrame[t].col(0))
                                                         : Eigen::Vector3d::UnitX();
    add(deformationGradient(xv, mesh.tets[t], tetRest(mesh.rest, mesh.tets[t])), a0);
  }
  for (const Hex& h : mesh.hexes) add(hexCentreGradient(mesh.rest, x, h), Eigen::Vector3d::UnitX());
  return k;
}

Eigen::Matrix3Xd fieldMatrix(const Eigen::VectorXd* v, const Mesh& mesh, const char* name) {
  if (v->size() != 3 * mesh.rest.cols())
    throw std::invalid_argument(std::string("writeVtu: field ") + name + " has " + std::to_string(v->size()) +
                                " values, expected 3 x " + std::to_string(mesh.rest.cols()));
  return Eigen::Map<const Eigen::Matrix3Xd>(v->data(), 3, mesh.rest.cols());
}

void vectorArray(TextWriter& out, const char* name, const Eigen::Matrix3Xd& values) {
  out << "        <DataArray type=\"Float64\" Name=\"" << name << "\" NumberOfComponents=\"3\" format=\"ascii\">\n";
  for (Eigen::Index i = 0; i < values.cols(); ++i) {
    out << "          ";
    writeNodeXyz(out, values, static_cast<int>(i));
    out << '\n';
  }
  out << "        </DataArray>\n";
}

void scalarArray(TextWriter& out, const char* name, const std::vector<double>& values) {
  out << "        <DataArray type=\"Float64\" Name=\"" << name << "\" format=\"ascii\">\n";
  for (double v : values) out << "          " << v << '\n';
  out << "        </DataArray>\n";
}

}  // namespace

void writeVtu(const std::string& path, const Mesh& mesh, const VtuFields& fields) {
  const Eigen::Matrix3Xd x = fields.positions ? fieldMatrix(fields.positions, mesh, "positions") : mesh.rest;
  const int numCells = static_cast<int>(mesh.tets.size() + mesh.hexes.size());
  TextWriter out(path);
  out << "<?xml version=\"1.0\"?>\n"
      << "<VTKFile type=\"UnstructuredGrid\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
      << "  <UnstructuredGrid>\n"
      << "    <Piece NumberOfPoints=\"" << mesh.numNodes() << "\" NumberOfCells=\"" << numCells << "\">\n";

  out << "      <PointData Vectors=\"displacement\">\n";
  vectorArray(out, "displacement", x - mesh.rest);
  if (fields.pointPositions) vectorArray(out, "position", x);
  if (fields.velocity) vectorArray(out, "velocity", fieldMatrix(fields.velocity, mesh, "velocity"));
  if (fields.acceleration)
    vectorArray(out, "acceleration", fieldMatrix(fields.acceleration, mesh, "acceleration"));
  if (fields.force) vectorArray(out, "force", fieldMatrix(fields.force, mesh, "force"));
  out << "      </PointData>\n";

  out << "      <CellData>\n";
  if (fields.cellVolumeRatio || fields.cellStrain || fields.cellFibre) {
    const CellKinematics k = cellKinematics(mesh, x);
    if (fields.cellVolumeRatio) scalarArray(out, "volume_ratio", k.volumeRatio);
    if (fields.cellStrain) scalarArray(out, "green_strain_norm", k.strainNorm);
    if (fields.cellFibre) {
      Eigen::Matrix3Xd fibre(3, numCells);
      for (int c = 0; c < numCells; ++c) fibre.col(c) = k.fibre[c];
      vectorArray(out, "fibre_direction", fibre);
    }
  }
  if (fields.cellMaterial) {
    out << "        <DataArray type=\"Int32\" Name=\"material\" format=\"ascii\">\n";
    for (std::size_t t = 0; t < mesh.tets.size(); ++t)
      out << "          " << (t < mesh.material.size() ? mesh.material[t] : 0) << '\n';
    for (std::size_t h = 0; h < mesh.hexes.size(); ++h) out << "          0\n";
    out << "        </DataArray>\n";
  }
  out << "      </CellData>\n";

  out << "      <Points>\n";
  vectorArray(out, "positions", x);
  out << "      </Points>\n      <Cells>\n"
      << "        <DataArray type=\"Int64\" Name=\"connectivity\" format=\"ascii\">\n";
  for (const Tet& t : mesh.tets) out << "          " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
  for (const Hex& h : mesh.hexes) {
    out << "         ";
    for (int v : h) out << ' ' << v;
    out << '\n';
  }
  out << "        </DataArray>\n"
      << "        <DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
  long long offset = 0;
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) out << "          " << (offset += 4) << '\n';
  for (std::size_t h = 0; h < mesh.hexes.size(); ++h) out << "          " << (offset += 8) << '\n';
  out << "        </DataArray>\n"
      << "        <DataArray type=\"UInt8\" Name=\"types\" format=\"ascii\">\n";
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) out << "          10\n";
  for (std::size_t h = 0; h < mesh.hexes.size(); ++h) out << "          12\n";
  out << "        </DataArray>\n      </Cells>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
  out.close();
}

void writeGmsh2(const std::string& path, const Mesh& mesh) {
  TextWriter out(path);
  out << "$MeshFormat\n2.2 0 8\n$EndMeshFormat\n$Nodes\n" << mesh.numNodes() << '\n';
  for (int i = 0; i < mesh.numNodes(); ++i) {
    out << (i + 1) << ' ';
    writeNodeXyz(out, mesh.rest, i);
    out << '\n';
  }
  out << "$EndNodes\n$Elements\n" << static_cast<long long>(mesh.tets.size() + mesh.hexes.size()) << '\n';
  long long id = 0;
  // Tags: physical group = material id + 1 (Gmsh groups are positive), elementary entity 1.
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) {
    const int physical = (t < mesh.material.size() ? mesh.material[t] : 0) + 1;
    out << ++id << " 4 2 " << physical << " 1";
    for (int v : mesh.tets[t]) out << ' ' << (v + 1);
    out << '\n';
  }
  for (const Hex& h : mesh.hexes) {
    out << ++id << " 5 2 1 1";
    for (int v : h) out << ' ' << (v + 1);
    out << '\n';
  }
  out << "$EndElements\n";
  out.close();
}

void writeGmsh4(const std::string& path, const Mesh& mesh) {
  const int n = mesh.numNodes();
  const Box box = boundingBox(mesh.rest);
  TextWriter out(path);
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  // One volume entity (tag 1) holding every node and element.
  out << "$Entities\n0 0 0 1\n1 " << box.min.x() << ' ' << box.min.y() << ' ' << box.min.z() << ' '
      << box.max.x() << ' ' << box.max.y() << ' ' << box.max.z() << " 0 0\n$EndEntities\n";
  out << "$Nodes\n1 " << n << " 1 " << n << "\n3 1 0 " << n << '\n';
  for (int i = 0; i < n; ++i) out << (i + 1) << '\n';
  for (int i = 0; i < n; ++i) {
    writeNodeXyz(out, mesh.rest, i);
    out << '\n';
  }
  const long long total = static_cast<long long>(mesh.tets.size() + mesh.hexes.size());
  const int blocks = (mesh.tets.empty() ? 0 : 1) + (mesh.hexes.empty() ? 0 : 1);
  out << "$EndNodes\n$Elements\n" << blocks << ' ' << total << " 1 " << total << '\n';
  long long id = 0;
  if (!mesh.tets.empty()) {
    out << "3 1 4 " << static_cast<long long>(mesh.tets.size()) << '\n';
    for (const Tet& t : mesh.tets) {
      out << ++id;
      for (int v : t) out << ' ' << (v + 1);
      out << '\n';
    }
  }
  if (!mesh.hexes.empty()) {
    out << "3 1 5 " << static_cast<long long>(mesh.hexes.size()) << '\n';
    for (const Hex& h : mesh.hexes) {
      out << ++id;
      for (int v : h) out << ' ' << (v + 1);
      out << '\n';
    }
  }
  out << "$EndElements\n";
  out.close();
}

void writeTetgen(const std::string& basePath, const Mesh& mesh) {
  if (!mesh.hexes.empty()) throw std::invalid_argument("writeTetgen: the TetGen format cannot hold hexahedra");
  TextWriter node(basePath + ".node");
  node << "# tissue_trainer mesh: points, dimension, attributes, boundary markers\n"
       << mesh.numNodes() << " 3 0 0\n";
  for (int i = 0; i < mesh.numNodes(); ++i) {
    node << (i + 1) << ' ';
    writeNodeXyz(node, mesh.rest, i);
    node << '\n';
  }
  node.close();
  TextWriter ele(basePath + ".ele");
  ele << "# tets, nodes per tet, region attribute\n" << mesh.numTets() << " 4 0\n";
  for (int t = 0; t < mesh.numTets(); ++t) {
    ele << (t + 1);
    for (int v : mesh.tets[t]) ele << ' ' << (v + 1);
    ele << '\n';
  }
  ele.close();
}

void writeVtkLegacy(const std::string& path, const Mesh& mesh) {
  const long long cells = static_cast<long long>(mesh.tets.size() + mesh.hexes.size());
  TextWriter out(path);
  out << "# vtk DataFile Version 3.0\ntissue_trainer mesh\nASCII\nDATASET UNSTRUCTURED_GRID\n"
      << "POINTS " << mesh.numNodes() << " double\n";
  for (int i = 0; i < mesh.numNodes(); ++i) {
    writeNodeXyz(out, mesh.rest, i);
    out << '\n';
  }
  out << "CELLS " << cells << ' ' << static_cast<long long>(5 * mesh.tets.size() + 9 * mesh.hexes.size()) << '\n';
  for (const Tet& t : mesh.tets) out << "4 " << t[0] << ' ' << t[1] << ' ' << t[2] << ' ' << t[3] << '\n';
  for (const Hex& h : mesh.hexes) {
    out << '8';
    for (int v : h) out << ' ' << v;
    out << '\n';
  }
  out << "CELL_TYPES " << cells << '\n';
  for (std::size_t t = 0; t < mesh.tets.size(); ++t) out << "10\n";
  for (std::size_t h = 0; h < mesh.hexes.size(); ++h) out << "12\n";
  out.close();
}

Mesh readMesh(const std::string& path, ReadNotes* notes) {
  const std::string ext = lowerExtension(path);
  if (ext == ".msh") return readGmsh(path, notes);
  if (ext == ".node" || ext == ".ele") return readTetgen(path, notes);
  if (ext == ".vtk") return readVtkLegacy(path, notes);
  if (ext == ".vtu") return readVtu(path, notes);
  throw InputError(path, 0, "expected a mesh file ending in .msh, .node, .ele, .vtk or .vtu");
}

void writeMesh(const std::string& path, const Mesh& mesh) {
  const std::string ext = lowerExtension(path);
  if (ext == ".vtu") return writeVtu(path, mesh);
  if (ext == ".msh") return writeGmsh2(path, mesh);
  if (ext == ".vtk") return writeVtkLegacy(path, mesh);
  if (ext == ".node" || ext == ".ele") return writeTetgen(path.substr(0, path.size() - ext.size()), mesh);
  throw std::invalid_argument(path + ": expected a mesh file ending in .vtu, .msh, .vtk, .node or .ele");
}

}  // namespace tt
