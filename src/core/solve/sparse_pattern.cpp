#include "tissue_trainer/core/solve/sparse_pattern.h"

#include <algorithm>

namespace tt {
namespace {

// Greedy colouring in tet order: each tet takes the smallest colour none of the tets at its
// nodes has yet. Returns the colour of every tet.
std::vector<int> colourTets(int numNodes, const std::vector<Tet>& tets, int& colours) {
  std::vector<std::vector<int>> tetsAt(numNodes);
  for (size_t e = 0; e < tets.size(); ++e)
    for (int a : tets[e]) tetsAt[a].push_back(static_cast<int>(e));
  std::vector<int> colour(tets.size(), -1);
  std::vector<int> usedBy;  // usedBy[c] == e: colour c is taken by a neighbour of tet e
  colours = 0;
  for (size_t e = 0; e < tets.size(); ++e) {
    for (int a : tets[e])
      for (int other : tetsAt[a])
        if (colour[other] >= 0) usedBy[colour[other]] = static_cast<int>(e);
    int c = 0;
    while (c < colours && usedBy[c] == static_cast<int>(e)) ++c;
    if (c == colours) {
      ++colours;
      usedBy.push_back(-1);
    }
    colour[e] = c;
  }
  return colour;
}

}  // namespace

SparsePattern::SparsePattern(int numNodes, const std::vector<Tet>& tets,
                             const std::vector<std::array<int, 2>>& extraPairs)
    : numNodes_(numNodes) {
  std::vector<std::vector<int>> neighbours(numNodes);
  auto link = [&](int a, int b) {
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  };
  for (int a = 0; a < numNodes; ++a) neighbours[a].push_back(a);
  for (const Tet& t : tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) link(t[i], t[j]);
  for (const auto& p : extraPairs) link(p[0], p[1]);

  std::vector<Eigen::Triplet<double>> entries;
  size_t count = 0;
  for (auto& n : neighbours) {
    std::sort(n.begin(), n.end());
    n.erase(std::unique(n.begin(), n.end()), n.end());
    count += 9 * n.size();
  }
  entries.reserve(count);
  for (int a = 0; a < numNodes; ++a)
    for (int b : neighbours[a])
      for (int i = 0; i < 3; ++i)
        for (int j = 0; j < 3; ++j) entries.emplace_back(3 * a + i, 3 * b + j, 0.0);
  pattern_.resize(3 * numNodes, 3 * numNodes);
  pattern_.setFromTriplets(entries.begin(), entries.end());
  pattern_.makeCompressed();

  tetOffsets_.resize(tets.size());
  const int* outer = pattern_.outerIndexPtr();
  const int* inner = pattern_.innerIndexPtr();
  for (size_t e = 0; e < tets.size(); ++e)
    for (int la = 0; la < 4; ++la)
      for (int lb = 0; lb < 4; ++lb)
        for (int i = 0; i < 3; ++i) {
          const int row = 3 * tets[e][la] + i;
          const int* pos = std::lower_bound(inner + outer[row], inner + outer[row + 1],
                                            3 * tets[e][lb]);
          tetOffsets_[e][(la * 4 + lb) * 3 + i] = static_cast<int>(pos - inner);
        }

  int colours = 0;
  const std::vector<int> colour = colourTets(numNodes, tets, colours);
  colourStarts_.assign(colours + 1, 0);
  for (int c : colour) ++colourStarts_[c + 1];
  for (int c = 0; c < colours; ++c) colourStarts_[c + 1] += colourStarts_[c];
  tetsByColour_.resize(tets.size());
  std::vector<int> next(colourStarts_.begin(), colourStarts_.end() - 1);
  for (size_t e = 0; e < tets.size(); ++e) tetsByColour_[next[colour[e]]++] = static_cast<int>(e);
}

SparseMatrix SparsePattern::zeroMatrix() const {
  SparseMatrix K = pattern_;
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  return K;
}

void SparsePattern::addTetBlock(SparseMatrix& K, int tet, const Matrix12d& Ke) const {
  double* values = K.valuePtr();
  const std::array<int, 48>& offsets = tetOffsets_[tet];
  for (int la = 0; la < 4; ++la)
    for (int lb = 0; lb < 4; ++lb)
      for (int i = 0; i < 3; ++i) {
        double* row = values + offsets[(la * 4 + lb) * 3 + i];
        for (int j = 0; j < 3; ++j) row[j] += Ke(3 * la + i, 3 * lb + j);
      }
}

void SparsePattern::addNodeBlock(SparseMatrix& K, int a, int b,
                                 const Eigen::Matrix3d& block) const {
  const int* outer = K.outerIndexPtr();
  const int* inner = K.innerIndexPtr();
  double* values = K.valuePtr();
  for (int i = 0; i < 3; ++i) {
    const int row = 3 * a + i;
    const int* pos = std::lower_bound(inner + outer[row], inner + outer[row + 1], 3 * b);
    double* entry = values + (pos - inner);
    for (int j = 0; j < 3; ++j) entry[j] += block(i, j);
  }
}

std::vector<std::array<int, 2>> hexNodePairs(const std::vector<Hex>& hexes) {
  std::vector<std::array<int, 2>> pairs;
  pairs.reserve(hexes.size() * 28);
  for (const Hex& h : hexes)
    for (int a = 0; a < 8; ++a)
      for (int b = a + 1; b < 8; ++b) pairs.push_back({std::min(h[a], h[b]), std::max(h[a], h[b])});
  return pairs;
}

SparsePattern meshPattern(const Mesh& mesh, std::vector<std::array<int, 2>> extraPairs) {
  const std::vector<std::array<int, 2>> hexPairs = hexNodePairs(mesh.hexes);
  extraPairs.insert(extraPairs.end(), hexPairs.begin(), hexPairs.end());
  return SparsePattern(mesh.numNodes(), mesh.tets, extraPairs);
}

}  // namespace tt
