// The start of bench_bullet_liver, computed in a process of its own: our contact
// (TissueContact) links the single-precision Bullet, which cannot share a process with the
// double-precision Bullet that bench_bullet_liver steps (both export the same symbols).
//
// As bench_implicit_step prepares its rows: the liver palpation scene (config/scenes/
// liver_palpation.yaml) on its liver refined by TetGen (tetgen -r<SWITCHES>Q, e.g. q1.4a0.1:
// the same surface, more tets; "none": the scene's own 596-tet liver) sags to rest under
// gravity (3 s in steps of 0.1 s, backward Euler solved to 1e-10, then the velocity zeroed);
// a 6 mm sphere is pressed 6 mm into the highest point of the anterior face near the trocar
// axis and the liver is stepped 10 times (10 ms) with the contact re-queried each step; at
// that pressed state one more query gives the contact force on every node.
// Writes DIR/scene.yaml (the scene on the mesh) and DIR/state.txt: the scene's path, then
// per node the sagged position and the pressed contact force:
//   scene PATH
//   nodes N
//   x y z fx fy fz          (N lines, m and N)
//   bench_bullet_liver_state --out DIR --tetgen SWITCHES
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "common/liver_bench_scene.h"
#include "tissue_trainer/core/contact/tissue_contact.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/scene.h"

namespace {

using namespace tt;
namespace fs = std::filesystem;
using bench::sourceDir;

constexpr double kToolRadius = 0.006, kToolDepth = 0.006, kStep = 0.01;

// liver.msh refined by `tetgen -r<switches>Q` in dir; throws when TetGen fails.
std::string refinedLiver(const fs::path& dir, const std::string& switches) {
  writeMesh((dir / "liver.node").string(), readMesh(sourceDir() + "/config/meshes/liver.msh"));
  const std::string command = "cd '" + dir.string() + "' && tetgen -r" + switches +
                              "Q liver > tetgen.log 2>&1";
  if (std::system(command.c_str()) != 0 || !fs::exists(dir / "liver.1.ele"))
    throw std::runtime_error("tetgen -r" + switches + " failed (see " + (dir / "tetgen.log").string() + ")");
  return (dir / "liver.1.ele").string();
}

void writeState(const fs::path& path, const std::string& scene, const Eigen::VectorXd& x,
                const Eigen::VectorXd& force) {
  FILE* out = std::fopen(path.c_str(), "w");
  if (!out) throw std::runtime_error("cannot write " + path.string());
  std::fprintf(out, "scene %s\nnodes %d\n", scene.c_str(), static_cast<int>(x.size() / 3));
  for (int i = 0; i < x.size(); i += 3)
    std::fprintf(out, "%.17g %.17g %.17g %.17g %.17g %.17g\n", x[i], x[i + 1], x[i + 2],
                 force[i], force[i + 1], force[i + 2]);
  std::fclose(out);
}

int run(const fs::path& dir, const std::string& switches) {
  setThreadCount(1);
  fs::create_directories(dir);
  const std::string mesh = switches == "none" ? sourceDir() + "/config/meshes/liver.msh"
                                              : refinedLiver(dir, switches);
  const fs::path scenePath = dir / "scene.yaml";
  bench::writeLiverSceneWithMesh(mesh, scenePath.string());
  Scene scene = loadScene(scenePath.string());
  System& system = scene.system;

  BackwardEulerIntegrator settle(bench::tightBackwardEuler());
  bench::sagToRest(system, settle);
  const Eigen::VectorXd sagged = system.state.x;

  ToolShape sphere;
  sphere.type = ToolShape::Type::kSphere;
  sphere.radius = kToolRadius;
  sphere.link = "tip";
  TissueContact contact(system, *scene.contact, {sphere});
  const Eigen::Isometry3d pose = bench::pressingPose(system, kToolRadius, kToolDepth);
  contact.setTool(pose, {pose}, 1.0, system.state.t);
  for (int s = 0; s < 10; ++s) {
    contact.update();
    settle.advance(system, kStep);
  }
  const size_t points = contact.update().points.size();
  Eigen::VectorXd force = Eigen::VectorXd::Zero(system.numDofs());
  contact.model().addForce(system.state.x, system.state.v, force);

  writeState(dir / "state.txt", scenePath.string(), sagged, force);
  std::printf("liver %d tets, %d nodes; sphere at (%.4f, %.4f, %.4f) m; pressed state: %zu contact "
              "points, total contact force %.4f N\n", system.mesh.numTets(), system.numNodes(),
              pose.translation().x(), pose.translation().y(), pose.translation().z(), points,
              force.reshaped(3, system.numNodes()).rowwise().sum().norm());
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  tt::tools::CommandLine args(argc, argv,
                              "bench_bullet_liver_state --out DIR --tetgen SWITCHES (TetGen's, "
                              "e.g. q1.4a0.1, or none)");
  const std::string out = args.text("--out", "");
  const std::string tetgen = args.text("--tetgen", "");
  args.finish();
  if (out.empty() || tetgen.empty()) args.fail("--out and --tetgen are required");
  try {
    return run(out, tetgen);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_bullet_liver_state: %s\n", e.what());
    return 1;
  }
}
