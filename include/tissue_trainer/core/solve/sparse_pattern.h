#pragma once
// A sparse 3n x 3n matrix with a fixed pattern: one 3x3 block for every pair of nodes that
// share an element. Element stiffness blocks (tets and hexes) are added through precomputed
// value offsets, so assembly does no search and no allocation.
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <cstdint>
#include <memory>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

using SparseMatrix = Eigen::SparseMatrix<double, Eigen::RowMajor, int>;
using Matrix12d = Eigen::Matrix<double, 12, 12>;
using Matrix24d = Eigen::Matrix<double, 24, 24>;

// Which local nodes of an element a part of the threaded assembly writes the rows of: bit la
// is set for local node la (kAllTetRows: a tet's four, kAllHexRows: a hex's eight, as on one
// thread).
using TetRows = std::uint8_t;
using HexRows = std::uint8_t;
constexpr TetRows kAllTetRows = 0xF;
constexpr HexRows kAllHexRows = 0xFF;

// The threaded assembly's split of the rows ("owner computes"): every node belongs to one
// part; a part visits, in increasing index order, the tets (then the hexes) with a node of its
// own and writes only its own nodes' rows. An element with nodes of two parts is evaluated by
// both.
struct RowOwnership {
  std::vector<std::vector<int>> tets;         // per part: the tets it visits
  std::vector<std::vector<TetRows>> rows;     // per part, per tet it visits: the rows it writes
  std::vector<std::vector<int>> hexes;        // per part: the hexes it visits
  std::vector<std::vector<HexRows>> hexRows;  // per part, per hex it visits: the rows it writes
};

class SparsePattern {
 public:
  SparsePattern();
  // Pattern of all node pairs sharing a tet or a hex, plus extra node pairs (e.g. springs).
  SparsePattern(int numNodes, const std::vector<Tet>& tets,
                const std::vector<std::array<int, 2>>& extraPairs = {},
                const std::vector<Hex>& hexes = {});

  // A zero matrix with this pattern (compressed).
  SparseMatrix zeroMatrix() const;

  // K(3a+i, 3b+j) += Ke(3la+i, 3lb+j) for the local nodes la, lb of tet t (la in `rows`).
  void addTetBlock(SparseMatrix& K, int tet, const Matrix12d& Ke,
                   TetRows rows = kAllTetRows) const;
  // K(3a+i, 3b+j) += scale * Ke(3la+i, 3lb+j) for the local nodes la, lb of hex h (la in
  // `rows`).
  void addHexBlock(SparseMatrix& K, int hex, const Matrix24d& Ke, double scale,
                   HexRows rows = kAllHexRows) const;
  // K(3a+i, 3b+j) += block(i, j); a binary search per row (for pairs of nodes of no element:
  // springs, contacts, cavity walls).
  void addNodeBlock(SparseMatrix& K, int a, int b, const Eigen::Matrix3d& block) const;

  int numNodes() const { return numNodes_; }
  Eigen::Index nonZeros() const { return pattern_.nonZeros(); }

  // Offsets of tet t's entries, as used by addTetBlock: entry (la * 4 + lb) * 3 + i is the
  // value offset of K(3a+i, 3b) (the three entries j = 0..2 follow it).
  const std::array<int, 48>& tetOffsets(int tet) const { return tetOffsets_[tet]; }

  int numTets() const { return static_cast<int>(tets_.size()); }
  int numHexes() const { return static_cast<int>(hexes_.size()); }

  // The rows split into `parts` bands of nodes: consecutive runs of a breadth-first order of
  // the nodes from a peripheral one (level sets of the mesh graph, so a band borders only the
  // bands before and after it, across about one layer of tets), balanced by the tets at the
  // nodes. Every entry of K then receives its terms in the same order as on one thread.
  // Computed on first use for each part count and kept (safe to call from several threads).
  const RowOwnership& rowOwnership(int parts) const;

 private:
  struct OwnershipCache;
  int numNodes_ = 0;
  SparseMatrix pattern_;
  std::vector<Tet> tets_;
  std::vector<Hex> hexes_;
  // Per tet, per (la, lb) pair, per row i: the offset of entry (3a+i, 3b) in the value array;
  // the same per hex.
  std::vector<std::array<int, 48>> tetOffsets_;
  std::vector<std::array<int, 192>> hexOffsets_;
  std::vector<int> breadthFirstOrder_;           // every node once, component by component
  std::shared_ptr<OwnershipCache> ownership_;   // shared by copies (same topology)
};

// The pattern of a mesh: its tets and hexes (with offsets) and `extraPairs`.
SparsePattern meshPattern(const Mesh& mesh, std::vector<std::array<int, 2>> extraPairs = {});

}  // namespace tt
