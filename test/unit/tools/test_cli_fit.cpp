// The contract of `tissue_cli fit` (docs/cli.md, "Landmark fitting: fit"): activations
// recovered from the landmarks of a known equilibrium, exit 4 when the fit stops early, and a
// malformed targets file as one error line.
#include "cli_test_util.h"
#ifdef TT_CLI_PATH
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>

#include "../fit/fit_test_util.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

// Writes a targets file of its equilibrium at the activations (0.3, 0.6, 0.45):
// every 4th free node and one tet point.
std::string writeTargets(const std::string& scenePath) {
  Scene scene = loadScene(scenePath);
  System& s = scene.system;
  testutil::setActivations(s, {0.3, 0.6, 0.45});
  EXPECT_TRUE(solveEquilibrium(s, testutil::tightEquilibrium()).converged());
  std::ostringstream out;
  out.precision(17);
  out << "# landmarks of the block at (0.3, 0.6, 0.45)\n\n";
  for (const Landmark& l : testutil::nodeLandmarks(s, s.state.x, 4))
    out << "node " << l.nodes[0] << " " << l.target.transpose() << "\n";
  const Tet& t = s.mesh.tets.back();
  const Eigen::Vector3d p = 0.25 * (s.state.x.segment<3>(3 * t[0]) + s.state.x.segment<3>(3 * t[1]) +
                                    s.state.x.segment<3>(3 * t[2]) + s.state.x.segment<3>(3 * t[3]));
  out << "tet " << s.mesh.numTets() - 1 << " 0.25 0.25 0.25 0.25 " << p.transpose() << "  # centroid\n";
  return testutil::writeScene("fit_targets.txt", out.str());
}

TEST(CliFit, RecoversTheActivationsAndWritesTheFittedState) {
  const std::string scene = testutil::threeMuscleBlockPath();
  const std::string targets = writeTargets(scene);
  const fs::path out = fs::temp_directory_path() / "tt_cli_fit_out";
  fs::remove_all(out);
  const testutil::CliResult r =
      testutil::runCli("fit " + scene + " --targets " + targets + " --out " + out.string());
  ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
  std::istringstream lines(r.out);
  std::map<std::string, double> activation;
  double residual = -1;
  int iterations = 0;
  bool converged = false;
  for (std::string line; std::getline(lines, line);) {
    std::istringstream words(line);
    std::string word, name;
    words >> word;
    if (word == "activation") words >> name >> activation[name];
    if (word == "residual") words >> residual;
    if (word == "iteration") ++iterations;
    if (word == "converged") converged = true;
  }
  EXPECT_TRUE(converged);
  EXPECT_GT(iterations, 0);
  EXPECT_NEAR(activation["lower"], 0.3, 1e-6);
  EXPECT_NEAR(activation["middle"], 0.6, 1e-6);
  EXPECT_NEAR(activation["upper"], 0.45, 1e-6);
  EXPECT_GE(residual, 0.0);
  EXPECT_LT(residual, 1e-9);
  EXPECT_TRUE(fs::exists(out / "fit.vtu"));
}

TEST(CliFit, StopsWithExitCode4AndTheReasonWhenNotConverged) {
  const std::string scene = testutil::threeMuscleBlockPath();
  const std::string targets = writeTargets(scene);
  const testutil::CliResult r =
      testutil::runCli("fit " + scene + " --targets " + targets + " --max-iterations 1");
  EXPECT_EQ(r.exitCode, 4);
  EXPECT_NE(r.out.find("\nnot converged (iteration_limit): "), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("\nresidual "), std::string::npos) << r.out;
}

// The block with its bottom face marked `jaw: true`: --jaw fits a jaw transform moving those
// nodes. The targets were taken with the jaw at rest, so it comes back as the identity.
TEST(CliFit, JawFlagFitsTheScenesJawNodes) {
  std::ifstream in(testutil::threeMuscleBlockPath());
  const std::string text((std::istreambuf_iterator<char>(in)), {});
  const std::string scene = testutil::writeScene(
      "jaw_block.yaml", testutil::replaced(text, "max: [1, 1, 0.001]}}", "max: [1, 1, 0.001]}, jaw: true}"));
  const std::string targets = writeTargets(scene);
  const testutil::CliResult r = testutil::runCli("fit " + scene + " --targets " + targets + " --jaw");
  ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
  EXPECT_NE(r.out.find(", 15 parameters\n"), std::string::npos) << r.out;  // 3 activations + 12
  const size_t at = r.out.find("\njaw ");
  ASSERT_NE(at, std::string::npos) << r.out;
  std::istringstream jaw(r.out.substr(at + 5));
  const double identity[12] = {1, 0, 0, 0, 1, 0, 0, 0, 1, 0, 0, 0};
  for (int k = 0; k < 12; ++k) {
    double value = -1;
    jaw >> value;
    EXPECT_NEAR(value, identity[k], k < 9 ? 1e-6 : 1e-8) << k;
  }
}

TEST(CliFit, JawFlagNeedsJawNodesAndExcludesTheJawBox) {
  const std::string scene = testutil::threeMuscleBlockPath();
  const std::string targets = writeTargets(scene);
  testutil::CliResult r = testutil::runCli("fit " + scene + " --targets " + targets + " --jaw");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--jaw: the scene has no jaw nodes (a boundary.fixed entry with jaw: true)"),
            std::string::npos) << r.err;
  r = testutil::runCli("fit " + scene + " --targets " + targets + " --jaw --jaw-box -1 -1 -1 1 1 0.001");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("give --jaw or --jaw-box, not both"), std::string::npos) << r.err;
}

TEST(CliFit, AMalformedTargetsFileIsOneErrorLine) {
  const std::string scene = testutil::threeMuscleBlockPath();
  const std::string targets = testutil::writeScene("bad_targets.txt", "node 0 0 0 0\nnode 1 0 0\n");
  const testutil::CliResult r = testutil::runCli("fit " + scene + " --targets " + targets);
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, targets + ":2: 'node' expects 4 numbers, got 3\n");
  EXPECT_TRUE(r.out.empty()) << r.out;
}

}  // namespace
}  // namespace tt
#endif
