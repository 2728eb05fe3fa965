// The cost of the speed trick of Jeffrey, "A non-linear anisotropic Finite Element Method for
// surgical simulation", Sec. 3: nodes whose net force is below a threshold are not propagated
// by the Newtonian scheme. On the muscle demo (muscle_scene.h, edge_length
// fast, Newtonian at half its stability limit at rest) the thresholds are fractions of the largest
// net nodal force at the peak of the pull; the error is the largest node distance to the
// threshold-0 run with the same integrator and step (so it is the trick's own error), at the
// peak of the pull and at the end. Wall time: median over repeats.
//   bench_force_threshold [--quick] [--repeats N=3]   (--quick: thresholds 0 and 1e-2, one repeat)
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "common/muscle_scene.h"
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/model/edge_length.h"

namespace {

using namespace tt;
using namespace tt::muscle_scene;
using tt::bench::maxNodeDistance;

constexpr double kFrame = 0.01;  // s

std::unique_ptr<ForceModel> edgeLength(const Mesh& m, const std::vector<Material>& mat) {
  return std::make_unique<EdgeLengthModel>(m, mat);
}

struct Run {
  bool ok = true;
  Eigen::VectorXd atPeak, atEnd;
  double wallSeconds = 0.0;
  double frozenFraction = 0.0;  // of free node-steps
  double maxForceAtPeak = 0.0;  // largest net force on a free node at the peak (N)
};

Run simulate(double step, double threshold) {
  auto s = muscle(edgeLength);
  NewtonianIntegrator integrator(NewtonianParams{step, false, threshold});
  Run run;
  const int frames = static_cast<int>(std::lround(kEnd / kFrame));
  const int peakFrame = static_cast<int>(std::lround(kPeak / kFrame));
  long steps = 0;
  for (int f = 1; f <= frames; ++f) {
    const StepReport r = integrator.advance(*s, kFrame);
    if (!r.ok) {
      run.ok = false;
      return run;
    }
    steps += r.substeps;
    run.wallSeconds += r.wallSeconds;
    if (f == peakFrame) {
      run.atPeak = s->state.x;
      Eigen::VectorXd force;
      s->computeForce(s->state.x, s->state.v, force);
      s->zeroConstrained(force);
      for (int a = 0; a < s->numNodes(); ++a)
        run.maxForceAtPeak = std::max(run.maxForceAtPeak, force.segment<3>(3 * a).norm());
    }
  }
  run.atEnd = s->state.x;
  int freeNodes = 0;
  for (int a = 0; a < s->numNodes(); ++a) freeNodes += !s->isConstrained[3 * a];
  run.frozenFraction = static_cast<double>(integrator.frozenNodeSteps()) / (steps * freeNodes);
  return run;
}

Run medianRun(double step, double threshold, int repeats) {
  std::vector<double> wall;
  Run run;
  for (int r = 0; r < repeats; ++r) {
    run = simulate(step, threshold);
    if (!run.ok) return run;
    wall.push_back(run.wallSeconds);
  }
  std::nth_element(wall.begin(), wall.begin() + wall.size() / 2, wall.end());
  run.wallSeconds = wall[wall.size() / 2];
  return run;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // rows appear as they are measured
  tools::CommandLine options(argc, argv, "bench_force_threshold [--quick] [--repeats N]");
  const bool quick = options.flag("--quick");
  const int repeats = options.positiveInteger("--repeats", quick ? 1 : 3);
  options.finish();
  auto probe = muscle(edgeLength);
  const double step = 0.5 * 2.0 / omegaMax(*probe);
  const Run exact = medianRun(step, 0.0, repeats);
  if (!exact.ok) {
    std::printf("threshold-0 run failed\n");
    return 1;
  }
  std::printf("bench_force_threshold %d: muscle %d nodes, %d tets, edge_length fast, newtonian "
              "h = %.2f us, %.1f s simulated; largest net free-node force at the peak %.3e N\n",
              repeats, probe->numNodes(), probe->mesh.numTets(), step * 1e6, kEnd,
              exact.maxForceAtPeak);
  std::printf("%12s %12s %10s %10s %12s %12s\n", "threshold(N)", "x max force", "frozen",
              "wall (s)", "err peak(mm)", "err end(mm)");
  const std::vector<double> fractions =
      quick ? std::vector<double>{0.0, 1e-2} : std::vector<double>{0.0, 1e-4, 1e-3, 1e-2, 1e-1};
  for (const double fraction : fractions) {
    const double threshold = fraction * exact.maxForceAtPeak;
    const Run run = fraction == 0.0 ? exact : medianRun(step, threshold, repeats);
    if (!run.ok) {
      std::printf("%12.3e %12.0e   failed\n", threshold, fraction);
      continue;
    }
    std::printf("%12.3e %12.0e %9.1f%% %10.3f %12.3e %12.3e\n", threshold, fraction,
                100.0 * run.frozenFraction, run.wallSeconds,
                1e3 * maxNodeDistance(run.atPeak, exact.atPeak),
                1e3 * maxNodeDistance(run.atEnd, exact.atEnd));
  }
  return 0;
}
