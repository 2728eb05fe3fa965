// The threaded element loops (parallel.h, tet_loops.h): the row bands of the stiffness assembly
// cover every tet and hex row once, the hex blocks go in through offsets as they did through a
// search, the forces and energies of every tet model on 2 and 3 threads agree
// with 1 thread to round-off and repeat bitwise, and the stiffness is bitwise that of 1 thread.
#include <gtest/gtest.h>

#include <cstring>
#include <memory>
#include <algorithm>
#include <set>

#include "model_test_util.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/model/tensor_mass.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

using namespace testutil;

// Sets the thread count for one scope and restores the previous one.
class ThreadScope {
 public:
  explicit ThreadScope(int threads) : previous_(threadCount()) { setThreadCount(threads); }
  ~ThreadScope() { setThreadCount(previous_); }

 private:
  int previous_;
};

bool bitwiseEqual(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return a.size() == b.size() &&
         std::memcmp(a.data(), b.data(), sizeof(double) * static_cast<size_t>(a.size())) == 0;
}

struct Evaluation {
  Eigen::VectorXd force, stiffness;  // stiffness: K's value array
  double addForceEnergy = 0.0, energy = 0.0;
};

Evaluation evaluate(const ForceModel& model, const SparsePattern& pattern,
                    const Eigen::VectorXd& x, int threads) {
  ThreadScope scope(threads);
  Evaluation out;
  // A non-zero starting force: the models add into f.
  out.force = Eigen::VectorXd::LinSpaced(x.size(), -1.0, 1.0);
  out.addForceEnergy = model.addForce(x, Eigen::VectorXd::Zero(x.size()), out.force);
  out.energy = model.energy(x);
  SparseMatrix K = pattern.zeroMatrix();
  model.addStiffness(x, 0.7, pattern, K);
  out.stiffness = Eigen::Map<const Eigen::VectorXd>(K.valuePtr(), K.nonZeros());
  return out;
}

TEST(Parallel, ThreadCountIsClampedAndDefaultsToOne) {
  EXPECT_EQ(threadCount(), 1);
  {
    ThreadScope scope(0);
    EXPECT_EQ(threadCount(), 1);
  }
  {
    ThreadScope scope(1000);
    EXPECT_LE(threadCount(), kMaxThreads);
  }
  EXPECT_EQ(threadCount(), 1);
}

TEST(Parallel, RangesCoverEveryItemOnceForAnyPartCount) {
  for (int parts : {1, 2, 3, 7}) {
    ThreadScope scope(parts);
    std::vector<int> hits(101, 0);
    parallelRanges(parts, 101, [&](int, int begin, int end) {
      for (int i = begin; i < end; ++i) ++hits[i];
    });
    for (int h : hits) EXPECT_EQ(h, 1) << parts << " parts";
  }
}

// Every row of K is written by exactly one part, from every tet at its node, and the bands are
// bands: the tets visited twice are a thin layer, not a scattering over the mesh.
TEST(Parallel, RowOwnershipWritesEveryTetRowOnceInThinBands) {
  std::mt19937 rng(3);
  const Mesh m = boxMesh(12, 6, 5, 0.01, rng);
  const SparsePattern pattern(m.numNodes(), m.tets);
  for (int parts : {2, 3, 5}) {
    const RowOwnership& own = pattern.rowOwnership(parts);
    EXPECT_EQ(&own, &pattern.rowOwnership(parts)) << "kept, not rebuilt";
    ASSERT_EQ(own.tets.size(), static_cast<size_t>(parts));
    std::vector<int> writes(4 * m.tets.size(), 0);  // per tet, per local node
    size_t visits = 0;
    for (int part = 0; part < parts; ++part) {
      ASSERT_EQ(own.tets[part].size(), own.rows[part].size());
      EXPECT_TRUE(std::is_sorted(own.tets[part].begin(), own.tets[part].end())) << part;
      EXPECT_FALSE(own.tets[part].empty()) << part;
      visits += own.tets[part].size();
      for (size_t i = 0; i < own.tets[part].size(); ++i) {
        EXPECT_NE(own.rows[part][i], 0) << "a visit that writes nothing";
        for (int la = 0; la < 4; ++la)
          if (own.rows[part][i] & (1u << la)) ++writes[4 * own.tets[part][i] + la];
      }
    }
    for (int w : writes) EXPECT_EQ(w, 1) << parts << " parts";
    // A 12x6x5 box has 2160 tets; a band border crosses it in about one layer of 6x5 cells
    // (180 tets): far below the 2160 * (parts - 1) of a split without locality.
    EXPECT_LT(visits - m.tets.size(), 400u * (parts - 1)) << parts << " parts";
  }
}

TEST(Parallel, ModelsAgreeAcrossThreadCountsAndRepeatBitwise) {
  std::mt19937 rng(17);
  const Mesh m = boxMesh(6, 5, 4, 0.01, rng);
  const auto mats = testMaterials();
  std::vector<std::unique_ptr<ForceModel>> models;
  models.push_back(std::make_unique<EdgeLengthModel>(m, mats, EdgeLengthPath::kFast));
  models.push_back(std::make_unique<EdgeLengthModel>(m, mats, EdgeLengthPath::kLiteral));
  models.push_back(std::make_unique<StvkDisplacementModel>(m, mats, AlphaSign::kCorrect));
  models.push_back(std::make_unique<StvkDisplacementModel>(m, mats, AlphaSign::kPaperLiteral));
  models.push_back(std::make_unique<TensorMassModel>(m, mats));
  const SparsePattern pattern(m.numNodes(), m.tets);
  const Eigen::VectorXd x = perturbed(m, 0.001, rng);
  for (const auto& model : models) {
    const Evaluation one = evaluate(*model, pattern, x, 1);
    ASSERT_GT(one.stiffness.lpNorm<Eigen::Infinity>(), 0.0);
    for (int threads : {2, 3}) {
      const Evaluation a = evaluate(*model, pattern, x, threads);
      const Evaluation b = evaluate(*model, pattern, x, threads);
      const std::string what = std::string(model->name()) + ", " + std::to_string(threads) + " threads";
      // The force starts at O(1) values: compare the models' part of it.
      const Eigen::VectorXd start = Eigen::VectorXd::LinSpaced(x.size(), -1.0, 1.0);
      EXPECT_LT(relDiff(Eigen::VectorXd(a.force - start), Eigen::VectorXd(one.force - start)), 1e-12)
          << what;
      EXPECT_TRUE(bitwiseEqual(a.stiffness, one.stiffness)) << what;
      EXPECT_NEAR(a.energy, one.energy, 1e-13 * std::abs(one.energy)) << what;
      EXPECT_NEAR(a.addForceEnergy, one.addForceEnergy, 1e-13 * std::abs(one.energy)) << what;
      EXPECT_TRUE(bitwiseEqual(a.force, b.force)) << what;
      EXPECT_TRUE(bitwiseEqual(a.stiffness, b.stiffness)) << what;
      EXPECT_EQ(a.energy, b.energy) << what;
    }
  }
}

// A box of hexes (no tet split), its nodes jittered so that no two element blocks are equal.
Mesh hexBoxForThreads(int cells, std::mt19937& rng) {
  Mesh m = boxGrid(cells + 2, cells + 1, cells + 1, Eigen::Vector3d(0.03, 0.02, 0.02),
                   TetSplit::kNone);
  std::uniform_real_distribution<double> jitter(-1e-3, 1e-3);
  for (int a = 0; a < m.numNodes(); ++a)
    for (int i = 0; i < 3; ++i) m.rest(i, a) += jitter(rng);
  m.fillDefaults();
  return m;
}

// Every row of K is written by exactly one part from every hex at its node, as for the tets.
TEST(Parallel, RowOwnershipWritesEveryHexRowOnce) {
  std::mt19937 rng(5);
  const Mesh m = hexBoxForThreads(5, rng);
  const SparsePattern pattern = meshPattern(m);
  ASSERT_EQ(pattern.numHexes(), m.numHexes());
  for (int parts : {2, 3}) {
    const RowOwnership& own = pattern.rowOwnership(parts);
    std::vector<int> writes(8 * m.hexes.size(), 0);  // per hex, per local node
    for (int part = 0; part < parts; ++part) {
      ASSERT_EQ(own.hexes[part].size(), own.hexRows[part].size());
      EXPECT_TRUE(std::is_sorted(own.hexes[part].begin(), own.hexes[part].end())) << part;
      EXPECT_FALSE(own.hexes[part].empty()) << part;
      for (size_t i = 0; i < own.hexes[part].size(); ++i)
        for (int la = 0; la < 8; ++la)
          if (own.hexRows[part][i] & (1u << la)) ++writes[8 * own.hexes[part][i] + la];
    }
    for (int w : writes) EXPECT_EQ(w, 1) << parts << " parts";
  }
}

// The hex stiffness through the pattern's offsets, on 1, 2 and 3 threads, is bitwise the one
// added block by block with a search per row (a pattern that knows the hex node pairs only).
TEST(Parallel, HexStiffnessThroughOffsetsIsBitwiseTheSearchedOne) {
  std::mt19937 rng(23);
  const Mesh m = hexBoxForThreads(4, rng);
  const auto model = makeElasticModel("hyperelastic_neo_hookean", m, testMaterials());
  std::vector<std::array<int, 2>> hexPairs;
  for (const Hex& h : m.hexes)
    for (int a = 0; a < 8; ++a)
      for (int b = a + 1; b < 8; ++b) hexPairs.push_back({h[a], h[b]});
  const SparsePattern searched(m.numNodes(), m.tets, hexPairs);
  const SparsePattern withOffsets = meshPattern(m);
  ASSERT_EQ(searched.numHexes(), 0);
  ASSERT_EQ(searched.nonZeros(), withOffsets.nonZeros());
  const Eigen::VectorXd x = perturbed(m, 0.001, rng);
  const Evaluation reference = evaluate(*model, searched, x, 1);
  ASSERT_GT(reference.stiffness.lpNorm<Eigen::Infinity>(), 0.0);
  for (int threads : {1, 2, 3})
    EXPECT_TRUE(bitwiseEqual(evaluate(*model, withOffsets, x, threads).stiffness,
                             reference.stiffness))
        << threads << " threads";
}

TEST(Parallel, BackwardEulerStepsAgreeOnOneAndTwoThreads) {
  std::mt19937 rng(29);
  Mesh m = boxMesh(5, 3, 3, 0.01, rng);
  for (int a = 0; a < m.numNodes(); ++a)
    if (m.rest(0, a) < 0.002) m.nodeTags[a] = kFixedAll;
  auto run = [&](int threads) {
    ThreadScope scope(threads);
    System s(m, testMaterials());
    s.models.push_back(std::make_unique<EdgeLengthModel>(s.mesh, s.materials));
    s.externalForce.setZero();
    for (int a = 0; a < s.numNodes(); ++a) s.externalForce[3 * a + 2] = -1e-3;
    BackwardEulerParams p;
    p.linearTolerance = 1e-12;
    BackwardEulerIntegrator integrator(p);
    for (int step = 0; step < 5; ++step) EXPECT_TRUE(integrator.advance(s, 0.01).ok);
    return s.state.x;
  };
  const Eigen::VectorXd rest = restVector(m);
  const Eigen::VectorXd one = run(1), two = run(2);
  ASSERT_GT((one - rest).lpNorm<Eigen::Infinity>(), 1e-6);
  EXPECT_LT(relDiff(Eigen::VectorXd(two - rest), Eigen::VectorXd(one - rest)), 1e-9);
  EXPECT_TRUE(bitwiseEqual(two, run(2)));
}

}  // namespace
}  // namespace tt
