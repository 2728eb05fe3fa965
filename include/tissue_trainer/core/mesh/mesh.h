#pragma once
// The tetrahedral (optionally hexahedral) mesh: rest geometry, elements, boundary surface,
// per-element fibre frame and material id, and per-node tags.
#include <Eigen/Core>
#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace tt {

using Tet = std::array<int, 4>;
using Hex = std::array<int, 8>;
using Triangle = std::array<int, 3>;

// Per-node tags (bit flags): fixed per axis as in "Adamss: Advanced Anisotropic Mass-Spring
// System", Sec. 2.6, and controlled nodes whose position follows a prescribed path.
enum NodeTag : std::uint8_t {
  kFixedX = 1u << 0,
  kFixedY = 1u << 1,
  kFixedZ = 1u << 2,
  kFixedAll = kFixedX | kFixedY | kFixedZ,
  kControlled = 1u << 3,
};

// The numbers the nodes and tets had in the mesh's file when the loader reordered them for
// locality (mesh_order.h); empty vectors: the mesh is in its file's order. Scene keys, files
// beside the mesh and messages speak the file's numbers; everything else the mesh's.
struct FileNumbering {
  std::vector<int> fileNode, meshNode;  // fileNode[n]: file number of node n; meshNode inverse
  std::vector<int> fileTet, meshTet;    // the same for tets (hexes keep their file order)

  int nodeToFile(int n) const { return fileNode.empty() ? n : fileNode[n]; }
  int nodeFromFile(int n) const { return meshNode.empty() ? n : meshNode[n]; }
  int tetToFile(int t) const { return fileTet.empty() ? t : fileTet[t]; }
  int tetFromFile(int t) const { return meshTet.empty() ? t : meshTet[t]; }
};

struct Mesh {
  Eigen::Matrix3Xd rest;                // rest positions, one column per node (m)
  std::vector<Tet> tets;                // positively oriented: det[P1-P0, P2-P0, P3-P0] > 0
  std::vector<Hex> hexes;               // optional, VTK/Gmsh node order
  std::vector<Triangle> surface;        // boundary triangles, outward normals (right-hand)
  // Per tet: the fibre frame (orthonormal columns: fibre a0, sheet, sheet-normal) and the
  // material id (index into the scene's table); the same per hex.
  std::vector<Eigen::Matrix3d> fibreFrame;
  std::vector<int> material;
  std::vector<Eigen::Matrix3d> hexFibreFrame;
  std::vector<int> hexMaterial;
  std::vector<std::uint8_t> nodeTags;   // per node, NodeTag bits
  FileNumbering numbering;

  int numNodes() const { return static_cast<int>(rest.cols()); }
  int numTets() const { return static_cast<int>(tets.size()); }
  int numHexes() const { return static_cast<int>(hexes.size()); }

  // Gives every tet and hex the identity frame and material 0, every node no tag, when the
  // corresponding arrays are empty. Readers and generators call it last.
  void fillDefaults();
};

// Signed volume det[P1-P0, P2-P0, P3-P0] / 6 of tet t at positions x (3 x n). The position
// helpers of mesh/ take Eigen::Ref, so that a Map of a state vector (3n) binds without a copy
// (a const Matrix3Xd& would copy every node for every call).
double tetVolume(const Eigen::Ref<const Eigen::Matrix3Xd>& x, const Tet& t);

// Boundary triangles (faces that belong to exactly one tet), oriented outward.
std::vector<Triangle> extractSurface(const Mesh& mesh);

// Axis-aligned bounding box of the rest positions.
struct Box {
  Eigen::Vector3d min, max;
};
Box boundingBox(const Eigen::Ref<const Eigen::Matrix3Xd>& x);

}  // namespace tt
