#include "tissue_trainer/core/solve/sparse_pattern.h"

#include <algorithm>
#include <mutex>

namespace tt {
namespace {

// The nodes in breadth-first order, component by component, each component from a peripheral
// node (the last one reached from its lowest-numbered node), as for Cuthill-McKee.
std::vector<int> breadthFirstOrder(const std::vector<std::vector<int>>& neighbours) {
  const int count = static_cast<int>(neighbours.size());
  std::vector<int> order, trial;
  order.reserve(count);
  std::vector<int> mark(count, -1);
  auto sweep = [&](int start, int stamp, std::vector<int>& out) {
    size_t head = out.size();
    out.push_back(start);
    mark[start] = stamp;
    for (; head < out.size(); ++head)
      for (int b : neighbours[out[head]])
        if (mark[b] != stamp) {
          mark[b] = stamp;
          out.push_back(b);
        }
  };
  for (int start = 0, component = 0; start < count; ++start) {
    if (mark[start] != -1) continue;
    trial.clear();
    sweep(start, 2 * component, trial);
    sweep(trial.back(), 2 * component + 1, order);
    ++component;
  }
  return order;
}

// Per element, per (la, lb) pair of its N local nodes, per row i: the offset of entry
// (3a+i, 3b) in the value array of `pattern`.
template <int N>
std::vector<std::array<int, N * N * 3>> blockOffsets(const SparseMatrix& pattern,
                                                     const std::vector<std::array<int, N>>& elements) {
  std::vector<std::array<int, N * N * 3>> offsets(elements.size());
  const int* outer = pattern.outerIndexPtr();
  const int* inner = pattern.innerIndexPtr();
  for (size_t e = 0; e < elements.size(); ++e)
    for (int la = 0; la < N; ++la)
      for (int lb = 0; lb < N; ++lb)
        for (int i = 0; i < 3; ++i) {
          const int row = 3 * elements[e][la] + i;
          const int* pos = std::lower_bound(inner + outer[row], inner + outer[row + 1],
                                            3 * elements[e][lb]);
          offsets[e][(la * N + lb) * 3 + i] = static_cast<int>(pos - inner);
        }
  return offsets;
}

// values[offset of (3a+i, 3b) + j] += entry(3 la + i, 3 lb + j) for the local nodes la in
// `rows` and every lb of an element with N nodes (offsets as blockOffsets gives them).
template <int N, class Entry>
void addElementBlocks(double* values, const std::array<int, N * N * 3>& offsets,
                      std::uint8_t rows, const Entry& entry) {
  for (int la = 0; la < N; ++la) {
    if (!(rows & (1u << la))) continue;
    for (int lb = 0; lb < N; ++lb)
      for (int i = 0; i < 3; ++i) {
        double* row = values + offsets[(la * N + lb) * 3 + i];
        for (int j = 0; j < 3; ++j) row[j] += entry(3 * la + i, 3 * lb + j);
      }
  }
}

// The owner-computes split of a list of elements with N nodes (RowOwnership): per part, the
// elements with a node of the part, in increasing order, and the rows of the part in each.
template <int N, class Rows>
void splitByOwner(const std::vector<std::array<int, N>>& elements, const std::vector<int>& owner,
                  std::vector<std::vector<int>>& visits, std::vector<std::vector<Rows>>& rows) {
  for (int e = 0; e < static_cast<int>(elements.size()); ++e)
    for (int la = 0; la < N; ++la) {
      const int part = owner[elements[e][la]];
      Rows own = 0;
      for (int lb = 0; lb < N; ++lb)
        if (owner[elements[e][lb]] == part) own |= static_cast<Rows>(1u << lb);
      if (own & ((1u << la) - 1)) continue;  // an earlier local node listed this part already
      visits[part].push_back(e);
      rows[part].push_back(own);
    }
}

}  // namespace

struct SparsePattern::OwnershipCache {
  std::mutex mutex;
  std::vector<std::unique_ptr<RowOwnership>> byParts;
};

SparsePattern::SparsePattern() : ownership_(std::make_shared<OwnershipCache>()) {}

SparsePattern::SparsePattern(int numNodes, const std::vector<Tet>& tets,
                             const std::vector<std::array<int, 2>>& extraPairs,
                             const std::vector<Hex>& hexes)
    : numNodes_(numNodes), tets_(tets), hexes_(hexes),
      ownership_(std::make_shared<OwnershipCache>()) {
  std::vector<std::vector<int>> neighbours(numNodes);
  auto link = [&](int a, int b) {
    neighbours[a].push_back(b);
    neighbours[b].push_back(a);
  };
  for (int a = 0; a < numNodes; ++a) neighbours[a].push_back(a);
  for (const Tet& t : tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) link(t[i], t[j]);
  for (const Hex& h : hexes)
    for (int i = 0; i < 8; ++i)
      for (int j = i + 1; j < 8; ++j) link(h[i], h[j]);
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

  tetOffsets_ = blockOffsets<4>(pattern_, tets);
  hexOffsets_ = blockOffsets<8>(pattern_, hexes);

  breadthFirstOrder_ = breadthFirstOrder(neighbours);
}

SparseMatrix SparsePattern::zeroMatrix() const {
  SparseMatrix K = pattern_;
  std::fill(K.valuePtr(), K.valuePtr() + K.nonZeros(), 0.0);
  return K;
}

void SparsePattern::addTetBlock(SparseMatrix& K, int tet, const Matrix12d& Ke,
                                TetRows rows) const {
  addElementBlocks<4>(K.valuePtr(), tetOffsets_[tet], rows,
                      [&](int r, int c) { return Ke(r, c); });
}

void SparsePattern::addHexBlock(SparseMatrix& K, int hex, const Matrix24d& Ke, double scale,
                                HexRows rows) const {
  addElementBlocks<8>(K.valuePtr(), hexOffsets_[hex], rows,
                      [&](int r, int c) { return scale * Ke(r, c); });
}

const RowOwnership& SparsePattern::rowOwnership(int parts) const {
  parts = std::max(parts, 1);
  std::lock_guard<std::mutex> lock(ownership_->mutex);
  auto& byParts = ownership_->byParts;
  if (static_cast<int>(byParts.size()) <= parts) byParts.resize(parts + 1);
  if (byParts[parts]) return *byParts[parts];

  // Bands of the breadth-first order holding equal shares of the elements (counted at each
  // node; a hex as much work as about six tets).
  std::vector<long long> weight(numNodes_, 1);
  for (const Tet& t : tets_)
    for (int a : t) ++weight[a];
  for (const Hex& h : hexes_)
    for (int a : h) weight[a] += 6;
  long long total = 0;
  for (long long w : weight) total += w;
  std::vector<int> owner(numNodes_, 0);
  long long before = 0;
  for (int node : breadthFirstOrder_) {
    owner[node] = static_cast<int>(std::min<long long>(parts - 1, before * parts / total));
    before += weight[node];
  }

  auto ownership = std::make_unique<RowOwnership>();
  ownership->tets.resize(parts);
  ownership->rows.resize(parts);
  ownership->hexes.resize(parts);
  ownership->hexRows.resize(parts);
  splitByOwner<4>(tets_, owner, ownership->tets, ownership->rows);
  splitByOwner<8>(hexes_, owner, ownership->hexes, ownership->hexRows);
  byParts[parts] = std::move(ownership);
  return *byParts[parts];
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

SparsePattern meshPattern(const Mesh& mesh, std::vector<std::array<int, 2>> extraPairs) {
  return SparsePattern(mesh.numNodes(), mesh.tets, extraPairs, mesh.hexes);
}

}  // namespace tt
