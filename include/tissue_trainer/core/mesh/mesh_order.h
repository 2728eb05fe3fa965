#pragma once
// Node and tet orders for cache locality. A TetGen mesh numbers its nodes and tets without
// locality, so the element loops (force, stiffness assembly) and the sparse products jump
// through memory. Renumbering the nodes to a small bandwidth of the node graph (reverse
// Cuthill-McKee: E. Cuthill, J. McKee, "Reducing the bandwidth of sparse symmetric matrices",
// 1969; reversed as in A. George, J. Liu, "Computer Solution of Large Sparse Positive Definite
// Systems", Sec. 4.3) or along a Morton (Z-order) curve, and the tets by their smallest new
// node, lets neighbouring elements touch neighbouring memory.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

enum class NodeOrdering { kFile, kReverseCuthillMcKee, kMorton };

// A renumbering: newNode[n] is the new number of node n, newTet[t] that of tet t. Bijections
// on [0, numNodes) and [0, numTets).
struct MeshOrder {
  std::vector<int> newNode, newTet;
};

// The nodes in reverse Cuthill-McKee order of the graph whose edges join the nodes of an
// element (tet or hex); each connected part from a pseudo-peripheral node (George-Liu). Returns
// the old node numbers in their new order.
std::vector<int> reverseCuthillMcKee(const Mesh& mesh);

// The nodes sorted by the Morton key of their rest position (21 bits per axis over the
// bounding box). Returns the old node numbers in their new order.
std::vector<int> mortonNodeOrder(const Mesh& mesh);

// The node order of `ordering`, then the tets sorted by their smallest new node (ties by the
// next ones), so that a loop over the tets walks the nodes forward.
MeshOrder localityOrder(const Mesh& mesh, NodeOrdering ordering);

// Renumbers the mesh (rest, tets, hexes, surface, per-tet fibre frame and material, node tags)
// by `order` and records the file's numbers in mesh.numbering (composed with any earlier
// renumbering). The local node order inside each element is kept, so orientations stay.
void applyOrder(Mesh& mesh, const MeshOrder& order);

// A vector of 3 values per node (positions, forces) from the file's node order to the mesh's
// (mesh.numbering), and back.
Eigen::VectorXd nodeValuesFromFile(const FileNumbering& numbering, const Eigen::VectorXd& values);
Eigen::VectorXd nodeValuesToFile(const FileNumbering& numbering, const Eigen::VectorXd& values);

// Largest |a - b| over the node pairs (a, b) of an element: the half-bandwidth of the
// stiffness matrix in nodes.
int nodeBandwidth(const Mesh& mesh);

}  // namespace tt
