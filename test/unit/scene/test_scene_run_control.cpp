// Simulation control of a scene run ("Adamss: Advanced Anisotropic Mass-Spring System",
// Sec. 2.2): the stop conditions (t_max, the kinetic energy below a threshold, an interrupt)
// and the exported data (the CSV's barycentre and volumes, the VTU series and its .pvd).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "../csv_test_util.h"
#include "cavity_test_util.h"
#include "scene_test_util.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/model/adamss/cavity.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/scene/scene_runner.h"

namespace tt {
namespace {

namespace fs = std::filesystem;
using testutil::replaced;
using testutil::writeScene;

// A 2 x 2 x 4 cm block clamped at z = 0, hanging under gravity with mass damping.
const char* const kRunControlBlock = R"(name: block
mesh: {generator: box, nodes: [3, 3, 4], size: [0.02, 0.02, 0.04]}
materials: [{young_modulus: 5000, poisson_ratio: 0.3, density: 1000}]
force_models: [{type: tensor_mass}]
integrator: {type: backward_euler}
boundary: {fixed: [{plane: {point: [0, 0, 0], normal: [0, 0, 1]}}]}
loads: {gravity: [0, 0, -9.81], rayleigh_mass: 30}
run: {frame_time: 0.01, duration: 2.0, stop_kinetic_energy: 1.0e-9}
output: {vtu_every: 5, csv: true}
)";

fs::path outDir(const std::string& name) {
  const fs::path dir = fs::temp_directory_path() / "tt_run_control" / name;
  fs::remove_all(dir);
  return dir;
}

// Column `name` of the CSV rows (header first), as numbers.
std::vector<double> column(const std::vector<std::vector<std::string>>& rows,
                           const std::string& name) {
  const std::vector<std::string>& header = rows.at(0);
  const auto at = std::find(header.begin(), header.end(), name);
  EXPECT_NE(at, header.end()) << name;
  std::vector<double> values;
  if (at == header.end()) return values;
  for (size_t r = 1; r < rows.size(); ++r) values.push_back(std::stod(rows[r].at(at - header.begin())));
  return values;
}

std::string fileText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The values of the VTU point-data array `name` (3 per node).
std::vector<double> vtuArray(const fs::path& path, const std::string& name) {
  const std::string text = fileText(path);
  const size_t head = text.find("Name=\"" + name + "\"");
  EXPECT_NE(head, std::string::npos) << name;
  if (head == std::string::npos) return {};
  const size_t begin = text.find('>', head) + 1, end = text.find("</DataArray>", begin);
  std::istringstream in(text.substr(begin, end - begin));
  std::vector<double> values;
  for (double v; in >> v;) values.push_back(v);
  return values;
}

TEST(RunControl, StopsAtTheFirstFrameBelowTheKineticEnergyThreshold) {
  Scene scene = loadScene(writeScene("block.yaml", kRunControlBlock));
  ASSERT_TRUE(scene.kineticEnergyStop.has_value());
  EXPECT_EQ(scene.kineticEnergyStop->below, 1e-9);
  EXPECT_EQ(scene.kineticEnergyStop->notBefore, 0.0);
  RunOptions options;
  options.outDir = outDir("energy").string();
  const RunSummary summary = runScene(scene, options);
  ASSERT_TRUE(summary.ok) << summary.failure;
  EXPECT_EQ(summary.stop, StopReason::kKineticEnergy);
  EXPECT_STREQ(stopReasonName(summary.stop), "kinetic_energy");
  EXPECT_GT(summary.frames, 5);
  EXPECT_LT(summary.frames, 200);  // settled long before t_max
  EXPECT_LT(summary.last.kineticEnergy, 1e-9);

  // The CSV agrees: every earlier frame is at or above the threshold, the last one below.
  const auto rows = test::readCsv(fs::path(options.outDir) / "block.csv");
  const std::vector<double> kinetic = column(rows, "kinetic_energy");
  ASSERT_EQ(static_cast<int>(kinetic.size()), summary.frames);
  for (size_t k = 0; k + 1 < kinetic.size(); ++k) EXPECT_GE(kinetic[k], 1e-9) << "frame " << k + 1;
  EXPECT_LT(kinetic.back(), 1e-9);
  // The frame the run stops on is written even though it is not a multiple of vtu_every.
  char last[32];
  std::snprintf(last, sizeof last, "block_%06d.vtu", summary.frames);
  EXPECT_TRUE(fs::exists(fs::path(options.outDir) / last)) << last;
}

TEST(RunControl, TheKineticEnergyStopWaitsForItsStartTime) {
  // At rest (no gravity) the kinetic energy is 0 from the first frame: the run stops at the
  // first frame ending at or after stop_not_before, or at t_max without the stop.
  const std::string still = replaced(kRunControlBlock, "gravity: [0, 0, -9.81], ", "");
  Scene early = loadScene(writeScene("still.yaml", still));
  EXPECT_EQ(runScene(early, {}).frames, 1);
  // Ten frames of 0.01 s end at 0.09999999999999999 s: the frame ending at 0.1 up to round-off
  // counts.
  for (const char* start : {"0.045", "0.05", "0.1"}) {
    Scene waiting = loadScene(writeScene(
        "wait.yaml", replaced(still, "stop_kinetic_energy: 1.0e-9",
                              std::string("stop_kinetic_energy: 1.0e-9, stop_not_before: ") + start)));
    const RunSummary waited = runScene(waiting, {});
    EXPECT_EQ(waited.stop, StopReason::kKineticEnergy);
    const int frames = static_cast<int>(std::ceil(std::stod(start) / 0.01 - 1e-9));
    EXPECT_EQ(waited.frames, frames) << start;
    EXPECT_NEAR(waited.simulatedTime, 0.01 * frames, 1e-12);
  }
  Scene plain = loadScene(writeScene(
      "plain.yaml", replaced(still, ", stop_kinetic_energy: 1.0e-9", "")));
  EXPECT_FALSE(plain.kineticEnergyStop.has_value());
  const RunSummary full = runScene(plain, {0.1, "", nullptr});
  EXPECT_EQ(full.stop, StopReason::kDuration);
  EXPECT_EQ(full.frames, 10);
}

// run.settle_time: the block released under gravity is stepped to rest before a session
// starts; frames of at most the given length, the last one shortened to end on the time.
TEST(RunControl, SettlingStepsTheSceneToRestForItsSettleTime) {
  Scene scene = loadScene(writeScene("settle.yaml", replaced(kRunControlBlock, "duration: 2.0,", "duration: 2.0, settle_time: 0.55,")));
  EXPECT_EQ(scene.settleTime, 0.55);
  Scene fresh = loadScene(writeScene("block.yaml", kRunControlBlock));
  EXPECT_EQ(fresh.settleTime, 0.0);
  const double releasedKinetic = [&] {
    Scene released = loadScene(writeScene("block.yaml", kRunControlBlock));
    released.integrator->advance(released.system, 0.1);
    return measureFrame(released.system, 1, {}).kineticEnergy;
  }();

  const SettleSummary settled = settleScene(scene, scene.settleTime, 0.1);
  ASSERT_TRUE(settled.ok) << settled.failure;
  EXPECT_EQ(settled.frames, 6);  // five of 0.1 s and one of 0.05 s
  EXPECT_NEAR(settled.simulatedTime, 0.55, 1e-12);
  EXPECT_NEAR(scene.system.state.t, 0.55, 1e-12);
  const FrameLog after = measureFrame(scene.system, 0, {});
  EXPECT_GT(after.maxDisplacement, 1e-4);  // it sagged
  EXPECT_LT(after.kineticEnergy, 1e-3 * releasedKinetic);  // and came to rest

  EXPECT_THROW(settleScene(scene, 0.1, 0.0), std::invalid_argument);
  EXPECT_THROW(settleScene(scene, -1.0, 0.1), std::invalid_argument);
  EXPECT_EQ(settleScene(scene, 0.0, 0.1).frames, 0);
}

TEST(RunControl, AnInterruptEndsTheRunAfterTheFrameWithEveryOutput) {
  Scene scene = loadScene(writeScene("block.yaml", kRunControlBlock));
  RunOptions options;
  options.outDir = outDir("interrupt").string();
  int asked = 0;
  options.stopRequested = [&] { return ++asked == 3; };
  const RunSummary summary = runScene(scene, options);
  EXPECT_TRUE(summary.ok);
  EXPECT_EQ(summary.stop, StopReason::kInterrupt);
  EXPECT_EQ(summary.frames, 3);
  EXPECT_NEAR(summary.simulatedTime, 0.03, 1e-12);
  const fs::path dir(options.outDir);
  EXPECT_EQ(test::readCsv(dir / "block.csv").size(), 4u);  // header and three frames
  EXPECT_TRUE(fs::exists(dir / "block_000000.vtu"));
  EXPECT_TRUE(fs::exists(dir / "block_000003.vtu"));
  // The collection lists the frames written, with their times.
  const std::string pvd = fileText(dir / "block.pvd");
  const std::regex dataSet("<DataSet timestep=\"([^\"]+)\" file=\"([^\"]+)\"/>");
  std::vector<std::pair<double, std::string>> listed;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), dataSet); it != std::sregex_iterator(); ++it)
    listed.emplace_back(std::stod((*it)[1]), (*it)[2]);
  ASSERT_EQ(listed.size(), 2u) << pvd;
  EXPECT_EQ(listed[0].second, "block_000000.vtu");
  EXPECT_EQ(listed[0].first, 0.0);
  EXPECT_EQ(listed[1].second, "block_000003.vtu");
  EXPECT_NEAR(listed[1].first, 0.03, 1e-12);
}

// Frame 0 is the rest state: the elastic forces vanish, so the acceleration f / m is gravity
// on every free node and zero on the clamped ones; positions and offsets are the rest mesh
// and zero.
TEST(RunControl, TheVtuSeriesHoldsPositionsOffsetsVelocitiesAndAccelerations) {
  Scene scene = loadScene(writeScene("block.yaml", kRunControlBlock));
  const Mesh mesh = scene.system.mesh;
  RunOptions options;
  options.outDir = outDir("vtu").string();
  options.duration = 0.05;
  ASSERT_TRUE(runScene(scene, options).ok);
  const fs::path first = fs::path(options.outDir) / "block_000000.vtu";
  const std::vector<double> a = vtuArray(first, "acceleration");
  const std::vector<double> position = vtuArray(first, "position");
  const std::vector<double> offset = vtuArray(first, "displacement");
  ASSERT_EQ(static_cast<int>(a.size()), 3 * mesh.numNodes());
  ASSERT_EQ(position.size(), a.size());
  ASSERT_EQ(offset.size(), a.size());
  int clamped = 0;
  for (int i = 0; i < mesh.numNodes(); ++i) {
    const bool fixed = mesh.rest(2, i) == 0.0;
    clamped += fixed;
    EXPECT_EQ(a[3 * i], 0.0);
    EXPECT_EQ(a[3 * i + 1], 0.0);
    EXPECT_NEAR(a[3 * i + 2], fixed ? 0.0 : -9.81, 1e-9) << "node " << i;
    for (int k = 0; k < 3; ++k) {
      EXPECT_EQ(position[3 * i + k], mesh.rest(k, i));
      EXPECT_EQ(offset[3 * i + k], 0.0);
    }
  }
  EXPECT_EQ(clamped, 9);

  // Later frames: position = rest + offset, and the velocity is the state's.
  const fs::path fifth = fs::path(options.outDir) / "block_000005.vtu";
  const std::vector<double> x5 = vtuArray(fifth, "position"), u5 = vtuArray(fifth, "displacement");
  const std::vector<double> v5 = vtuArray(fifth, "velocity");
  ASSERT_EQ(v5.size(), a.size());
  for (int i = 0; i < mesh.numNodes(); ++i)
    for (int k = 0; k < 3; ++k) {
      EXPECT_NEAR(x5[3 * i + k], mesh.rest(k, i) + u5[3 * i + k], 1e-15);
      EXPECT_NEAR(v5[3 * i + k], scene.system.state.v[3 * i + k], 1e-15);
    }
  EXPECT_LT(*std::min_element(u5.begin(), u5.end()), -1e-6);  // the block sags
}

// A hollow box moved as a whole at 0.1 m/s along z: the centre of mass moves with it from the
// box's centre, and the total and cavity volumes stay those of the rest shape (hand-computed).
const char* const kHollow = R"(name: hollow
mesh: {file: MESH}
materials: [{young_modulus: 10, poisson_ratio: 0.3, stress_unit: kPa, density: 1000}]
force_models:
  - {type: hyperelastic, law: neo_hookean}
  - type: adamss_cavity
    surface: {box: {min: [0.0049, 0.0049, 0.0049], max: [0.0201, 0.0201, 0.0201]}}
    pressure: 0.5
    stress_unit: kPa
integrator: {type: backward_euler}
boundary:
  controlled: [{box: {min: [-1, -1, -1], max: [1, 1, 1]}, velocity: [0, 0, 0.1]}]
run: {frame_time: 0.01, duration: 0.05}
output: {csv: true}
)";

std::string hollowScene() {
  const fs::path mesh = fs::temp_directory_path() / "tt_run_control_hollow.msh";
  writeMesh(mesh.string(), testutil::hollowBox(5, 3, 0.005));
  return replaced(kHollow, "MESH", mesh.string());
}

TEST(RunControl, TheCsvLogsTheBarycentreTheVolumeAndEachCavity) {
  Scene scene = loadScene(writeScene("hollow.yaml", hollowScene()));
  RunOptions options;
  options.outDir = outDir("csv").string();
  ASSERT_TRUE(runScene(scene, options).ok);
  const auto rows = test::readCsv(fs::path(options.outDir) / "hollow.csv");
  const std::string header =
      "frame,time,kinetic_energy,elastic_energy,load_energy,volume_ratio,max_displacement,"
      "substeps,rejected,newton_iterations,linear_iterations,error_estimate,step_wall_s,ok,"
      "halvings,barycentre_x,barycentre_y,barycentre_z,volume,cavity_volume_0";
  std::string read;
  for (const std::string& name : rows.at(0)) read += (read.empty() ? "" : ",") + name;
  EXPECT_EQ(read, header);
  const std::vector<double> time = column(rows, "time");
  ASSERT_EQ(time.size(), 5u);
  const double wall = std::pow(0.025, 3) - std::pow(0.015, 3);
  for (size_t k = 0; k < time.size(); ++k) {
    EXPECT_NEAR(column(rows, "barycentre_x")[k], 0.0125, 1e-12);
    EXPECT_NEAR(column(rows, "barycentre_y")[k], 0.0125, 1e-12);
    EXPECT_NEAR(column(rows, "barycentre_z")[k], 0.0125 + 0.1 * time[k], 1e-12);
    EXPECT_NEAR(column(rows, "volume")[k], wall, 1e-15);
    EXPECT_NEAR(column(rows, "cavity_volume_0")[k], std::pow(0.015, 3), 1e-15);
    EXPECT_NEAR(column(rows, "volume_ratio")[k], 1.0, 1e-11);
  }
}

// Left free, the pressure inflates the cavity: the logged volume is the model's at the state.
TEST(RunControl, TheCavityColumnFollowsTheInflatedCavity) {
  Scene scene = loadScene(writeScene(
      "inflate.yaml",
      replaced(hollowScene(), "controlled: [{box: {min: [-1, -1, -1], max: [1, 1, 1]}, velocity: [0, 0, 0.1]}]",
               "fixed: [{plane: {point: [0, 0, 0], normal: [0, 0, 1]}}]")));
  RunOptions options;
  options.outDir = outDir("inflate").string();
  ASSERT_TRUE(runScene(scene, options).ok);
  const auto& cavity = dynamic_cast<const adamss::CavityModel&>(*scene.system.models.at(1));
  const std::vector<double> volume =
      column(test::readCsv(fs::path(options.outDir) / "hollow.csv"), "cavity_volume_0");
  ASSERT_EQ(volume.size(), 5u);
  EXPECT_GT(volume.front(), std::pow(0.015, 3) * (1 + 1e-6));
  EXPECT_GT(volume.back(), volume.front());
  EXPECT_NEAR(volume.back(), cavity.volume(scene.system.state.x), 1e-12 * volume.back());
}

}  // namespace
}  // namespace tt
