// The demo of Jeffrey, "A non-linear anisotropic Finite Element Method for surgical
// simulation", Sec. 3: the anisotropic spindle muscle (861 nodes, 2400 tets here; Jeffrey's
// has 2552), E_L 150 kPa / nu 0.4 along the fibres (which follow the spindle), E_T
// 20 kPa / nu 0.4 across, density 1060, both tendon end layers fixed, mass-proportional
// damping. A node on the belly surface is pulled 1 cm sideways (radially out) over 0.1 s and
// back over the next 0.1 s. For each force model and integrator: the simulation rate
// (simulated s per wall s, steps per wall s; median over repeats) beside the largest node
// distance to a reference run at the peak of the pull (t = 0.1 s) and at the end (t = 0.2 s).
// Reference: edge_length fast with the second-order Newtonian scheme at h = 5 us (a Radau IIA
// run at tolerance 1e-8 took 5845 steps and two minutes); its own error is estimated against
// the same run at h = 10 us and printed. The Newtonian rows use half the stability limit at
// rest (0.9 of it blew up: the stiffness grows with the deformation).
//   bench_muscle_demo [--quick] [--repeats N=1] [--radau-tolerance T=1e-3] [--be-substeps N=1]
// (--be-substeps: backward Euler substeps per frame; --quick: the reference, then one row)
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/model/tensor_mass.h"
#include "common/bench_support.h"
#include "common/command_line.h"
#include "common/muscle_scene.h"

namespace {

using namespace tt;
using namespace tt::muscle_scene;
using tt::bench::maxNodeDistance;

constexpr double kFrame = 0.01;   // s

struct ModelChoice {
  const char* label;
  ModelMaker make;
};

const std::vector<ModelChoice>& models() {
  static const std::vector<ModelChoice> list = {
      {"edge_length fast", [](const Mesh& m, const std::vector<Material>& mat) {
         return std::make_unique<EdgeLengthModel>(m, mat); }},
      {"edge_length literal", [](const Mesh& m, const std::vector<Material>& mat) {
         return std::make_unique<EdgeLengthModel>(m, mat, EdgeLengthPath::kLiteral); }},
      {"stvk_displacement", [](const Mesh& m, const std::vector<Material>& mat) {
         return std::make_unique<StvkDisplacementModel>(m, mat); }},
      {"tensor_mass", [](const Mesh& m, const std::vector<Material>& mat) {
         return std::make_unique<TensorMassModel>(m, mat); }},
  };
  return list;
}

struct IntegratorChoice {
  std::string label;
  std::function<std::unique_ptr<Integrator>()> make;
};

struct Run {
  bool ok = true;
  std::string failure;
  Eigen::VectorXd atPeak, atEnd;
  long steps = 0;
  double wallSeconds = 0.0;
};

Run simulate(const ModelChoice& model, Integrator& integrator) {
  auto s = muscle(model.make);
  Run run;
  const int frames = static_cast<int>(std::lround(kEnd / kFrame));
  const int peakFrame = static_cast<int>(std::lround(kPeak / kFrame));
  for (int f = 1; f <= frames; ++f) {
    const StepReport r = integrator.advance(*s, kFrame);
    if (!r.ok) {
      run.ok = false;
      run.failure = r.failure;
      return run;
    }
    run.steps += r.substeps;
    run.wallSeconds += r.wallSeconds;
    if (f == peakFrame) run.atPeak = s->state.x;
  }
  run.atEnd = s->state.x;
  return run;
}

RadauOptions radauOptions(double tol) {
  RadauOptions o;
  o.absTol = tol * 0.01;  // positions relative to the 1 cm pull
  o.absTolVelocity = tol * 0.1;
  o.relTol = tol;
  o.initialStep = 1e-4;
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);  // rows appear as they are measured
  tools::CommandLine options(argc, argv,
                             "bench_muscle_demo [--quick] [--repeats N=1] "
                             "[--radau-tolerance T=1e-3] [--be-substeps N=1]");
  const bool quick = options.flag("--quick");
  const int repeats = options.positiveInteger("--repeats", 1);
  const double radauTol = options.positiveNumber("--radau-tolerance", 1e-3);
  const int beSubsteps = options.positiveInteger("--be-substeps", 1);
  options.finish();
  auto probe = muscle(models()[0].make);
  const double hStable = 2.0 / omegaMax(*probe);
  std::printf("bench_muscle_demo %d %g %d: %d nodes, %d tets, node %d pulled %.0f mm along +x "
              "and back over %.1f s; Newtonian stable step 2/omega_max = %.2f us\n",
              repeats, radauTol, beSubsteps, probe->numNodes(), probe->mesh.numTets(),
              bellyNode(probe->mesh), kPull * 1e3, kEnd, hStable * 1e6);

  // --quick: a coarser reference (a smoke run, not a measurement).
  const double fineStep = quick ? 2e-5 : 5e-6;
  NewtonianIntegrator fine(NewtonianParams{fineStep}), coarse(NewtonianParams{2 * fineStep});
  const Run reference = simulate(models()[0], fine);
  const Run check = simulate(models()[0], coarse);
  if (!reference.ok || !check.ok) {
    std::printf("reference failed: %s\n", reference.failure.c_str());
    return 1;
  }
  std::printf("reference: newtonian h = %.0f us, edge_length fast, %ld steps, %.1f s wall; "
              "h = %.0f us differs by %.2e mm (peak), %.2e mm (end)\n",
              fineStep * 1e6, reference.steps, reference.wallSeconds, 2e6 * fineStep,
              1e3 * maxNodeDistance(check.atPeak, reference.atPeak),
              1e3 * maxNodeDistance(check.atEnd, reference.atEnd));

  const double newtonianStep = 0.5 * hStable;
  const std::vector<IntegratorChoice> integrators = {
      {"newtonian h=" + std::to_string(newtonianStep * 1e6).substr(0, 5) + "us",
       [=] { return std::make_unique<NewtonianIntegrator>(NewtonianParams{newtonianStep}); }},
      {"backward_euler h=" + std::to_string(kFrame / beSubsteps * 1e3).substr(0, 4) + "ms",
       [=] {
         BackwardEulerParams p = bench::jacobiBackwardEuler();
         p.substeps = beSubsteps;
         return std::make_unique<BackwardEulerIntegrator>(p);
       }},
      {"radau_iia tol=" + std::to_string(radauTol).substr(0, 7),
       [=] { return std::make_unique<RadauIIA>(radauOptions(radauTol)); }},
  };
  std::printf("%-22s %-26s %10s %10s %12s %12s\n", "model", "integrator", "sim s/s",
              "steps/s", "err peak(mm)", "err end(mm)");
  for (const ModelChoice& model : models())
    for (const IntegratorChoice& choice : integrators) {
      if (quick && (&model != &models()[0] || &choice != &integrators.front())) continue;
      std::vector<double> wall;
      Run run;
      for (int r = 0; r < repeats; ++r) {
        auto integrator = choice.make();
        run = simulate(model, *integrator);
        if (!run.ok) break;
        wall.push_back(run.wallSeconds);
      }
      if (!run.ok) {
        std::printf("%-22s %-26s   failed: %s\n", model.label, choice.label.c_str(),
                    run.failure.c_str());
        continue;
      }
      std::nth_element(wall.begin(), wall.begin() + wall.size() / 2, wall.end());
      const double seconds = wall[wall.size() / 2];
      std::printf("%-22s %-26s %10.3f %10.0f %12.3e %12.3e\n", model.label,
                  choice.label.c_str(), kEnd / seconds, run.steps / seconds,
                  1e3 * maxNodeDistance(run.atPeak, reference.atPeak),
                  1e3 * maxNodeDistance(run.atEnd, reference.atEnd));
    }
  return 0;
}
