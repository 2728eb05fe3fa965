#include "common/liver_bench_scene.h"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <stdexcept>

#include "tissue_trainer/core/mesh/mesh_io.h"

namespace tt {
namespace bench {

std::string refinedLiver(const std::string& workDir, int target, int& tets) {
  if (std::system("command -v tetgen > /dev/null 2>&1") != 0) return "";
  const std::string dir = workDir + "/liver_" + std::to_string(target);
  if (std::system(("mkdir -p " + dir).c_str()) != 0) return "";
  writeMesh(dir + "/liver.node", readMesh(sourceDir() + "/config/meshes/liver.msh"));
  // The quality bound adds tets of its own: on liver.msh the count goes about as a^-0.6 with
  // the volume bound a (file units; 51,349 tets at a = 0.003), so a scales by ratio^1.7.
  double volume = 0.003 * std::pow(51349.0 / target, 1.7);
  for (int attempt = 0; attempt < 5; ++attempt) {
    char cmd[512];
    std::snprintf(cmd, sizeof cmd, "cd %s && tetgen -rq1.4a%.6gQ liver > tetgen.log 2>&1",
                  dir.c_str(), volume);
    if (std::system(cmd) != 0) return "";
    tets = readMesh(dir + "/liver.1.ele").numTets();
    const double ratio = static_cast<double>(tets) / target;
    if (ratio > 0.85 && ratio < 1.15) break;
    volume *= std::pow(ratio, 1.7);
  }
  return dir + "/liver.1.ele";
}

void writeLiverSceneWithMesh(const std::string& mesh, const std::string& path,
                             const std::vector<SceneEdit>& edits) {
  std::ifstream in(sourceDir() + "/config/scenes/liver_palpation.yaml");
  std::stringstream text;
  text << in.rdbuf();
  std::string scene = text.str();
  const auto replace = [&scene](const std::string& from, const std::string& to) {
    const size_t at = scene.find(from);
    if (at == std::string::npos) throw std::runtime_error("liver_palpation.yaml has no '" + from + "'");
    scene.replace(at, from.size(), to);
  };
  replace("file: ../meshes/liver.msh", "file: " + mesh);
  replace("file: ../meshes/liver-smooth.obj", "file: " + sourceDir() + "/config/meshes/liver-smooth.obj");
  for (const SceneEdit& e : edits) replace(e.from, e.to);
  std::ofstream out(path);
  out << scene;
  if (!out) throw std::runtime_error("cannot write " + path);
}

BackwardEulerParams tightBackwardEuler() { return jacobiBackwardEuler(1e-10, 20000); }

void sagToRest(System& system, BackwardEulerIntegrator& settle) {
  for (int s = 0; s < 30; ++s) settle.advance(system, 0.1);
  system.state.v.setZero();
}

Eigen::Isometry3d pressingPose(const System& system, double radius, double depth) {
  Eigen::Vector3d top(-0.035, 0.075, -1e9);
  for (int a = 0; a < system.numNodes(); ++a) {
    const Eigen::Vector3d p = system.state.x.segment<3>(3 * a);
    if (std::hypot(p.x() + 0.035, p.y() - 0.075) < 0.02 && p.z() > top.z()) top = p;
  }
  return Eigen::Isometry3d(Eigen::Translation3d(top + Eigen::Vector3d(0, 0, radius - depth)));
}

}  // namespace bench
}  // namespace tt
