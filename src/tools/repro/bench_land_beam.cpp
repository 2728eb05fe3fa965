// Problem 1 of Land et al., "Verification of cardiac mechanics software: benchmark problems
// and solutions for testing active and passive material behaviour" (Proc. R. Soc. A 2015,
// Sec. 2c): the beam x in [0, 10], y in [0, 1], z in [0, 1] mm, clamped at x = 0, the
// transversely isotropic Guccione law (C = 2 kPa, b_f = 8, b_t = 2, b_fs = 4, fibres along x)
// with the volumetric penalty of material/guccione.h, a follower pressure of 0.004 kPa on the
// bottom face z = 0 ramped linearly over the load steps, each solved by the quasistatic
// integrator. Prints the deformed z of the point (10, 0.5, 1) mm beside the consensus of the
// paper's Fig. 3 (4.17 mm; the converged submissions between about 4.15 and 4.19 mm), for meshes
// of 10n x n x n cells (n even, so the point is a node), with DOFs, Newton iterations and time.
//   bench_land_beam [--quick] [--cells N,N,...=2,4,6,8] [--split none|six_mirrored=none]
//                   [--bulk-modulus KPA=100] [--load-steps N=10]
// (--quick: n = 2 only; --split none: trilinear hexes, 2x2x2 Gauss points; six_mirrored:
// 6 linear tets per cell)
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "common/bench_support.h"
#include "tissue_trainer/core/integrate/integrator.h"
#include "tissue_trainer/core/scene/scene.h"

namespace {

using namespace tt;

constexpr double kConsensusZ = 4.17;  // mm, Fig. 3 of the paper

// The shipped scene (config/scenes/land_beam.yaml, 20 x 2 x 2 hexes, ten load steps) with its
// mesh, split, penalty and load steps replaced.
std::string beamScene(int n, const std::string& split, double bulkModulus, int loadSteps) {
  const std::filesystem::path path =
      std::filesystem::path(bench::sourceDir()) / "config" / "scenes" / "land_beam.yaml";
  std::ifstream file(path);
  std::stringstream text;
  text << file.rdbuf();
  std::string scene = text.str();
  const auto replace = [&scene, &path](const std::string& from, const std::string& to) {
    const size_t at = scene.find(from);
    if (at == std::string::npos)
      throw std::runtime_error(path.string() + ": expected '" + from + "' in the shipped scene");
    scene.replace(at, from.size(), to);
  };
  const std::string nodes = std::to_string(n + 1);
  replace("nodes: [21, 3, 3]", "nodes: [" + std::to_string(10 * n + 1) + ", " + nodes + ", " + nodes + "]");
  replace("split: none", "split: " + split);
  char number[64];
  std::snprintf(number, sizeof number, "bulk_modulus: %.17g", bulkModulus);
  replace("bulk_modulus: 100", number);
  std::snprintf(number, sizeof number, "frame_time: %.17g", 1.0 / loadSteps);
  replace("frame_time: 0.1", number);
  return scene;
}

struct BeamResult {
  int dofs = 0;
  int newton = 0;
  double z = 0.0;  // mm
  double seconds = 0.0;
  bool ok = true;
  std::string failure;
};

BeamResult solveBeam(int n, const std::string& split, double bulkModulus, int loadSteps) {
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("land_beam_" + std::to_string(n) + ".yaml");
  std::ofstream(path) << beamScene(n, split, bulkModulus, loadSteps);
  Scene scene = loadScene(path.string());
  System& s = scene.system;
  const Eigen::Vector3d probe(0.01, 0.0005, 0.001);
  int node = 0;
  for (int i = 1; i < s.numNodes(); ++i)
    if ((s.mesh.rest.col(i) - probe).norm() < (s.mesh.rest.col(node) - probe).norm()) node = i;
  BeamResult r;
  r.dofs = s.numDofs() - static_cast<int>(s.constrainedDofs.size());
  const auto start = std::chrono::steady_clock::now();
  for (int step = 0; step < loadSteps && r.ok; ++step) {
    const StepReport report = scene.integrator->advance(s, scene.frameTime);
    r.newton += report.newtonIterations;
    r.ok = report.ok;
    r.failure = report.failure;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.z = 1e3 * s.state.x[3 * node + 2];
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  tools::CommandLine cl(argc, argv,
                        "bench_land_beam [--quick] [--cells N,N,...] [--split none|six_mirrored] "
                        "[--bulk-modulus KPA] [--load-steps N]");
  const bool quick = cl.flag("--quick");
  const std::vector<std::string> cells =
      cl.list("--cells", quick ? std::vector<std::string>{"2"}
                               : std::vector<std::string>{"2", "4", "6", "8"});
  const std::string split = cl.text("--split", "none");
  const double bulk = cl.positiveNumber("--bulk-modulus", 100.0);
  const int loadSteps = cl.positiveInteger("--load-steps", 10);
  cl.finish();
  if (split != "none" && split != "six_mirrored")
    cl.fail("--split: expected none or six_mirrored, got '" + split + "'");
  std::vector<int> sizes;
  for (const std::string& c : cells) {
    const int n = std::atoi(c.c_str());
    if (n < 2 || n % 2 != 0) cl.fail("--cells: expected even integers >= 2, got '" + c + "'");
    sizes.push_back(n);
  }
  std::printf("Land et al. 2015, problem 1: z of (10, 0.5, 1) mm; split %s, bulk modulus %g kPa, "
              "%d load steps\n", split.c_str(), bulk, loadSteps);
  std::printf("%-12s %8s %8s %10s %10s %9s %8s\n", "cells", "DOFs", "Newton", "z (mm)",
              "consensus", "diff (%)", "time (s)");
  int failures = 0;
  for (int n : sizes) {
    const BeamResult r = solveBeam(n, split, bulk, loadSteps);
    const std::string label = std::to_string(10 * n) + "x" + std::to_string(n) + "x" + std::to_string(n);
    if (!r.ok) {
      std::printf("%-12s %8d failed: %s\n", label.c_str(), r.dofs, r.failure.c_str());
      ++failures;
      continue;
    }
    std::printf("%-12s %8d %8d %10.4f %10.2f %9.2f %8.2f\n", label.c_str(), r.dofs, r.newton, r.z,
                kConsensusZ, 100.0 * (r.z - kConsensusZ) / kConsensusZ, r.seconds);
  }
  return failures == 0 ? 0 : 1;
}
