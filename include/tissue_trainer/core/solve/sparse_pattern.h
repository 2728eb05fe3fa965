#pragma once
// A sparse 3n x 3n matrix with a fixed pattern: one 3x3 block for every pair of nodes that
// share an element. Element stiffness blocks are added through precomputed value offsets,
// so assembly does no search and no allocation.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;

class SparsePattern {
 public:
  SparsePattern() = default;
  // Pattern of all node pairs sharing a tet, plus extra node pairs (e.g. springs).
  SparsePattern(int numNodes, const std::vector<Tet>& tets,
                const std::vector<std::array<int, 2>>& extraPairs = {});

  // A zero matrix with this pattern (compressed).
  SparseMatrix zeroMatrix() const;

  // K(3a+i, 3b+j) += Ke(3la+i, 3lb+j) for the local nodes la, lb of tet t.
  void addTetBlock(SparseMatrix& K, int tet, const Matrix12d& Ke) const;
  // K(3a+i, 3b+j) += block(i, j); a binary search per row (for non-tet elements).
  void addNodeBlock(SparseMatrix& K, int a, int b, const Eigen::Matrix3d& block) const;

  int numNodes() const { return numNodes_; }

  // Offsets of tet t's entries, as used by addTetBlock: entry (la * 4 + lb) * 3 + i is the
  // value offset of K(3a+i, 3b) (the three entries j = 0..2 follow it).
  const std::array<int, 48>& tetOffsets(int tet) const { return tetOffsets_[tet]; }

  // A greedy colouring of the tets: no two tets of one colour share a node, so the tets of a
  // colour can be assembled concurrently. The tets of colour c are
  // tetsByColour()[colourStarts()[c] .. colourStarts()[c + 1]), in increasing index order.
  const std::vector<int>& tetsByColour() const { return tetsByColour_; }
  const std::vector<int>& colourStarts() const { return colourStarts_; }

 private:
  int numNodes_ = 0;
  SparseMatrix pattern_;
  // Per tet, per (la, lb) pair, per row i: the offset of entry (3a+i, 3b) in the value array.
  std::vector<std::array<int, 48>> tetOffsets_;
  std::vector<int> tetsByColour_, colourStarts_;
};

// The node pairs (a < b) of the hexes, for a pattern that covers them as extra pairs.
std::vector<std::array<int, 2>> hexNodePairs(const std::vector<Hex>& hexes);

// The pattern of a mesh: its tets (with offsets and colours), its hexes and `extraPairs`.
SparsePattern meshPattern(const Mesh& mesh, std::vector<std::array<int, 2>> extraPairs = {});

}  // namespace tt
