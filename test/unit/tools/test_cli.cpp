// The tissue_cli contract (docs/cli.md): output format and exit codes.
// Only in the catkin build, which knows where tissue_cli is (TT_CLI_PATH).
#ifdef TT_CLI_PATH
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "cli_test_util.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

using Result = testutil::CliResult;
using testutil::runCli;

const std::string kLiver = std::string(TT_SOURCE_DIR) + "/config/meshes/liver.msh";

TEST(Cli, InfoReportsCountsOfTheLiver) {
  const Result r = runCli("info " + kLiver);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("181"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("596"), std::string::npos) << r.out;
}

// Generated grids written as TetGen and Gmsh v4 files: `info` counts what the generator made
// (nx ny nz nodes, five tets per cell).
TEST(Cli, InfoCountsGeneratedTetgenAndGmsh4Files) {
  Mesh box = boxGrid(4, 3, 5, Eigen::Vector3d(0.03, 0.02, 0.04), TetSplit::kFiveMirrored);
  box.hexes.clear();  // TetGen files hold tets only
  const fs::path dir = fs::temp_directory_path() / "tt_cli_generated";
  fs::create_directories(dir);
  writeTetgen((dir / "box").string(), box);
  writeGmsh4((dir / "box_v4.msh").string(), box);
  for (const std::string file : {"box.node", "box_v4.msh"}) {
    const Result r = runCli("info " + (dir / file).string());
    ASSERT_EQ(r.exitCode, 0) << file << ": " << r.err;
    EXPECT_NE(r.out.find("nodes 60, tets 120,"), std::string::npos) << file << ":\n" << r.out;
  }
}

TEST(Cli, ForcesMatchTheCoreModelToTheLastDigit) {
  const Mesh mesh = readMesh(kLiver);
  const fs::path positions = fs::temp_directory_path() / "tt_cli_positions.txt";
  Eigen::VectorXd x(3 * mesh.numNodes());
  {
    std::ofstream out(positions);
    out.precision(17);
    for (int n = 0; n < mesh.numNodes(); ++n) {
      const Eigen::Vector3d p = mesh.rest.col(n);
      const Eigen::Vector3d q(1.05 * p.x(), p.y() + 0.02 * p.x(), 0.97 * p.z());
      x.segment<3>(3 * n) = q;
      out << q.x() << " " << q.y() << " " << q.z() << "\n";
    }
  }
  const Result r = runCli("forces --mesh " + kLiver + " --deformed " + positions.string() +
                          " --model edge_length --lambda 2000 --mu 1000 --lambda-l 5000"
                          " --mu-l 3000 --fiber 1 1 0");
  ASSERT_EQ(r.exitCode, 0) << r.err;

  Mesh fibred = mesh;
  for (auto& frame : fibred.fibreFrame) frame.col(0) = Eigen::Vector3d(1, 1, 0).normalized();
  ElasticConstants k;
  k.lambda = 2000, k.mu = 1000, k.lambdaL = 5000, k.muL = 3000;
  const Material m = Material::withConstants(k, 1000.0);
  const EdgeLengthModel model(fibred, {m});
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  const double energy = model.addForce(x, Eigen::VectorXd::Zero(x.size()), f);

  std::istringstream in(r.out);
  std::string word;
  double printedEnergy;
  in >> word >> printedEnergy;
  EXPECT_EQ(word, "energy");
  EXPECT_GT(energy, 0.0);
  EXPECT_EQ(printedEnergy, energy);  // %.17g round-trips exactly
  Eigen::VectorXd printed(x.size());
  for (int i = 0; i < printed.size(); ++i) ASSERT_TRUE(in >> printed[i]) << "line " << i / 3;
  EXPECT_FALSE(in >> word) << "extra output";
  EXPECT_EQ((printed - f).cwiseAbs().maxCoeff(), 0.0);
}

TEST(Cli, BadInputGivesOneLineAndExitCode2) {
  const fs::path positions = fs::temp_directory_path() / "tt_cli_short.txt";
  std::ofstream(positions) << "0 0 0\n1 2 x\n";
  Result r = runCli("forces --mesh " + kLiver + " --deformed " + positions.string() +
                    " --model edge_length --lambda 1 --mu 1");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_EQ(r.err, positions.string() + ":2: expected a finite number, got 'x'\n");

  r = runCli("forces --mesh " + kLiver + " --deformed " + positions.string() +
             " --model edge_lenght --lambda 1 --mu 1");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("--model expects one of"), std::string::npos) << r.err;

  r = runCli("info /nonexistent.msh");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("/nonexistent.msh"), std::string::npos) << r.err;

  r = runCli("frobnicate");
  EXPECT_EQ(r.exitCode, 2);
  EXPECT_NE(r.err.find("unknown command 'frobnicate'"), std::string::npos) << r.err;
}

TEST(Cli, RunWritesTheCsvLogAndVtuSeriesItLists) {
  const fs::path dir = fs::temp_directory_path() / "tt_cli_run";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "block.yaml") << R"(name: block
mesh: {generator: box, nodes: [3, 3, 4], size: [0.02, 0.02, 0.03]}
materials: [{young_modulus: 5000, poisson_ratio: 0.3, density: 1000}]
force_models: [{type: edge_length}]
integrator: {type: backward_euler}
boundary: {fixed: [{plane: {point: [0, 0, 0], normal: [0, 0, 1]}}]}
loads: {gravity: [0, 0, -9.81]}
run: {frame_time: 0.01, duration: 0.1}
output: {vtu_every: 5, csv: true}
)";
  const Result r = runCli("run " + (dir / "block.yaml").string() + " --out " + (dir / "out").string());
  ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("summary frames=10"), std::string::npos) << r.out;
  std::ifstream csv(dir / "out" / "block.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header.rfind("frame,time,kinetic_energy,elastic_energy,load_energy,volume_ratio,max_displacement", 0), 0u);
  int lines = 0;
  for (std::string line; std::getline(csv, line);) ++lines;
  EXPECT_EQ(lines, 10);
  for (const char* name : {"block.pvd", "block_000000.vtu", "block_000005.vtu", "block_000010.vtu"})
    EXPECT_TRUE(fs::exists(dir / "out" / name)) << name;
  EXPECT_FALSE(fs::exists(dir / "out" / "block_000001.vtu"));
}

// A block settling under gravity and mass damping; `run` and `output` are appended.
const char* const kSettlingBlock = R"(name: settle
mesh: {generator: box, nodes: [3, 3, 4], size: [0.02, 0.02, 0.03]}
materials: [{young_modulus: 5000, poisson_ratio: 0.3, density: 1000}]
force_models: [{type: tensor_mass}]
integrator: {type: backward_euler}
boundary: {fixed: [{plane: {point: [0, 0, 0], normal: [0, 0, 1]}}]}
loads: {gravity: [0, 0, -9.81], rayleigh_mass: 30}
)";

TEST(Cli, RunStopsWhenTheKineticEnergyFallsBelowTheThreshold) {
  const fs::path dir = fs::temp_directory_path() / "tt_cli_settle";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "settle.yaml") << kSettlingBlock
                                     << "run: {frame_time: 0.01, duration: 5, stop_kinetic_energy: 1e-9}\n";
  const Result r = runCli("run " + (dir / "settle.yaml").string());
  ASSERT_EQ(r.exitCode, 0) << r.err << r.out;
  EXPECT_NE(r.out.find("stopped at t="), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("below stop_kinetic_energy 1e-09 J"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find(" stop=kinetic_energy\n"), std::string::npos) << r.out;
  EXPECT_EQ(r.out.find("summary frames=500 "), std::string::npos) << r.out;

  std::ofstream(dir / "full.yaml") << kSettlingBlock << "run: {frame_time: 0.01, duration: 0.05}\n";
  const Result full = runCli("run " + (dir / "full.yaml").string());
  ASSERT_EQ(full.exitCode, 0) << full.err;
  EXPECT_NE(full.out.find("summary frames=5 "), std::string::npos) << full.out;
  EXPECT_NE(full.out.find(" stop=duration\n"), std::string::npos) << full.out;
}

// SIGINT (and SIGTERM) end the run after the frame in progress: the outputs are written, the
// reason printed and the exit code is 5. The signal is sent once the run is under way (its CSV
// log has lines; a freshly built binary can take a while to start); the scene would run for
// hours otherwise.
TEST(Cli, RunEndsCleanlyOnAnInterrupt) {
  const fs::path dir = fs::temp_directory_path() / "tt_cli_interrupt";
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "settle.yaml") << kSettlingBlock
                                     << "run: {frame_time: 0.001, duration: 100000}\n"
                                        "output: {vtu_every: 100000, csv: true}\n";
  for (const char* signal : {"INT", "TERM"}) {
    const fs::path out = dir / signal;
    // sh runs the command given after it in the background, waits (at most 60 s) for its log,
    // signals it and returns its exit code.
    const std::string signalWhenRunning =
        "sh -c 'log=" + (out / "settle.csv").string() +
        "; \"$@\" & pid=$!; i=0; while [ ! -s $log ] && [ $i -lt 1200 ]; do sleep 0.05; "
        "i=$((i+1)); done; kill -" + signal + " $pid; wait $pid' sh ";
    const Result r = runCli("run " + (dir / "settle.yaml").string() + " --out " + out.string() +
                                " --threads 1",
                            signalWhenRunning);
    EXPECT_EQ(r.exitCode, 5) << signal << ": " << r.err << r.out;
    EXPECT_NE(r.out.find(std::string("interrupted by SIG") + signal), std::string::npos) << r.out;
    EXPECT_NE(r.out.find(" stop=interrupt\n"), std::string::npos) << r.out;
    const size_t at = r.out.find("summary frames=");
    ASSERT_NE(at, std::string::npos) << r.out;
    const int frames = std::stoi(r.out.substr(at + 15));
    EXPECT_GT(frames, 0);
    std::ifstream csv(out / "settle.csv");
    int lines = 0;
    for (std::string line; std::getline(csv, line);) ++lines;
    EXPECT_EQ(lines, frames + 1) << "header and one line per frame";
    char last[32];
    std::snprintf(last, sizeof last, "settle_%06d.vtu", frames);
    EXPECT_TRUE(fs::exists(out / last)) << last;
    EXPECT_TRUE(fs::exists(out / "settle.pvd"));
  }
}

// --- forces --scene -------------------------------------------------------------------------

// A placed, fibred, two-material block with two elastic models, gravity and a clamp: only
// the models count in `forces --scene`.
const char* const kForcesScene = R"(name: forces_block
mesh: {generator: box, nodes: [3, 3, 4], size: [2, 2, 3], length_unit: cm, scale: 1.5,
       rotate_deg: [10, 0, 30], translate: [0.1, -0.05, 0.02]}
materials:
  - {young_modulus: 5, poisson_ratio: 0.4, young_modulus_longitudinal: 9,
     poisson_ratio_longitudinal: 0.3, stress_unit: kPa, density: 1000}
  - {region: {box: {min: [-1, -1, 0.05], max: [1, 1, 1]}}, lambda: 3000, mu: 1500}
fibres: {direction: [1, 1, 0]}
force_models: [{type: edge_length, path: literal}, {type: tensor_mass}]
integrator: {type: backward_euler}
boundary: {fixed: [{nodes: [0, 1, 2]}]}
loads: {gravity: [0, 0, -9.81]}
)";

struct ForcesOutput {
  double energy = 0.0;
  Eigen::VectorXd force, stiffnessTimes;
};

// Parses the contract: `energy E`, n force lines, and optionally `stiffness_times` + n lines.
ForcesOutput parseForces(const std::string& out, int numNodes, bool withStiffness) {
  std::istringstream in(out);
  std::string word;
  ForcesOutput r;
  in >> word >> r.energy;
  EXPECT_EQ(word, "energy");
  r.force.resize(3 * numNodes);
  for (int i = 0; i < r.force.size(); ++i) EXPECT_TRUE(in >> r.force[i]) << "force line " << i / 3;
  if (withStiffness) {
    EXPECT_TRUE(in >> word);
    EXPECT_EQ(word, "stiffness_times");
    r.stiffnessTimes.resize(3 * numNodes);
    for (int i = 0; i < r.stiffnessTimes.size(); ++i)
      EXPECT_TRUE(in >> r.stiffnessTimes[i]) << "stiffness_times line " << i / 3;
  }
  EXPECT_FALSE(in >> word) << "extra output '" << word << "'";
  return r;
}

fs::path writeNodeVectors(const std::string& name, const Eigen::VectorXd& v) {
  const fs::path path = fs::temp_directory_path() / "tt_cli_scene" / name;
  std::ofstream out(path);
  out.precision(17);
  out << "# x y z per node\n";
  for (int n = 0; n < v.size() / 3; ++n)
    out << v[3 * n] << " " << v[3 * n + 1] << " " << v[3 * n + 2] << "\n";
  return path;
}

fs::path writeForcesScene() {
  const fs::path dir = fs::temp_directory_path() / "tt_cli_scene";
  fs::create_directories(dir);
  std::ofstream(dir / "block.yaml") << kForcesScene;
  return dir / "block.yaml";
}

// Energy against central differences along d, stiffness_times against central differences of
// the printed forces; at the placed rest positions energy and forces vanish (gravity is left
// out: its weight would be ~2e-3 N per node).
TEST(Cli, ForcesOfASceneAgreeWithFiniteDifferences) {
  const fs::path scene = writeForcesScene();
  const Scene loaded = loadScene(scene.string());
  const int n = loaded.system.numNodes();
  ASSERT_EQ(n, 36);
  const Eigen::VectorXd rest = loaded.system.mesh.rest.reshaped();
  Eigen::VectorXd x = rest, d(rest.size());
  for (int i = 0; i < x.size(); ++i) {
    x[i] += 0.004 * std::sin(37.0 * rest[i] + 0.7 * i);  // ~10 % strains on a 1-cm cell
    d[i] = 0.01 * std::cos(1.9 * i);
  }
  const std::string common = "forces --scene " + scene.string() + " --deformed ";

  const Result atRest = runCli(common + writeNodeVectors("rest.txt", rest).string());
  ASSERT_EQ(atRest.exitCode, 0) << atRest.err;
  const ForcesOutput r0 = parseForces(atRest.out, n, false);
  EXPECT_LT(std::abs(r0.energy), 1e-15);
  EXPECT_LT(r0.force.cwiseAbs().maxCoeff(), 1e-10);

  const Result at = runCli(common + writeNodeVectors("x.txt", x).string() + " --stiffness-times " +
                           writeNodeVectors("d.txt", d).string());
  ASSERT_EQ(at.exitCode, 0) << at.err;
  const ForcesOutput r = parseForces(at.out, n, true);
  EXPECT_GT(r.energy, 0.0);

  const double h = 1e-4;  // moves nodes by ~1e-6 m
  const Result plus = runCli(common + writeNodeVectors("xp.txt", x + h * d).string());
  const Result minus = runCli(common + writeNodeVectors("xm.txt", x - h * d).string());
  ASSERT_EQ(plus.exitCode, 0) << plus.err;
  ASSERT_EQ(minus.exitCode, 0) << minus.err;
  const ForcesOutput rp = parseForces(plus.out, n, false), rm = parseForces(minus.out, n, false);
  const double slope = (rp.energy - rm.energy) / (2.0 * h);
  EXPECT_NEAR(slope, -r.force.dot(d), 1e-6 * std::abs(r.force.dot(d)));
  const Eigen::VectorXd dfdx_d = (rp.force - rm.force) / (2.0 * h);
  EXPECT_LT((r.stiffnessTimes + dfdx_d).norm(), 1e-6 * r.stiffnessTimes.norm());
  // H is symmetric: d . H x_dir == x_dir . H d is not checked here (one direction); but H d
  // must be positive along d for this mildly stretched, stable state.
  EXPECT_GT(d.dot(r.stiffnessTimes), 0.0);
}

// The flag form with --stiffness-times gives the assembled -K d of the model.
// The number after `key` on its own line of `out` (NaN when the line is missing).
double valueAfter(const std::string& out, const std::string& key) {
  const size_t at = out.find("\n" + key + " ");
  if (at == std::string::npos) return std::nan("");
  return std::stod(out.substr(at + key.size() + 2));
}

// `info SCENE.yaml`: the placed mesh's report, then the critical step of the Adamss chapter,
// Eq. 2.150. The block's edges are 1 cm scaled by 1.5; its fastest wave is the first
// material's along the fibre, sqrt((lambda_L + 2 mu_L) / rho) with E_L = 9 kPa, nu_L = 0.3.
TEST(Cli, InfoOfASceneGivesShortestEdgeWaveSpeedAndCriticalStep) {
  const fs::path scene = writeForcesScene();
  const Result r = runCli("info " + scene.string());
  ASSERT_EQ(r.exitCode, 0) << r.err;
  EXPECT_NE(r.out.find("scene forces_block"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("nodes 36, tets"), std::string::npos) << r.out;
  const double edge = valueAfter(r.out, "shortest_edge");
  const double c = valueAfter(r.out, "wave_speed");
  const double hc = valueAfter(r.out, "critical_step");
  const double lambdaL = 9000.0 * 0.3 / (1.3 * 0.4), muL = 9000.0 / 2.6;
  const double expectedC = std::sqrt((lambdaL + 2.0 * muL) / 1000.0);
  EXPECT_NEAR(edge, 0.015, 1e-8) << r.out;
  EXPECT_NEAR(c, expectedC, 1e-5 * expectedC) << r.out;
  EXPECT_NEAR(hc, 0.015 / expectedC, 1e-5 * hc) << r.out;
  EXPECT_NE(r.out.find("P-wave sqrt((lambda + 2 mu) / rho), the fastest material: 0"),
            std::string::npos)
      << r.out;
  const Result bad = runCli("info " + (scene.parent_path() / "none.yaml").string());
  EXPECT_EQ(bad.exitCode, 2);
}

TEST(Cli, FlagFormStiffnessTimesIsMinusKd) {
  Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d(0.02, 0.02, 0.02), TetSplit::kFiveMirrored);
  const fs::path dir = fs::temp_directory_path() / "tt_cli_scene";
  fs::create_directories(dir);
  writeMesh((dir / "box.vtu").string(), mesh);
  const Mesh read = readMesh((dir / "box.vtu").string());
  Eigen::VectorXd x = read.rest.reshaped(), d(x.size());
  for (int i = 0; i < x.size(); ++i) {
    x[i] *= 1.0 + 0.05 * std::sin(1.3 * i);
    d[i] = std::cos(0.7 * i);
  }
  const Result r = runCli("forces --mesh " + (dir / "box.vtu").string() + " --deformed " +
                          writeNodeVectors("flag_x.txt", x).string() + " --stiffness-times " +
                          writeNodeVectors("flag_d.txt", d).string() +
                          " --model stvk_displacement --lambda 2000 --mu 1000");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const ForcesOutput out = parseForces(r.out, read.numNodes(), true);
  Mesh one = read;
  one.material.assign(one.numTets(), 0);
  ElasticConstants k;
  k.lambda = k.lambdaL = 2000.0;
  k.mu = k.muL = 1000.0;
  const Material m = Material::withConstants(k, 1000.0);
  const StvkDisplacementModel model(one, {m});
  const SparsePattern pattern(one.numNodes(), one.tets);
  SparseMatrix K = pattern.zeroMatrix();
  model.addStiffness(x, 1.0, pattern, K);
  const Eigen::VectorXd expected = -(K * d);
  EXPECT_LT((out.stiffnessTimes - expected).norm(), 1e-12 * expected.norm());
}

// A hex mesh in the flag form: the hyperelastic preset's K d over the hexes' pattern, and a
// tet-only model refused in one line.
TEST(Cli, FlagFormOnAHexMesh) {
  const Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d(0.02, 0.02, 0.02), TetSplit::kNone);
  const fs::path dir = fs::temp_directory_path() / "tt_cli_hex";
  fs::create_directories(dir);
  writeMesh((dir / "hex.vtu").string(), mesh);
  const Mesh read = readMesh((dir / "hex.vtu").string());
  ASSERT_EQ(read.numHexes(), 8);
  Eigen::VectorXd x = read.rest.reshaped(), d(x.size());
  for (int i = 0; i < x.size(); ++i) {
    x[i] *= 1.0 + 0.05 * std::sin(1.3 * i);
    d[i] = std::cos(0.7 * i);
  }
  const std::string files = " --deformed " + writeNodeVectors("hex_x.txt", x).string() +
                            " --stiffness-times " + writeNodeVectors("hex_d.txt", d).string() +
                            " --lambda 2000 --mu 1000 --mesh " + (dir / "hex.vtu").string();
  const Result r = runCli("forces --model hyperelastic_neo_hookean" + files);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const ForcesOutput out = parseForces(r.out, read.numNodes(), true);
  ElasticConstants k;
  k.lambda = k.lambdaL = 2000.0;
  k.mu = k.muL = 1000.0;
  const Material m = Material::withConstants(k, 1000.0);
  const auto model = makeElasticModel("hyperelastic_neo_hookean", read, {m});
  const SparsePattern pattern = meshPattern(read);
  SparseMatrix K = pattern.zeroMatrix();
  model->addStiffness(x, 1.0, pattern, K);
  const Eigen::VectorXd expected = -(K * d);
  EXPECT_LT((out.stiffnessTimes - expected).norm(), 1e-12 * expected.norm());

  const Result refused = runCli("forces --model edge_length" + files);
  EXPECT_EQ(refused.exitCode, 2);
  EXPECT_NE(refused.err.find("covers tetrahedra only"), std::string::npos) << refused.err;
  EXPECT_EQ(std::count(refused.err.begin(), refused.err.end(), '\n'), 1) << refused.err;
}

TEST(Cli, ForcesOfASceneRejectBadInputInOneLine) {
  const fs::path scene = writeForcesScene();
  const std::string sceneArg = "forces --scene " + scene.string();
  const fs::path dir = scene.parent_path();
  std::string lines;
  for (int k = 0; k < 35; ++k) lines += "0 0 0\n";
  std::ofstream(dir / "short.txt") << lines;
  std::ofstream(dir / "word.txt") << "0 0 0\n\n1 abc 2\n";
  std::ofstream(dir / "four.txt") << "0 0 0 0\n";
  std::ofstream(dir / "long.txt") << lines << "0 0 0\n0 0 0\n";
  struct Case {
    std::string arguments, error;
  };
  const std::string good = (dir / "x.txt").string();
  writeNodeVectors("x.txt", Eigen::VectorXd::Zero(3 * 36));
  const std::vector<Case> cases = {
      {sceneArg + " --deformed " + (dir / "short.txt").string(),
       (dir / "short.txt").string() + ":35: expected 36 lines (one per mesh node), found 35"},
      {sceneArg + " --deformed " + (dir / "long.txt").string(),
       (dir / "long.txt").string() + ":37: expected 36 lines (one per mesh node), found more"},
      {sceneArg + " --deformed " + (dir / "word.txt").string(),
       (dir / "word.txt").string() + ":3: expected a finite number, got 'abc'"},
      {sceneArg + " --deformed " + (dir / "four.txt").string(),
       (dir / "four.txt").string() + ":1: expected 3 numbers 'x y z'"},
      {sceneArg + " --deformed " + (dir / "missing.txt").string(),
       (dir / "missing.txt").string() + ": cannot open the positions file"},
      {sceneArg + " --deformed " + good + " --stiffness-times " + (dir / "word.txt").string(),
       (dir / "word.txt").string() + ":3: expected a finite number, got 'abc'"},
      {"forces --scene " + (dir / "none.yaml").string() + " --deformed " + good,
       (dir / "none.yaml").string() + ": cannot open the scene file"},
      {sceneArg + " --deformed " + good + " --frobnicate 1", "tissue_cli: unknown option --frobnicate"},
      {sceneArg + " --deformed " + good + " --model edge_length",
       "tissue_cli: --model belongs to the --mesh form, not to --scene"},
      {sceneArg, "tissue_cli: missing --deformed"}};
  for (const Case& c : cases) {
    const Result r = runCli(c.arguments);
    EXPECT_EQ(r.exitCode, 2) << c.arguments;
    EXPECT_EQ(r.err.rfind(c.error, 0), 0u) << c.arguments << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

// --- forces --model teran_muscle ------------------------------------------------------------

struct MuscleCase {
  Mesh mesh;
  std::string files;  // --mesh, --deformed, --stiffness-times
  Eigen::VectorXd x, d;
};

// A 2 cm box of tets compressed along z by `squash` (0.6: compressed; -0.3: every tet
// inverted) with a smooth wobble, and a direction d.
MuscleCase muscleCase(const std::string& tag, double squash) {
  MuscleCase c;
  const fs::path dir = fs::temp_directory_path() / "tt_cli_scene";
  fs::create_directories(dir);
  writeMesh((dir / "muscle.vtu").string(),
            boxGrid(3, 3, 3, Eigen::Vector3d(0.02, 0.02, 0.02), TetSplit::kFiveMirrored));
  c.mesh = readMesh((dir / "muscle.vtu").string());
  c.x = c.mesh.rest.reshaped();
  c.d.resize(c.x.size());
  for (int i = 0; i < c.x.size(); ++i) {
    if (i % 3 == 2) c.x[i] *= squash;
    c.x[i] += 0.001 * std::sin(1.3 * i);
    c.d[i] = std::cos(0.7 * i);
  }
  c.files = " --mesh " + (dir / "muscle.vtu").string() + " --deformed " +
            writeNodeVectors(tag + "_x.txt", c.x).string() + " --stiffness-times " +
            writeNodeVectors(tag + "_d.txt", c.d).string();
  return c;
}

const char* const kMuscleFlags =
    " --model teran_muscle --mooney-rivlin 6e4 2e4 --bulk 6e4 --peak-stress 3e5"
    " --activation 0.6 --fiber 1 2 2";

// The core model the flags describe: fibre (1, 2, 2)/3 in every tet.
HyperelasticModel<TeranMuscleLaw> muscleModel(Mesh mesh, bool deviatoric, double threshold,
                                              bool psd,
                                              PsdMethod method = PsdMethod::kEigen) {
  for (Eigen::Matrix3d& frame : mesh.fibreFrame) frame.col(0) = Eigen::Vector3d(1, 2, 2) / 3.0;
  mesh.material.assign(mesh.numTets(), 0);
  TeranMuscleLaw::Constants k;  // 6e4, 2e4, 6e4, 3e5
  k.activation = 0.6;
  k.deviatoricStretch = deviatoric;
  return HyperelasticModel<TeranMuscleLaw>(mesh, {k}, {threshold, psd, method});
}

// Energy, forces and H d of the flag form are the core model's (threshold 0.25 by default),
// with --psd the projected H d (each --psd-method), on compressed and inverted states, for both
// fibre stretches.
TEST(Cli, FlagFormTeranMuscleIsTheCoreLaw) {
  for (double squash : {0.6, -0.3}) {
    const MuscleCase c = muscleCase(squash > 0 ? "compressed" : "inverted", squash);
    for (bool deviatoric : {true, false}) {
      for (int variant = 0; variant < 3; ++variant) {  // no projection, eigen, diagonal_blocks
        const bool psd = variant > 0;
        const PsdMethod method = variant == 2 ? PsdMethod::kDiagonalBlocks : PsdMethod::kEigen;
        const std::string flags = c.files + kMuscleFlags + " --fiber-stretch " +
                                  (deviatoric ? "deviatoric" : "nondeviatoric") +
                                  (psd ? " --psd" : "") +
                                  (variant == 2 ? " --psd-method diagonal_blocks" : "");
        const Result r = runCli("forces" + flags);
        ASSERT_EQ(r.exitCode, 0) << r.err;
        const ForcesOutput out = parseForces(r.out, c.mesh.numNodes(), true);
        const auto model = muscleModel(c.mesh, deviatoric, 0.25, psd, method);
        Eigen::VectorXd f = Eigen::VectorXd::Zero(c.x.size());
        const double energy = model.addForce(c.x, Eigen::VectorXd::Zero(c.x.size()), f);
        Eigen::VectorXd Hd = Eigen::VectorXd::Zero(c.x.size());
        model.addStiffnessTimes(c.x, c.d, -1.0, Hd);
        ASSERT_TRUE(out.force.allFinite() && out.stiffnessTimes.allFinite());
        EXPECT_NEAR(out.energy, energy, 1e-14 * std::abs(energy));
        EXPECT_LT((out.force - f).norm(), 1e-14 * f.norm());
        EXPECT_LT((out.stiffnessTimes - Hd).norm(), 1e-14 * Hd.norm());
        if (psd) EXPECT_GE(c.d.dot(out.stiffnessTimes), 0.0);
      }
    }
    // --inversion-threshold 0 on the inverted box: the bare law, an infinite energy.
    if (squash < 0) {
      const Result bare = runCli("forces" + c.files + kMuscleFlags +
                                 " --fiber-stretch deviatoric --inversion-threshold 0");
      ASSERT_EQ(bare.exitCode, 0) << bare.err;
      EXPECT_EQ(bare.out.rfind("energy inf", 0), 0u) << bare.out.substr(0, 40);
    }
  }
}

// At rest with alpha = 0 no force, and the energy is V 3 (A + B) (Eq. 10's constant).
TEST(Cli, FlagFormTeranMuscleAtRestHasTheConstantEnergy) {
  const MuscleCase c = muscleCase("rest", 1.0);
  const fs::path dir = fs::temp_directory_path() / "tt_cli_scene";
  const Eigen::VectorXd rest = c.mesh.rest.reshaped();
  const Result r = runCli("forces --mesh " + (dir / "muscle.vtu").string() + " --deformed " +
                          writeNodeVectors("rest_x.txt", rest).string() +
                          " --model teran_muscle --mooney-rivlin 5e3 1e3 --bulk 1e5"
                          " --peak-stress 3e5 --activation 0 --fiber 0 0 1"
                          " --fiber-stretch nondeviatoric");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const ForcesOutput out = parseForces(r.out, c.mesh.numNodes(), false);
  const double volume = 0.02 * 0.02 * 0.02;
  EXPECT_NEAR(out.energy, volume * 3.0 * (5e3 + 1e3), 1e-12 * out.energy);
  EXPECT_LT(out.force.cwiseAbs().maxCoeff(), 1e-12);
}

TEST(Cli, FlagFormTeranMuscleRejectsBadFlagsInOneLine) {
  const MuscleCase c = muscleCase("bad", 0.9);
  // The good flags with one replaced (value "" drops it).
  const auto with = [&](const std::string& flag, const std::string& value) {
    const std::vector<std::pair<std::string, std::string>> good = {
        {"model", "teran_muscle"}, {"mooney-rivlin", "6e4 2e4"}, {"bulk", "6e4"},
        {"peak-stress", "3e5"},    {"activation", "0.6"},        {"fiber", "1 2 2"},
        {"fiber-stretch", "deviatoric"}};
    std::string args = c.files;
    for (const auto& [name, v] : good) {
      const std::string use = name == flag ? value : v;
      if (!use.empty()) args += " --" + name + " " + use;
    }
    if (flag.rfind("extra ", 0) == 0) args += " " + flag.substr(6) + " " + value;
    return args;
  };
  struct Case {
    std::string arguments, error;
  };
  const std::vector<Case> cases = {
      {with("bulk", ""), "tissue_cli: missing --bulk"},
      {with("fiber-stretch", ""), "tissue_cli: missing --fiber-stretch"},
      {with("fiber", ""), "tissue_cli: missing --fiber"},
      {with("fiber-stretch", "isochoric"),
       "tissue_cli: --fiber-stretch expects deviatoric or nondeviatoric, got 'isochoric'"},
      {with("activation", "1.5"), "tissue_cli: --activation expects a value in [0, 1], got '1.5'"},
      {with("bulk", "-1"), "tissue_cli: --bulk expects a value >= 0, got '-1'"},
      {with("peak-stress", "soft"), "tissue_cli: --peak-stress expects a finite number, got 'soft'"},
      {with("extra --inversion-threshold", "1"),
       "tissue_cli: --inversion-threshold expects a value in [0, 1) (0 turns it off), got '1'"},
      {with("extra --mu", "1000"), "tissue_cli: --mu does not apply to --model teran_muscle"},
      {with("fiber", "0 0 0"), "tissue_cli: --fiber expects a non-zero direction"},
      {c.files + " --fiber 1 2 2 --fiber-stretch deviatoric --mooney-rivlin 6e4",
       "tissue_cli: --mooney-rivlin expects 2 value(s)"},
      {c.files + " --model hyperelastic_neo_hookean --lambda 2000 --mu 1000 --psd",
       "tissue_cli: --psd applies to --model teran_muscle only"},
      {with("extra --psd-method", "diagonal_blocks"), "tissue_cli: --psd-method applies with --psd only"},
      {with("extra --psd --psd-method", "newton"),
       "tissue_cli: --psd-method expects eigen or diagonal_blocks, got 'newton'"},
  };
  for (const Case& k : cases) {
    const Result r = runCli("forces" + k.arguments);
    EXPECT_EQ(r.exitCode, 2) << k.arguments;
    EXPECT_EQ(r.err.rfind(k.error, 0), 0u) << k.arguments << "\n" << r.err;
    EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
  }
}

// A tissue preset in the flag form: the forces of its models together, the material's E and nu
// from --lambda and --mu; `models` lists it and an unknown name's error names it.
TEST(Cli, FlagFormTakesATissuePreset) {
  const Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d(0.02, 0.02, 0.02), TetSplit::kFiveMirrored);
  const fs::path dir = fs::temp_directory_path() / "tt_cli_scene";
  fs::create_directories(dir);
  writeMesh((dir / "tissue.vtu").string(), mesh);
  Mesh read = readMesh((dir / "tissue.vtu").string());
  Eigen::VectorXd x = read.rest.reshaped();
  for (int i = 0; i < x.size(); ++i) x[i] *= 1.0 + 0.03 * std::sin(1.3 * i);
  const std::string files = " --mesh " + (dir / "tissue.vtu").string() + " --deformed " +
                            writeNodeVectors("tissue_x.txt", x).string();
  const Result r = runCli("forces --model adamss_hunter --lambda 2000 --mu 1000" + files);
  ASSERT_EQ(r.exitCode, 0) << r.err;
  const ForcesOutput out = parseForces(r.out, read.numNodes(), false);
  read.material.assign(read.numTets(), 0);
  ElasticConstants k;
  k.lambda = k.lambdaL = 2000.0;
  k.mu = k.muL = 1000.0;
  Material m = Material::withConstants(k, 1000.0);
  m.moduli = IsotropicModuli::fromLame(2000.0, 1000.0);
  const auto models = makePresetModels("adamss_hunter", read, {m});
  EXPECT_EQ(models.size(), 2u) << "the Hunter law and the volume term";
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  for (const auto& model : models) model->addForce(x, Eigen::VectorXd::Zero(x.size()), f);
  EXPECT_GT(f.norm(), 0.0);
  EXPECT_LT((out.force - f).norm(), 1e-12 * f.norm());

  const Result listed = runCli("models");
  ASSERT_EQ(listed.exitCode, 0) << listed.err;
  for (const TissuePreset& t : registry().tissuePresets())
    EXPECT_NE(listed.out.find("tissue_preset " + t.name + ": " + t.description + "\n"),
              std::string::npos) << t.name;
  const Result unknown = runCli("forces --model adamss_hunterr --lambda 2000 --mu 1000" + files);
  EXPECT_EQ(unknown.exitCode, 2);
  EXPECT_NE(unknown.err.find("adamss_springs"), std::string::npos) << unknown.err;
  EXPECT_EQ(std::count(unknown.err.begin(), unknown.err.end(), '\n'), 1) << unknown.err;
}

// `models` prints every registered entry and each of its keys.
TEST(Cli, ModelsListsEveryRegisteredEntryWithItsKeys) {
  const Result r = runCli("models");
  ASSERT_EQ(r.exitCode, 0) << r.err;
  // The lines of one entry: its head line and the indented lines below it.
  auto expectBlock = [&](const std::string& head, const std::vector<KeyDoc>& keys) {
    const size_t at = r.out.find(head);
    ASSERT_NE(at, std::string::npos) << head << "\n" << r.out;
    size_t end = r.out.find('\n', at);
    while (end != std::string::npos && r.out.compare(end + 1, 2, "  ") == 0)
      end = r.out.find('\n', end + 1);
    const std::string block = r.out.substr(at, end == std::string::npos ? end : end - at + 1);
    for (const KeyDoc& k : keys)
      EXPECT_NE(block.find("\n  key " + k.key + ": " + k.description + "\n"), std::string::npos)
          << head << " lacks key " << k.key << "\n" << block;
  };
  for (const auto& m : registry().forceModels()) {
    expectBlock("force_model " + m.name + ": " + m.description + "\n", m.keys);
    for (const auto& p : m.presets) EXPECT_NE(r.out.find("  preset " + p.name), std::string::npos);
  }
  for (const auto& l : registry().laws()) expectBlock("law " + l.name + ": ", l.materialKeys);
  for (const auto& i : registry().integrators())
    expectBlock("integrator " + i.name + ": " + i.description + "\n", i.keys);
}

}  // namespace
}  // namespace tt
#endif  // TT_CLI_PATH
