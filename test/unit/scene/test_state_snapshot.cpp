// State snapshots: exact round trip, atomic replacement, and every mismatch or damage refused
// with one line naming the file.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/scene/state_snapshot.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

struct SnapshotFixture : testing::Test {
  Mesh mesh = boxGrid(3, 3, 4, Eigen::Vector3d(0.02, 0.02, 0.03), TetSplit::kSix);
  std::uint64_t id = sceneFingerprint("box", mesh);
  std::string path = (fs::temp_directory_path() / "tt_snapshot_test.bin").string();

  State someState() const {
    State s;
    s.x = Eigen::VectorXd::Random(3 * mesh.numNodes());
    s.v = Eigen::VectorXd::Random(3 * mesh.numNodes());
    s.t = 12.345678901234;
    return s;
  }
  std::vector<char> bytes() const {
    std::ifstream f(path, std::ios::binary);
    return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
  }
  void overwrite(const std::vector<char>& b) const {
    std::ofstream f(path, std::ios::binary | std::ios::trunc);
    f.write(b.data(), static_cast<std::streamsize>(b.size()));
  }
  // The error line of reading the file, or "" when it is accepted.
  std::string refusal(std::uint64_t fingerprint, int nodes) const {
    try {
      readStateSnapshot(path, fingerprint, nodes);
    } catch (const InputError& e) {
      return e.what();
    }
    return "";
  }
  void TearDown() override { fs::remove(path); }
};

TEST_F(SnapshotFixture, RoundTripIsExact) {
  const State s = someState();
  writeStateSnapshot(path, s, id);
  const State r = readStateSnapshot(path, id, mesh.numNodes());
  EXPECT_EQ(r.t, s.t);
  EXPECT_EQ(r.x, s.x);
  EXPECT_EQ(r.v, s.v);
  EXPECT_FALSE(fs::exists(path + ".tmp"));
}

TEST_F(SnapshotFixture, ANewSnapshotReplacesTheOldOneWhole) {
  State s = someState();
  writeStateSnapshot(path, s, id);
  s.t = 20.0;
  s.x.setConstant(0.5);
  writeStateSnapshot(path, s, id);
  const State r = readStateSnapshot(path, id, mesh.numNodes());
  EXPECT_EQ(r.t, 20.0);
  EXPECT_EQ(r.x, s.x);
}

TEST_F(SnapshotFixture, FingerprintFollowsTheNameTheRestPositionsAndTheTets) {
  Mesh moved = mesh;
  moved.rest(2, 5) += 1e-9;
  Mesh renumbered = mesh;
  std::swap(renumbered.tets[0][0], renumbered.tets[0][1]);
  EXPECT_EQ(sceneFingerprint("box", mesh), id);
  EXPECT_NE(sceneFingerprint("box2", mesh), id);
  EXPECT_NE(sceneFingerprint("box", moved), id);
  EXPECT_NE(sceneFingerprint("box", renumbered), id);
}

TEST_F(SnapshotFixture, AnotherSceneOrNodeCountIsRefused) {
  writeStateSnapshot(path, someState(), id);
  EXPECT_NE(refusal(id + 1, mesh.numNodes()).find("another scene"), std::string::npos);
  const std::string nodes = refusal(id, mesh.numNodes() + 1);
  EXPECT_NE(nodes.find(std::to_string(mesh.numNodes()) + " nodes"), std::string::npos) << nodes;
  EXPECT_EQ(nodes.rfind(path, 0), 0u) << nodes;
  EXPECT_EQ(refusal(id, mesh.numNodes()), "");
}

TEST_F(SnapshotFixture, TruncatedFlippedOrForeignFilesAreRefused) {
  writeStateSnapshot(path, someState(), id);
  const std::vector<char> good = bytes();
  for (std::size_t keep : {std::size_t{0}, std::size_t{5}, std::size_t{30}, good.size() - 1}) {
    overwrite(std::vector<char>(good.begin(), good.begin() + static_cast<long>(keep)));
    EXPECT_NE(refusal(id, mesh.numNodes()), "") << "truncated to " << keep;
  }
  std::vector<char> flipped = good;
  flipped[good.size() / 2] ^= 0x10;
  overwrite(flipped);
  EXPECT_NE(refusal(id, mesh.numNodes()).find("checksum"), std::string::npos);
  std::vector<char> longer = good;
  longer.push_back('x');
  overwrite(longer);
  EXPECT_NE(refusal(id, mesh.numNodes()).find("after the checksum"), std::string::npos);
  overwrite(std::vector<char>(good.size(), 'A'));
  EXPECT_NE(refusal(id, mesh.numNodes()).find("not a state snapshot"), std::string::npos);
  fs::remove(path);
  EXPECT_NE(refusal(id, mesh.numNodes()).find("cannot open"), std::string::npos);
}

TEST_F(SnapshotFixture, NonFiniteValuesAreRefused) {
  State s = someState();
  s.v[7] = std::numeric_limits<double>::quiet_NaN();
  writeStateSnapshot(path, s, id);
  EXPECT_NE(refusal(id, mesh.numNodes()).find("non-finite"), std::string::npos);
  s = someState();
  s.t = std::numeric_limits<double>::infinity();
  writeStateSnapshot(path, s, id);
  EXPECT_NE(refusal(id, mesh.numNodes()).find("non-finite"), std::string::npos);
}

TEST_F(SnapshotFixture, AnUnwritableFolderThrowsNamingTheFile) {
  const std::string bad = "/nonexistent_tt_folder/snapshot.bin";
  try {
    writeStateSnapshot(bad, someState(), id);
    FAIL() << "no error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find(bad), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace tt
