// bench_fitting: landmark fitting of the activations of a three-muscle block (docs/muscles.md,
// "Landmark fitting") with target noise 0, 0.1 and 1 mm: recovered activations against the
// truth, iterations, wall time and final RMS residual, as one table.
#include <chrono>
#include <cstdio>
#include <random>

#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/scene/scene.h"

namespace {

void setActivations(tt::System& s, const double* a) {
  const char* names[3] = {"lower", "middle", "upper"};
  for (int i = 0; i < 3; ++i) {
    const tt::ActivationRef ref = s.findActivation(names[i]);
    ref.model->setActivation(ref.index, a[i]);
  }
}

}  // namespace

int main() {
  const std::string path = std::string(TT_SOURCE_ROOT) + "/config/scenes/three_muscle_block.yaml";
  const double truth[3] = {0.3, 0.6, 0.45};
  tt::EquilibriumParams eq;
  eq.preconditioner = tt::EquilibriumParams::Preconditioning::kCholesky;
  eq.absoluteTolerance = 1e-12;
  eq.relativeTolerance = 1e-14;
  std::printf("| landmarks | noise (mm) | lower | middle | upper | max error | iterations | stop | residual (m) | time (ms) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  for (int stride : {4, 1})
  for (double noise : {0.0, 1e-4, 1e-3}) {
    tt::Scene scene = tt::loadScene(path);
    tt::System& s = scene.system;
    const Eigen::VectorXd rest = s.state.x;
    setActivations(s, truth);
    const tt::EquilibriumReport truthSolve = tt::solveEquilibrium(s, eq);
    if (!truthSolve.converged()) {
      std::fprintf(stderr, "bench_fitting: the ground truth's equilibrium failed: %s\n",
                   truthSolve.reason.c_str());
      return 3;
    }
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss(0.0, noise > 0 ? noise : 1.0);
    std::vector<tt::Landmark> landmarks;
    for (int n = 0; n < s.numNodes(); n += stride) {
      if (s.isConstrained[3 * n]) continue;
      tt::Landmark l;
      l.nodes = {n, n, n, n};
      l.weights = Eigen::Vector4d(1, 0, 0, 0);
      l.target = s.state.x.segment<3>(3 * n);
      if (noise > 0) l.target += Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
      landmarks.push_back(l);
    }
    const double zero[3] = {0, 0, 0};
    setActivations(s, zero);
    s.state.x = rest;
    tt::FitParams params;
    params.equilibrium = eq;
    params.residualTolerance = 1e-12;
    params.stepTolerance = 1e-9;
    tt::LandmarkFit fit(s, landmarks, params);
    const auto start = std::chrono::steady_clock::now();
    const tt::FitResult r = fit.run();
    const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Eigen::VectorXd a = fit.parameters();
    double maxError = 0;
    for (int i = 0; i < 3; ++i) maxError = std::max(maxError, std::abs(a[i] - truth[i]));
    std::printf("| %zu | %g | %.6f | %.6f | %.6f | %.2e | %zu | %s | %.3e | %.0f |\n", landmarks.size(), 1e3 * noise, a[0],
                a[1], a[2], maxError, r.iterations.size(), tt::stopName(r.stop), r.residual, ms);
  }
  std::printf("truth: lower %.2f, middle %.2f, upper %.2f; %s\n", truth[0], truth[1], truth[2],
              "landmarks: every 4th free node, or every free node; Gaussian noise of the given standard deviation per coordinate");
  return 0;
}
