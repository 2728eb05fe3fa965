// bench_quasistatic: the speed of the quasistatic muscle update (docs/muscles.md, "Speed").
//   tongue : config/scenes/tongue_muscles.yaml at an activation a0 of its upper muscle, then
//            updates that change it by a small step (0.02: a ramp of 1/s at 50 Hz) or a large
//            one (0.2), each solved from the last equilibrium (warm start) by one persistent
//            EquilibriumSolver, as the quasistatic integrator does frame after frame;
//   block  : a muscle block of ~100k tets (one muscle along its length, one end clamped), the
//            same updates;
//   fit    : one Gauss-Newton iteration of the landmark fit of the tongue (its activations;
//            then with jaw and cranium transforms too): the equilibrium and the Jacobian's
//            assembly, factorisation and p solves.
// Every update is timed (wall and process CPU) and compared with a tightly converged
// reference from the same start: max node distance (m), so the error stands beside the time.
// Medians over the updates. CSV: DIR/quasistatic.csv and DIR/quasistatic_fit.csv.
//   bench_quasistatic [--quick] [--out DIR] [--threads N] [--updates N] [--cases a,b]
#include <cstdio>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/model/muscle_groups.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace {

constexpr const char* kTool = "bench_quasistatic";

std::string loadAverage() {
  std::ifstream in("/proc/loadavg");
  double one = 0.0;
  in >> one;
  char text[32];
  std::snprintf(text, sizeof text, "%.2f", one);
  return text;
}

// The solver settings compared: the scene's own, a new Cholesky factor every Newton
// iteration, and looser residual tolerances.
struct Setting {
  std::string name;
  tt::EquilibriumParams params;
};

// `all`: every setting; else the default and one looser tolerance (for the large block).
std::vector<Setting> settings(const tt::EquilibriumParams& base, bool all) {
  std::vector<Setting> out;
  out.push_back({"default", base});
  if (all) {
    out.push_back({"refactor_iterations=0", base});
    out.back().params.refactorIterations = 0;
  }
  for (double tolerance : all ? std::vector<double>{1e-6, 1e-4} : std::vector<double>{1e-6}) {
    char name[32];
    std::snprintf(name, sizeof name, "abs_tol=%g", tolerance);
    Setting s{name, base};
    s.params.absoluteTolerance = tolerance;
    out.push_back(s);
  }
  return out;
}

// The tightly converged equilibrium from x (the reference of an update).
Eigen::VectorXd reference(const tt::System& system, Eigen::VectorXd x,
                          const tt::EquilibriumParams& base) {
  tt::EquilibriumParams tight = base;
  tight.absoluteTolerance = 1e-11;
  tight.relativeTolerance = 1e-14;
  tight.preconditioner = tt::EquilibriumParams::Preconditioning::kCholesky;
  tt::EquilibriumSolver solver(tight);
  const tt::EquilibriumReport r = solver.solve(system, x);
  if (!r.converged() && r.stop != tt::EquilibriumStop::kIterationLimit)
    std::fprintf(stderr, "%s: the reference did not converge: %s\n", kTool, r.reason.c_str());
  return x;
}

struct UpdateRow {
  std::string problem, setting;
  double step = 0.0;
  int updates = 0;
  double wallMs = 0.0, cpuMs = 0.0, newton = 0.0, cg = 0.0, factorizations = 0.0,
         forceEvaluations = 0.0, residual = 0.0, error = 0.0;
};

// Updates of activation `slot` between a0 and a0 + step (alternating), each warm-started from
// the last equilibrium by one persistent solver.
UpdateRow runUpdates(tt::System& system, tt::ActivationRef slot, double a0, double step,
                     int updates, const Setting& setting, const std::string& problem) {
  slot.model->setActivation(slot.index, a0);
  Eigen::VectorXd x = reference(system, system.state.x, setting.params);
  tt::EquilibriumSolver solver(setting.params);
  std::vector<double> wall, cpu, newton, cg, factorizations, forces;
  UpdateRow row{problem, setting.name, step, updates};
  // A first solve at a0 sets up the solver's matrices and factor, as in a running scene.
  solver.solve(system, x);
  for (int k = 0; k < updates; ++k) {
    slot.model->setActivation(slot.index, k % 2 == 0 ? a0 + step : a0);
    const double w0 = tt::bench::wallSeconds(), c0 = tt::bench::cpuSeconds();
    const tt::EquilibriumReport r = solver.solve(system, x);
    wall.push_back(1e3 * (tt::bench::wallSeconds() - w0));
    cpu.push_back(1e3 * (tt::bench::cpuSeconds() - c0));
    if (!r.converged())
      std::fprintf(stderr, "%s: %s %s update %d: %s\n", kTool, problem.c_str(),
                   setting.name.c_str(), k, r.reason.c_str());
    newton.push_back(r.newtonIterations);
    cg.push_back(r.linearIterations);
    factorizations.push_back(r.factorizations);
    forces.push_back(r.forceEvaluations);
    row.residual = std::max(row.residual, r.residual);
    const double error = tt::bench::maxNodeDistance(x, reference(system, x, setting.params));
    row.error = std::max(row.error, error);
  }
  system.state.x = x;
  using tt::bench::median;
  row.wallMs = median(wall);
  row.cpuMs = median(cpu);
  row.newton = median(newton);
  row.cg = median(cg);
  row.factorizations = median(factorizations);
  row.forceEvaluations = median(forces);
  return row;
}

void printRow(std::FILE* out, const UpdateRow& r, const std::string& load) {
  std::fprintf(out, "%s,%s,%g,%d,%.3f,%.3f,%g,%g,%g,%g,%.3e,%.3e,%d,%s\n", r.problem.c_str(),
               r.setting.c_str(), r.step, r.updates, r.wallMs, r.cpuMs, r.newton, r.cg,
               r.factorizations, r.forceEvaluations, r.residual, r.error, tt::threadCount(),
               load.c_str());
}

// Median times (ms) of the parts of an update at x: a force pass, a stiffness assembly, a
// Cholesky factorisation and one CG iteration (a matrix-vector product and a solve with the
// factor).
void printParts(std::FILE* out, const std::string& problem, const tt::System& system,
                const Eigen::VectorXd& x) {
  const int repeats = 5;
  std::vector<double> force, stiffness, factor, iteration;
  Eigen::VectorXd f, z;
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(x.size());
  tt::SparseMatrix K;
  tt::CholeskyPreconditioner cholesky(false);
  const auto time = [](std::vector<double>& into, const auto& work) {
    const double w0 = tt::bench::wallSeconds();
    work();
    into.push_back(1e3 * (tt::bench::wallSeconds() - w0));
  };
  for (int k = 0; k < repeats; ++k) {
    time(force, [&] { system.computeForce(x, v, f); });
    time(stiffness, [&] { system.assembleStiffness(x, K, -1.0); });
    system.constrainMatrix(K);
    time(factor, [&] { cholesky.factorNow(K); });
    time(iteration, [&] {
      z = K * f;
      cholesky.apply(z, f);
    });
  }
  using tt::bench::median;
  std::fprintf(out, "%s,%.3f,%.3f,%.3f,%.3f,%d\n", problem.c_str(), median(force),
               median(stiffness), median(factor), median(iteration), tt::threadCount());
}

tt::EquilibriumParams sceneParams(tt::Scene& scene) {
  tt::Integrator* integrator = scene.integrator.get();
  if (auto* guard = dynamic_cast<tt::StabilityGuard*>(integrator)) integrator = &guard->inner();
  const auto* q = dynamic_cast<const tt::QuasistaticIntegrator*>(integrator);
  if (!q) {
    std::fprintf(stderr, "%s: %s is not a quasistatic scene\n", kTool, scene.file.c_str());
    std::exit(3);
  }
  return q->params();
}

std::string tonguePath() {
  return std::string(TT_SOURCE_ROOT) + "/config/scenes/tongue_muscles.yaml";
}

// The muscle block: a beam along x (cellsAlong x cells x cells cells, 6 tets each), one muscle
// with fibres along x over all of it, the end x = 0 clamped, no gravity.
std::unique_ptr<tt::System> muscleBlock(int cellsAlong, int cells) {
  tt::Mesh mesh = tt::cantileverBeam(0.1, 0.025, cellsAlong, cells);
  const std::vector<tt::Material> materials = {tt::Material::isotropic(6e3, 0.45, 1050.0)};
  auto system = std::make_unique<tt::System>(mesh, materials);
  tt::TeranMuscleLaw::Constants k;
  k.A = 2e3, k.B = 0.5e3, k.K = 50e3, k.sigmaMax = 30e3;
  tt::MuscleGroup group;
  group.name = "muscle";
  for (int e = 0; e < system->mesh.numTets(); ++e) group.elements.push_back(e);
  tt::LawOptions options;
  options.inversionThreshold = 0.2;
  system->models.push_back(std::make_unique<tt::MuscleGroupsModel>(
      system->mesh, std::vector<tt::TeranMuscleLaw::Constants>{k},
      std::vector<tt::MuscleGroup>{group}, options));
  system->updateConstraints();
  return system;
}

// One Gauss-Newton iteration of the landmark fit of the tongue's activations (with the jaw
// and cranium transforms when `jawAndCranium`, the jaw being the clamped root): evaluate() at
// parameters a small step away from the last, i.e. the warm-started equilibrium and the
// Jacobian (assembly, one factorisation, p solves). Medians over `updates` iterations.
std::string fitRow(bool jawAndCranium, int updates) {
  tt::Scene scene = tt::loadScene(tonguePath());
  tt::System& s = scene.system;
  const tt::EquilibriumParams base = sceneParams(scene);
  const tt::ActivationRef upper = s.findActivation("superior_longitudinal");
  const tt::ActivationRef lower = s.findActivation("transverse");
  upper.model->setActivation(upper.index, 0.5);
  lower.model->setActivation(lower.index, 0.2);
  s.state.x = reference(s, s.state.x, base);
  std::vector<tt::Landmark> landmarks;
  for (int n = 0; n < s.numNodes(); n += 20) {
    if (s.isConstrained[3 * n]) continue;
    tt::Landmark l;
    l.nodes = {n, n, n, n};
    l.weights = Eigen::Vector4d(1, 0, 0, 0);
    l.target = s.state.x.segment<3>(3 * n);
    landmarks.push_back(l);
  }
  tt::FitParams params;
  params.equilibrium = base;
  params.fitJaw = params.fitCranium = jawAndCranium;
  for (int n = 0; n < s.numNodes(); ++n)
    if (s.isConstrained[3 * n] && s.isConstrained[3 * n + 1] && s.isConstrained[3 * n + 2])
      params.jawNodes.push_back(n);
  tt::LandmarkFit fit(s, landmarks, params);
  Eigen::VectorXd theta = fit.parameters(), y;
  Eigen::MatrixXd J;
  fit.evaluate(theta, y, &J);  // sets up the solver and the factor's analysis
  std::vector<double> total, equilibrium, assembly, factorization, solves, newton, cg;
  for (int k = 0; k < updates; ++k) {
    theta[0] += k % 2 == 0 ? 0.02 : -0.02;
    const double w0 = tt::bench::wallSeconds();
    if (!fit.evaluate(theta, y, &J))
      std::fprintf(stderr, "%s: fit evaluation failed: %s\n", kTool, fit.failure().c_str());
    const double ms = 1e3 * (tt::bench::wallSeconds() - w0);
    const tt::JacobianCost& c = fit.lastJacobianCost();
    total.push_back(ms);
    assembly.push_back(1e3 * c.assembly);
    factorization.push_back(1e3 * c.factorization);
    solves.push_back(1e3 * c.solves);
    equilibrium.push_back(ms - 1e3 * (c.assembly + c.factorization + c.solves));
    newton.push_back(fit.equilibriumReport().newtonIterations);
    cg.push_back(fit.equilibriumReport().linearIterations);
  }
  using tt::bench::median;
  char row[512];
  std::snprintf(row, sizeof row, "%s,%d,%zu,%.3f,%.3f,%.3f,%.3f,%.3f,%g,%g,%d,%s\n",
               jawAndCranium ? "activations+jaw+cranium" : "activations",
               fit.parameterCount(), landmarks.size(), median(total), median(equilibrium),
               median(assembly), median(factorization), median(solves), median(newton),
               median(cg), tt::threadCount(), loadAverage().c_str());
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  tt::tools::CommandLine options(argc, argv,
                                 "bench_quasistatic [--quick] [--out DIR] [--threads N] "
                                 "[--updates N] [--cases tongue,block,fit]");
  const bool quick = options.flag("--quick");
  const std::string out =
      options.text("--out", std::string(TT_SOURCE_ROOT) + "/docs/report/muscles");
  const int threads = options.positiveInteger("--threads", 0);  // 0: not given
  const int updates = options.positiveInteger("--updates", quick ? 2 : 6);
  const std::vector<std::string> cases = options.list("--cases", {});
  options.finish();
  tt::bench::requireKnown(kTool, "case", cases, {"tongue", "block", "fit"});
  if (threads > 0) tt::setThreadCount(threads);
  else if (tt::threadCount() == 1) tt::setThreadCount(tt::hardwareThreads());
  std::system(("mkdir -p '" + out + "'").c_str());
  const std::string csvPath = out + "/quasistatic.csv";
  std::FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "%s: cannot write %s\n", kTool, csvPath.c_str());
    return 3;
  }
  const char* header =
      "problem,setting,step,updates,median_wall_ms,median_cpu_ms,median_newton,median_cg,"
      "median_factorizations,median_force_evaluations,max_residual_N,max_error_m,threads,"
      "load\n";
  std::fputs(header, csv);
  std::fputs(header, stdout);
  const std::string partsPath = out + "/quasistatic_parts.csv";
  std::FILE* parts = std::fopen(partsPath.c_str(), "w");
  const char* partsHeader = "problem,force_ms,stiffness_ms,factorization_ms,cg_iteration_ms,threads\n";
  std::fputs(partsHeader, parts);
  const std::vector<double> steps = quick ? std::vector<double>{0.02} : std::vector<double>{0.02, 0.2};

  if (tt::bench::selected(cases, "tongue")) {
    tt::Scene scene = tt::loadScene(tonguePath());
    const tt::ActivationRef slot = scene.system.findActivation("superior_longitudinal");
    const tt::EquilibriumParams base = sceneParams(scene);
    const Eigen::VectorXd rest = scene.system.state.x;
    for (const Setting& setting : settings(base, true))
      for (double step : steps) {
        scene.system.state.x = rest;
        const UpdateRow row = runUpdates(scene.system, slot, 0.5, step, updates, setting,
                                         "tongue_11k");
        printRow(csv, row, loadAverage());
        printRow(stdout, row, loadAverage());
        std::fflush(stdout);
      }
    printParts(parts, "tongue_11k", scene.system, scene.system.state.x);
  }
  if (tt::bench::selected(cases, "block")) {
    const int along = quick ? 12 : 64, across = quick ? 4 : 16;
    auto system = muscleBlock(along, across);
    const tt::ActivationRef slot = system->findActivation("muscle");
    tt::EquilibriumParams base;
    base.preconditioner = tt::EquilibriumParams::Preconditioning::kCholesky;
    const Eigen::VectorXd rest = system->state.x;
    const std::string name = "block_" + std::to_string(system->mesh.numTets() / 1000) + "k";
    for (const Setting& setting : settings(base, quick))
      for (double step : steps) {
        system->state.x = rest;
        const UpdateRow row = runUpdates(*system, slot, 0.3, step, updates, setting, name);
        printRow(csv, row, loadAverage());
        printRow(stdout, row, loadAverage());
        std::fflush(stdout);
      }
    printParts(parts, name, *system, system->state.x);
  }
  if (tt::bench::selected(cases, "fit")) {
    const std::string fitPath = out + "/quasistatic_fit.csv";
    std::FILE* fitCsv = std::fopen(fitPath.c_str(), "w");
    const char* fitHeader =
        "parameters,p,landmarks,median_iteration_ms,median_equilibrium_ms,median_assembly_ms,"
        "median_factorization_ms,median_solves_ms,median_newton,median_cg,threads,load\n";
    for (std::FILE* f : {fitCsv, stdout}) std::fputs(fitHeader, f);
    for (bool jawAndCranium : {false, true}) {
      const std::string row = fitRow(jawAndCranium, updates);
      for (std::FILE* f : {fitCsv, stdout}) std::fputs(row.c_str(), f);
      std::fflush(stdout);
    }
    std::fclose(fitCsv);
  }
  std::fclose(csv);
  std::fclose(parts);
  std::printf("parts: %s\n", partsPath.c_str());
  return 0;
}
