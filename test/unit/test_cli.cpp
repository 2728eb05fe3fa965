// The tissue_cli contract (docs/cli.md): output format and exit codes.
// Only in the catkin build, which knows where tissue_cli is (TT_CLI_PATH).
#ifdef TT_CLI_PATH
#include <gtest/gtest.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/model/edge_length.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

struct Result {
  int exitCode;
  std::string out, err;
};

Result runCli(const std::string& arguments) {
  const fs::path errFile = fs::temp_directory_path() / "tt_cli_stderr.txt";
  const std::string command =
      std::string(TT_CLI_PATH) + " " + arguments + " 2>" + errFile.string();
  Result r;
  FILE* pipe = popen(command.c_str(), "r");
  char buffer[4096];
  size_t n;
  while ((n = fread(buffer, 1, sizeof buffer, pipe)) > 0) r.out.append(buffer, n);
  const int status = pclose(pipe);
  r.exitCode = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream err(errFile);
  r.err.assign(std::istreambuf_iterator<char>(err), {});
  return r;
}

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
  Material m;
  m.lambda = 2000, m.mu = 1000, m.lambdaL = 5000, m.muL = 3000;
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

}  // namespace
}  // namespace tt
#endif  // TT_CLI_PATH
