#pragma once
// Mesh readers and writers. Every reader throws tt::InputError with "FILE:LINE: what was
// expected" on bad input, never allocates from an unchecked declared count, and reports
// element types it ignored (lower-dimensional elements of mixed meshes) in `notes`.
#include <string>
#include <vector>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

struct ReadNotes {
  std::vector<std::string> lines;  // e.g. "ignored 860 triangles (type 2), 71 lines (type 1)"
};

// Picks the reader from the extension: .msh (Gmsh v1, v2 or v4 ASCII, detected from the
// content), .node/.ele (TetGen; either name), .vtk (legacy ASCII unstructured grid),
// .vtu (VTK XML, ASCII). Inverted rest tets are reordered to positive orientation (counted in
// notes). The surface is extracted and default frames/materials/tags filled.
Mesh readMesh(const std::string& path, ReadNotes* notes = nullptr);

Mesh readGmsh(const std::string& path, ReadNotes* notes = nullptr);
Mesh readTetgen(const std::string& path, ReadNotes* notes = nullptr);  // .node or .ele path
Mesh readVtkLegacy(const std::string& path, ReadNotes* notes = nullptr);
Mesh readVtu(const std::string& path, ReadNotes* notes = nullptr);

// A triangle surface (OBJ): vertices and triangles (polygons are fanned).
struct SurfaceMesh {
  Eigen::Matrix3Xd vertices;
  std::vector<Triangle> triangles;
};
SurfaceMesh readObj(const std::string& path);
void writeObj(const std::string& path, const SurfaceMesh& surface);

// Optional per-node and per-cell fields for the VTU writer; empty ones are not written.
struct VtuFields {
  const Eigen::VectorXd* positions = nullptr;      // 3n deformed positions (else rest)
  const Eigen::VectorXd* velocity = nullptr;       // 3n
  const Eigen::VectorXd* acceleration = nullptr;   // 3n
  bool pointPositions = false;                     // the positions also as point data
  const Eigen::VectorXd* force = nullptr;          // 3n
  bool cellVolumeRatio = true;                     // det F per tet
  bool cellStrain = true;                          // Frobenius norm of Green strain E
  bool cellFibre = true;                           // deformed fibre direction F a0
  bool cellMaterial = true;
};
// Writes displacement (positions - rest) along with the listed fields.
void writeVtu(const std::string& path, const Mesh& mesh, const VtuFields& fields = {});
void writeGmsh2(const std::string& path, const Mesh& mesh);
// Writes BASE.node and BASE.ele.
void writeTetgen(const std::string& basePath, const Mesh& mesh);
// Gmsh v4.1 ASCII (one volume entity) and legacy VTK ASCII unstructured grid.
void writeGmsh4(const std::string& path, const Mesh& mesh);
void writeVtkLegacy(const std::string& path, const Mesh& mesh);
// Picks the writer from the extension: .vtu, .msh (v2), .vtk, .node/.ele (TetGen).
void writeMesh(const std::string& path, const Mesh& mesh);

// Writers throw std::runtime_error ("PATH: cannot open for writing") when the file cannot be
// written and std::invalid_argument when the format cannot hold the mesh (hexes in TetGen)
// or a field has the wrong size. Numbers are written in shortest round-trip form, so a
// mesh read back is bit-identical.

}  // namespace tt
