#pragma once
// Whole-mesh loops over elements (tets, hexes) shared by the element force models, sequential or on
// tt::threadCount() threads (parallel.h):
//   forces    : each thread takes a contiguous range of tets; the first adds straight into f,
//               the others into their own zeroed force buffer, and the buffers are added to f
//               afterwards in thread order. Streaming the per-tet data in mesh order keeps the
//               cheap force kernel fast, and the extra work (zero + add of 3n doubles per extra
//               thread) is small beside the tets.
//   stiffness : a per-thread copy of K would cost more than the assembly itself, so each
//               thread owns a band of rows (SparsePattern::rowOwnership) and writes only
//               those, visiting the tets (then the hexes) at its nodes in mesh order; the
//               elements across a band border are evaluated twice. Every entry of K receives its terms in the same
//               order for any thread count, so K is bitwise that of one thread. (A colouring of
//               the tets, with a barrier per colour, was slower on two threads than one
//               thread on TetGen livers: the tets of a colour lie all over the mesh.)
// Per-tet work is a callable inlined into the loop (no virtual call, no allocation).
#include <Eigen/Core>
#include <array>
#include <vector>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/solve/sparse_pattern.h"

namespace tt {

using Matrix34d = Eigen::Matrix<double, 3, 4>;

namespace detail {
// Force buffers of the threads other than the first, owned by the calling thread and kept
// between calls (sized to `size` doubles; no allocation once sized).
std::vector<Eigen::VectorXd>& forceBuffers(int count, Eigen::Index size);
}  // namespace detail

// The four node positions (or displacements) of tet t as columns.
inline Matrix34d gatherTet(const Eigen::VectorXd& x, const Tet& t) {
  Matrix34d xe;
  for (int p = 0; p < 4; ++p) xe.col(p) = x.segment<3>(3 * t[p]);
  return xe;
}

inline void scatterAddTet(const Matrix34d& fe, const Tet& t, Eigen::VectorXd& f) {
  for (int p = 0; p < 4; ++p) f.segment<3>(3 * t[p]) += fe.col(p);
}

// f += sum over elements of the nodal forces elementForce(e, fe) writes into fe (3 x N, one
// column per element node); returns the sum of what elementForce returns (the energies).
template <int N, class ElementForce>
double accumulateElementForces(const std::vector<std::array<int, N>>& elements,
                               Eigen::VectorXd& f, const ElementForce& elementForce) {
  const int parts = threadCount();
  const int count = static_cast<int>(elements.size());
  std::array<double, kMaxThreads> energies{};
  std::vector<Eigen::VectorXd>& buffers = detail::forceBuffers(parts - 1, f.size());
  parallelRanges(parts, count, [&](int part, int begin, int end) {
    Eigen::VectorXd& out = part == 0 ? f : buffers[part - 1];
    if (part > 0) out.setZero();
    double energy = 0.0;
    Eigen::Matrix<double, 3, N> fe;
    for (int e = begin; e < end; ++e) {
      energy += elementForce(e, fe);
      for (int p = 0; p < N; ++p) out.template segment<3>(3 * elements[e][p]) += fe.col(p);
    }
    energies[part] = energy;
  });
  if (parts > 1) {
    parallelRanges(parts, static_cast<int>(f.size()), [&](int, int begin, int end) {
      for (int b = 0; b < parts - 1; ++b)
        f.segment(begin, end - begin) += buffers[b].segment(begin, end - begin);
    });
  }
  double energy = 0.0;
  for (int part = 0; part < parts; ++part) energy += energies[part];
  return energy;
}

// f += sum over tets of the nodal forces tetForce(e, fe) writes into fe; returns the sum of
// what tetForce returns (the energies).
template <class TetForce>
double accumulateTetForces(const std::vector<Tet>& tets, Eigen::VectorXd& f,
                           const TetForce& tetForce) {
  return accumulateElementForces<4>(tets, f, tetForce);
}

// Sum over tets of tetValue(e).
template <class TetValue>
double sumOverTets(int count, const TetValue& tetValue) {
  const int parts = threadCount();
  std::array<double, kMaxThreads> sums{};
  parallelRanges(parts, count, [&](int part, int begin, int end) {
    double sum = 0.0;
    for (int e = begin; e < end; ++e) sum += tetValue(e);
    sums[part] = sum;
  });
  double sum = 0.0;
  for (int part = 0; part < parts; ++part) sum += sums[part];
  return sum;
}

// Calls addTet(e, rows) for every tet, where addTet adds into the rows of the local nodes of
// tet e that `rows` has (TetRows): once with kAllTetRows per tet in mesh order on one thread;
// on several, each tet once for every thread owning one of its nodes, with that thread's rows.
template <class AddTet>
void forEachTetByRows(const SparsePattern& pattern, int count, const AddTet& addTet) {
  const int parts = threadCount();
  if (parts == 1 || pattern.numTets() != count) {
    for (int e = 0; e < count; ++e) addTet(e, kAllTetRows);
    return;
  }
  const RowOwnership& ownership = pattern.rowOwnership(parts);
  parallelRanges(parts, parts, [&](int part, int, int) {
    const std::vector<int>& tets = ownership.tets[part];
    const std::vector<TetRows>& rows = ownership.rows[part];
    for (size_t i = 0; i < tets.size(); ++i) addTet(tets[i], rows[i]);
  });
}

// The same for the hexes (addHex(e, rows), HexRows); called after the tets, every entry of K
// still receives its terms in the same order as on one thread.
template <class AddHex>
void forEachHexByRows(const SparsePattern& pattern, int count, const AddHex& addHex) {
  const int parts = threadCount();
  if (parts == 1 || pattern.numHexes() != count) {
    for (int e = 0; e < count; ++e) addHex(e, kAllHexRows);
    return;
  }
  const RowOwnership& ownership = pattern.rowOwnership(parts);
  parallelRanges(parts, parts, [&](int part, int, int) {
    const std::vector<int>& hexes = ownership.hexes[part];
    const std::vector<HexRows>& rows = ownership.hexRows[part];
    for (size_t i = 0; i < hexes.size(); ++i) addHex(hexes[i], rows[i]);
  });
}

// K += scale * the element stiffness blocks of a model's tets and hexes: tetBlock(e) is the
// 12 x 12 and hexBlock(e) the 24 x 24 block (node-major: row 3 p + i) of element e, each run
// as forEachTetByRows and forEachHexByRows do. Through the pattern's precomputed offsets when
// it was built with these hexes (meshPattern), else a search per row.
template <class TetBlock, class HexBlock>
void addElementStiffness(const SparsePattern& pattern, SparseMatrix& K, double scale,
                         int tetCount, const TetBlock& tetBlock, const std::vector<Hex>& hexes,
                         const HexBlock& hexBlock) {
  forEachTetByRows(pattern, tetCount, [&](int e, TetRows rows) {
    pattern.addTetBlock(K, e, scale * tetBlock(e), rows);
  });
  const int hexCount = static_cast<int>(hexes.size());
  if (pattern.numHexes() == hexCount) {
    forEachHexByRows(pattern, hexCount, [&](int e, HexRows rows) {
      pattern.addHexBlock(K, e, hexBlock(e), scale, rows);
    });
    return;
  }
  for (int e = 0; e < hexCount; ++e) {
    const auto Ke = hexBlock(e);
    for (int a = 0; a < 8; ++a)
      for (int b = 0; b < 8; ++b)
        pattern.addNodeBlock(K, hexes[e][a], hexes[e][b],
                             scale * Ke.template block<3, 3>(3 * a, 3 * b));
  }
}

}  // namespace tt
