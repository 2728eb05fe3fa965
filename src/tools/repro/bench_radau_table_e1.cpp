// Table E.1 of Jeffrey, "A non-linear anisotropic Finite Element Method for surgical
// simulation": the Radau IIA integrator with the three Jacobian modes on a 4 x 4 x 4-node grid
// (27 hexes x 5 tets = 135 tets, 3 cm cube), bottom nodes fixed, the top corner node pulled
// sideways while gravity acts, edge-length StVK tissue with per-DOF damping. Per frame
// of 0.05 s: mean step h, Runge-Kutta steps, Jacobian evaluations, Newton iterations and LU
// factorizations (averages over frames), the median wall time per frame, and the largest
// position error against a tight-tolerance analytical-Jacobian run.
//   bench_radau_table_e1 [--quick] [--tolerance T=1e-5] [--frames N=20] [--repeats N=5]
//                        [--newton-tolerance K]
// (--quick: 2 frames, one repeat; --newton-tolerance: RadauOptions::newtonTolerance, the
// Newton stopping threshold, instead of Hairer and Wanner's, for the three modes)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/gravity.h"

namespace {

using namespace tt;

constexpr double kFrame = 0.05;

std::unique_ptr<System> gridScene() {
  Mesh mesh = boxGrid(4, 4, 4, Eigen::Vector3d(0.03, 0.03, 0.03), TetSplit::kFiveMirrored);
  const std::vector<Material> materials = {
      Material::transverselyIsotropic(3e4, 0.3, 1.2e5, 0.35, 1060.0)};
  int top = 0;
  for (int a = 0; a < mesh.numNodes(); ++a) {
    if (mesh.rest(2, a) < 1e-9) mesh.nodeTags[a] = kFixedAll;
    if ((mesh.rest.col(a) - Eigen::Vector3d(0, 0, 0.03)).norm() < 1e-9) top = a;
  }
  auto system = std::make_unique<System>(mesh, materials);
  system->damping = 2.0 * system->mass / 0.05;  // relaxation time ~ 0.05 s
  system->models.push_back(std::make_unique<EdgeLengthModel>(system->mesh, materials));
  system->models.push_back(
      std::make_unique<GravityModel>(system->mass, Eigen::Vector3d(0, 0, -9.81)));
  // The top corner is dragged 1 cm sideways over 0.5 s, then held.
  system->controlled.push_back(
      {{top}, {{0.0, 0.5}, {Eigen::Vector3d::Zero(), Eigen::Vector3d(0.01, 0.005, 0)}}});
  system->updateConstraints();
  return system;
}

struct Run {
  std::vector<Eigen::VectorXd> positions;  // after each frame
  double steps = 0, jacobians = 0, newton = 0, rejected = 0, factorizations = 0;
  double meanStep = 0, frameSeconds = 0;
  bool ok = true;
};

Run simulate(RadauJacobian mode, double tol, int frames, double newtonTolerance = 0.0) {
  auto system = gridScene();
  RadauOptions options;
  options.jacobian = mode;
  options.absTol = tol * 0.03;  // positions relative to the grid size
  options.absTolVelocity = tol * 0.03 / kFrame;
  options.relTol = tol;
  options.initialStep = 1e-3;
  options.newtonTolerance = newtonTolerance;
  RadauIIA radau(options);
  Run run;
  std::vector<double> seconds;
  double simulated = 0.0;
  for (int f = 0; f < frames; ++f) {
    const StepReport r = radau.advance(*system, kFrame);
    if (!r.ok) {
      std::printf("  frame %d failed: %s\n", f, r.failure.c_str());
      run.ok = false;
      return run;
    }
    run.steps += r.substeps;
    run.jacobians += r.jacobians;
    run.newton += r.newtonIterations;
    run.rejected += r.rejected;
    simulated += kFrame;
    seconds.push_back(r.wallSeconds);
    run.positions.push_back(system->state.x);
  }
  run.factorizations = static_cast<double>(radau.statistics().factorizations) / frames;
  run.meanStep = simulated / run.steps;
  run.steps /= frames;
  run.jacobians /= frames;
  run.newton /= frames;
  run.rejected /= frames;
  std::nth_element(seconds.begin(), seconds.begin() + frames / 2, seconds.end());
  run.frameSeconds = seconds[frames / 2];
  return run;
}

double maxError(const Run& run, const Run& reference) {
  double e = 0.0;
  for (size_t f = 0; f < run.positions.size(); ++f)
    e = std::max(e, (run.positions[f] - reference.positions[f]).lpNorm<Eigen::Infinity>());
  return e;
}

}  // namespace

int main(int argc, char** argv) {
  tt::tools::CommandLine options(
      argc, argv,
      "bench_radau_table_e1 [--quick] [--tolerance T=1e-5] [--frames N=20] [--repeats N=5] "
      "[--newton-tolerance K]");
  const bool quick = options.flag("--quick");
  const double tol = options.positiveNumber("--tolerance", 1e-5);
  const int frames = options.positiveInteger("--frames", quick ? 2 : 20);
  const int repeats = options.positiveInteger("--repeats", quick ? 1 : 5);
  const double newtonTolerance = options.positiveNumber("--newton-tolerance", 0.0);  // 0: Hairer's
  options.finish();
  {
    auto probe = gridScene();
    std::printf("bench_radau_table_e1: %d nodes, %d tets, %zu fixed or driven DOFs, frame %.2f s,"
                " %d frames, tolerance %.1e, Newton stopping threshold %s\n",
                probe->numNodes(), probe->mesh.numTets(), probe->constrainedDofs.size(), kFrame,
                frames, tol,
                newtonTolerance > 0.0 ? std::to_string(newtonTolerance).c_str()
                                      : "max(10 eps/rtol, min(0.03, sqrt(rtol)))");
  }
  const Run reference = simulate(RadauJacobian::kAnalytical, 1e-10, frames);
  if (!reference.ok) return 1;
  std::printf("%-12s %10s %9s %9s %9s %9s %9s %12s %12s\n", "Jacobian", "mean h(s)", "RK steps",
              "rejected", "J evals", "Newton", "LU", "ms/frame", "max err (m)");
  const struct {
    const char* name;
    RadauJacobian mode;
  } modes[] = {{"numerical", RadauJacobian::kNumerical},
               {"analytical", RadauJacobian::kAnalytical},
               {"simplified", RadauJacobian::kSimplified}};
  for (const auto& m : modes) {
    Run best;
    std::vector<double> times;
    for (int r = 0; r < repeats; ++r) {
      best = simulate(m.mode, tol, frames, newtonTolerance);
      if (!best.ok) return 1;
      times.push_back(best.frameSeconds);
    }
    std::nth_element(times.begin(), times.begin() + repeats / 2, times.end());
    std::printf("%-12s %10.4f %9.2f %9.2f %9.2f %9.2f %9.2f %12.3f %12.2e\n", m.name,
                best.meanStep, best.steps, best.rejected, best.jacobians, best.newton,
                best.factorizations, 1e3 * times[repeats / 2], maxError(best, reference));
  }
  std::printf("(averages per frame of %.2f s; Jeffrey Table E.1: numerical h 0.0200, 2.5 steps, "
              "2.4 J, 7.7 Newton; analytical 0.0336, 1.5, 1.5, 4.0; simplified 0.0052, 9.5, "
              "nil, 49.6)\n",
              kFrame);
  return 0;
}
