// Time per implicit step at organ scale: the liver palpation scene (config/scenes/
// liver_palpation.yaml: edge_length, gravity, mass damping, the top clamped) on TetGen quality
// refinements of its liver (tetgen -rq1.4a<volume>: the same surface, more tets) of about 3k,
// 10k, 50k and 100k tets, with a 6 mm sphere pressed 6 mm into the liver's anterior face
// through the real contact (TissueContact, Bullet). Each row is one linear-solver set-up of
// backward Euler (one linearised step, h = 10 ms): Jacobi-PCG, or CG preconditioned by a
// Cholesky factor (CHOLMOD or Eigen's SimplicialLDLT) refactorised in the background when the
// iterations pass refactor_iterations, or by one V-cycle of hypre's BoomerAMG hierarchy (set up
// again, synchronously, by the same rule), on one or two threads, at a PCG tolerance.
//
// For every timed step: the wall time of the step (force, assembly, solve) and of the contact
// query before it, the PCG iterations, the achieved relative residual, the factors or AMG
// hierarchies built over the row (`fact`, the first one included), and the step's error
// against the same step solved to 1e-10 from the same state with the exact stiffness (rows
// marked psd build their matrix from the PSD-projected one, the reference never does):
// max |x - x_ref| / max |x_ref - x_start|. Each size starts from the same state (the liver at rest, then the tool pressed in
// for 10 steps). Also the
// time of one factorisation of the system matrix at the start state, per backend, and of one
// AMG set-up.
//   bench_implicit_step [--quick] [--sizes 3000,10000,50000,100000] [--csv FILE] [--rows K,...]
//                       [--node-order rcm|morton|file]
// --sizes: target tet counts; --rows: the set-ups to run, as 1-based row numbers (default all);
// --node-order: the scene's mesh.node_order (default: the scene's default, rcm);
// --quick: 3000 tets, rows 6 and 14, 5 timed steps (a smoke run, not a measurement).
// TT_BENCH_TRACE=1 prints every step (time, iterations, factors, contact points).
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <sstream>
#include <utility>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "tissue_trainer/core/contact/tissue_contact.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/scene.h"
#include "common/liver_bench_scene.h"

namespace {

using namespace tt;
using Clock = std::chrono::steady_clock;
using Preconditioning = BackwardEulerParams::Preconditioning;
using bench::quantile;
using bench::sourceDir;

double seconds(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

const std::string kWork = "/tmp/tt_bench_implicit_step";

std::string refinedLiver(int target, int& tets) { return bench::refinedLiver(kWork, target, tets); }

// The palpation scene with another mesh of the same liver; psd: with the edge-length model's
// PSD-projected stiffness for the system matrix; nodeOrder: mesh.node_order when not empty.
std::string sceneWithMesh(const std::string& mesh, const std::string& nodeOrder, bool psd = false) {
  const std::string path = mesh + (psd ? "_psd.yaml" : ".yaml");
  std::vector<bench::SceneEdit> edits;
  if (!nodeOrder.empty())
    edits.push_back({"  scale: 0.025", "  node_order: " + nodeOrder + "\n  scale: 0.025"});
  if (psd) edits.push_back({"  - type: edge_length\n", "  - type: edge_length\n    psd_projection: true\n"});
  bench::writeLiverSceneWithMesh(mesh, path, edits);
  return path;
}

// A CSV field: quoted when it holds a comma.
std::string csvField(const std::string& text) {
  return text.find(',') == std::string::npos ? text : '"' + text + '"';
}

struct Setup {
  const char* label;
  Preconditioning preconditioner;
  CholeskyBackend backend;
  int threads;
  double tolerance;
  int refactorIterations = 15;
  bool psd = false;  // the system matrix from the PSD-projected stiffness (edge_length psd_projection)
};

struct Result {
  std::vector<double> stepMs, contactMs, iterations, residuals, errors;
  int factorizations = 0, refused = 0, failed = 0;
};

class Bench {
 public:
  Bench(const std::string& scenePath, const std::string& psdScenePath, int steps)
      : scenePath_(scenePath), psdScenePath_(psdScenePath), steps_(steps) {}

  // Loads the scene, lets the liver sag to rest under gravity (3 s in steps of 0.1 s; the
  // mass damping of 2/s and backward Euler's own damping settle it), presses the tool and
  // runs 10 steps: the start of every row, as a trainee finds the liver.
  void prepare() {
    Scene scene = loadScene(scenePath_);
    BackwardEulerIntegrator settle(bench::tightBackwardEuler());
    bench::sagToRest(scene.system, settle);
    toolPose_ = bench::pressingPose(scene.system, kToolRadius, 0.006);
    auto contact = makeContact(scene);
    for (int s = 0; s < 10; ++s) {
      contact->update();
      settle.advance(scene.system, kStep);
    }
    start_ = scene.system.state;
    tets_ = scene.system.mesh.numTets();
    dofs_ = scene.system.numDofs();
    inContact_ = contact->result().points.size();
  }

  Result run(const Setup& setup) {
    setThreadCount(setup.threads);
    Scene scene = loadScene(setup.psd ? psdScenePath_ : scenePath_);
    Scene exact = loadScene(scenePath_);  // the reference's: the exact stiffness
    scene.system.state = start_;
    auto contact = makeContact(scene);
    auto exactContact = makeContact(exact);
    BackwardEulerParams params;
    params.linearTolerance = setup.tolerance;
    params.linearMaxIterations = 5000;
    params.preconditioner = setup.preconditioner;
    params.choleskyBackend = setup.backend;
    params.refactorIterations = setup.refactorIterations;
    BackwardEulerIntegrator integrator(params);
    BackwardEulerIntegrator reference(bench::tightBackwardEuler());
    Result r;
    for (int s = 0; s < steps_ + kUntimed; ++s) {
      auto t0 = Clock::now();
      contact->update();
      const double contactMs = 1e3 * seconds(t0);
      const State before = scene.system.state;
      exact.system.state = before;
      exactContact->update();
      reference.advance(exact.system, kStep);
      const Eigen::VectorXd xRef = exact.system.state.x;
      t0 = Clock::now();
      const StepReport report = integrator.advance(scene.system, kStep);
      const double stepMs = 1e3 * seconds(t0);
      if (!report.ok) ++r.failed;
      if (std::getenv("TT_BENCH_TRACE"))
        std::printf("    step %d: %.2f ms, %d its, %d factors, contact points %zu\n", s, stepMs,
                    report.linearIterations, integrator.diagnostics().factorizations,
                    contact->result().points.size());
      if (s < kUntimed) continue;  // the first factorisation and warm-up
      r.stepMs.push_back(stepMs);
      r.contactMs.push_back(contactMs);
      r.iterations.push_back(report.linearIterations);
      r.residuals.push_back(integrator.diagnostics().lastRelativeResidual);
      r.errors.push_back((scene.system.state.x - xRef).lpNorm<Eigen::Infinity>() /
                         (xRef - before.x).lpNorm<Eigen::Infinity>());
    }
    r.factorizations = integrator.diagnostics().factorizations;
    r.refused = integrator.diagnostics().notPositiveDefinite + integrator.diagnostics().amgFailures;
    setThreadCount(1);
    return r;
  }

  // One build of `M` from the step's matrix M + h c - h^2 K at the start state (ms).
  double buildMs(RebuiltPreconditioner& M) {
    Scene scene = loadScene(scenePath_);
    System& system = scene.system;
    auto contact = makeContact(scene);
    system.state = start_;
    contact->update();
    SparseMatrix A;
    system.assembleStiffness(system.state.x, A);
    A *= -kStep * kStep;
    for (int dof = 0; dof < system.numDofs(); ++dof)
      A.coeffRef(dof, dof) += system.mass[dof] + kStep * system.damping[dof];
    system.constrainMatrix(A);
    if (std::getenv("TT_BENCH_TRACE")) {
      const SparseMatrix At = A.transpose();
      std::printf("    asymmetry |A - A^T| / |A| = %.3e\n", (A - At).norm() / A.norm());
    }
    const auto t0 = Clock::now();
    const bool ok = M.rebuildNow(A);
    const double ms = 1e3 * seconds(t0);
    return ok ? ms : NAN;
  }

  // Force and stiffness assembly alone at the start state, median of 9 (ms), on `threads`.
  std::pair<double, double> forceAndAssemblyMs(int threads) {
    setThreadCount(threads);
    Scene scene = loadScene(scenePath_);
    System& system = scene.system;
    system.state = start_;
    Eigen::VectorXd f;
    SparseMatrix K;
    std::vector<double> force, assembly;
    for (int r = 0; r < 9; ++r) {
      auto t0 = Clock::now();
      system.computeForce(system.state.x, system.state.v, f);
      force.push_back(1e3 * seconds(t0));
      t0 = Clock::now();
      system.assembleStiffness(system.state.x, K);
      assembly.push_back(1e3 * seconds(t0));
    }
    setThreadCount(1);
    return {quantile(force, 0.5), quantile(assembly, 0.5)};
  }

  int tets() const { return tets_; }
  int dofs() const { return dofs_; }
  size_t contactPoints() const { return inContact_; }

 private:
  static constexpr double kStep = 0.01;
  static constexpr int kUntimed = 3;
  static constexpr double kToolRadius = 0.006;

  std::unique_ptr<TissueContact> makeContact(Scene& scene) const {
    ToolShape sphere;
    sphere.type = ToolShape::Type::kSphere;
    sphere.radius = kToolRadius;
    sphere.link = "tip";
    auto contact = std::make_unique<TissueContact>(scene.system, *scene.contact,
                                                   std::vector<ToolShape>{sphere});
    contact->setTool(toolPose_, {toolPose_}, 1.0, scene.system.state.t);
    return contact;
  }

  std::string scenePath_, psdScenePath_;
  int steps_;
  State start_;
  Eigen::Isometry3d toolPose_ = Eigen::Isometry3d::Identity();
  int tets_ = 0, dofs_ = 0;
  size_t inContact_ = 0;
};

}  // namespace

int runAll(int argc, char** argv) {
  tools::CommandLine options(argc, argv,
                             "bench_implicit_step [--quick] [--sizes N,N,...] [--csv FILE] "
                             "[--rows K,K,...] [--node-order rcm|morton|file]");
  const bool quick = options.flag("--quick");
  using Names = std::vector<std::string>;
  std::vector<int> sizes;
  for (const std::string& item :
       options.list("--sizes", quick ? Names{"3000"} : Names{"3000", "10000", "50000", "100000"})) {
    const int n = std::atoi(item.c_str());
    if (n < 100) options.fail("--sizes expects tet counts >= 100, got '" + item + "'");
    sizes.push_back(n);
  }
  const std::string csvPath = options.text("--csv", "");
  const Names rowList = options.list("--rows", quick ? Names{"6", "14"} : Names{});
  const int stepsOverride = quick ? 5 : 0;
  const std::string nodeOrder = options.text("--node-order", "");
  if (!nodeOrder.empty() && nodeOrder != "rcm" && nodeOrder != "morton" && nodeOrder != "file")
    options.fail("--node-order expects rcm, morton or file, got '" + nodeOrder + "'");
  options.finish();
  FILE* csv = csvPath.empty() ? nullptr : std::fopen(csvPath.c_str(), "w");
  if (!csvPath.empty() && !csv) options.fail("cannot write " + csvPath);
  if (csv)
    std::fprintf(csv, "tets,dofs,setup,preconditioner,backend,threads,tolerance,steps,step_ms_p50,"
                      "step_ms_p99,step_ms_max,contact_ms_p50,cg_iterations_p50,cg_iterations_max,"
                      "residual_p50,factorizations,refused,failed,error_p50,error_max\n");
  std::printf("bench_implicit_step: liver_palpation.yaml on TetGen refinements of its liver, a 6 mm "
              "sphere pressed 6 mm in; backward_euler h = 10 ms; %d hardware threads; CHOLMOD, "
              "Eigen SimplicialLDLT and hypre BoomerAMG\n", hardwareThreads());
  const auto cholmod = CholeskyBackend::kCholmod, simplicial = CholeskyBackend::kEigenSimplicial;
  const auto jacobi = Preconditioning::kJacobi, cholesky = Preconditioning::kCholesky,
             amg = Preconditioning::kAmg;
  const std::vector<Setup> setups = {
      {"jacobi, scenes before", jacobi, cholmod, 1, 1e-8},
      {"jacobi", jacobi, cholmod, 1, 1e-4},
      {"cholesky", cholesky, cholmod, 1, 1e-8},
      {"cholesky", cholesky, cholmod, 1, 1e-6},
      {"cholesky", cholesky, cholmod, 1, 1e-4},
      {"cholesky, scenes now", cholesky, cholmod, 1, 1e-3},
      {"cholesky", cholesky, cholmod, 2, 1e-3},
      {"cholesky", cholesky, simplicial, 1, 1e-3},
      {"cholesky, refactor > 5", cholesky, cholmod, 1, 1e-3, 5},
      {"cholesky, never refactor", cholesky, cholmod, 1, 1e-3, 1000000},
      {"amg", amg, cholmod, 1, 1e-3},
      {"amg", amg, cholmod, 2, 1e-3},
      {"amg, refactor > 30", amg, cholmod, 1, 1e-3, 30},
      {"cholesky, psd", cholesky, cholmod, 1, 1e-3, 15, true},
      {"cholesky, psd", cholesky, cholmod, 2, 1e-3, 15, true},
      {"jacobi, psd", jacobi, cholmod, 1, 1e-4, 15, true},
  };
  std::vector<char> wanted(setups.size(), rowList.empty());
  for (const std::string& item : rowList) {
    const int row = std::atoi(item.c_str());
    if (row < 1 || row > static_cast<int>(setups.size()))
      options.fail("--rows expects numbers in [1, " + std::to_string(setups.size()) + "], got '" +
                   item + "'");
    wanted[row - 1] = 1;
  }
  for (const int target : sizes) {
    int tets = 0;
    const std::string mesh = refinedLiver(target, tets);
    if (mesh.empty()) {
      std::printf("\nno TetGen refinement for %d tets (tetgen missing or failed; see %s)\n",
                  target, kWork.c_str());
      continue;
    }
    const int steps =
        stepsOverride > 0 ? stepsOverride : target <= 10000 ? 60 : target <= 50000 ? 20 : 10;
    Bench bench(sceneWithMesh(mesh, nodeOrder), sceneWithMesh(mesh, nodeOrder, true), steps);
    bench.prepare();
    CholeskyPreconditioner cholmodFactor(false, cholmod), simplicialFactor(false, simplicial);
    AmgPreconditioner warmUp, boomerAmg;  // the first set-up also initialises MPI
    bench.buildMs(warmUp);
    const double cholmodMs = bench.buildMs(cholmodFactor);
    const double simplicialMs = bench.buildMs(simplicialFactor);
    const double amgMs = bench.buildMs(boomerAmg);
    std::printf("\nliver %d tets, %d DOFs, %zu contact points, %d timed steps per row; one "
                "factorisation: CHOLMOD %.0f ms, SimplicialLDLT %.0f ms; one AMG set-up %.0f ms\n",
                bench.tets(), bench.dofs(), bench.contactPoints(), steps, cholmodMs,
                simplicialMs, amgMs);
    for (int threads : {1, 2}) {
      const auto [forceMs, assemblyMs] = bench.forceAndAssemblyMs(threads);
      std::printf("  %d thread(s): force %.2f ms, stiffness assembly %.2f ms\n", threads,
                  forceMs, assemblyMs);
    }
    std::printf("  %-22s %-14s %3s %7s %8s %8s %8s %8s %6s %6s %9s %4s %9s %9s\n", "setup",
                "backend", "thr", "tol", "p50 ms", "p99 ms", "max ms", "contact", "its", "max",
                "residual", "fact", "error p50", "error max");
    for (size_t row = 0; row < setups.size(); ++row) {
      const Setup& setup = setups[row];
      if (!wanted[row]) continue;
      if (setup.preconditioner == jacobi && setup.tolerance < 1e-6 && target > 50000) continue;
      const Result r = bench.run(setup);
      const char* backend = setup.preconditioner == cholesky ? backendName(setup.backend)
                            : setup.preconditioner == amg    ? "boomeramg"
                                                             : "-";
      const char* preconditioner = setup.preconditioner == cholesky ? "cholesky"
                                   : setup.preconditioner == amg    ? "amg"
                                                                    : "jacobi";
      std::printf("  %-22s %-14s %3d %7.0e %8.2f %8.2f %8.2f %8.2f %6.0f %6.0f %9.1e %4d %9.1e "
                  "%9.1e%s\n", setup.label, backend, setup.threads, setup.tolerance,
                  quantile(r.stepMs, 0.5), quantile(r.stepMs, 0.99), quantile(r.stepMs, 1.0),
                  quantile(r.contactMs, 0.5), quantile(r.iterations, 0.5),
                  quantile(r.iterations, 1.0), quantile(r.residuals, 0.5), r.factorizations,
                  quantile(r.errors, 0.5), quantile(r.errors, 1.0),
                  r.failed ? (" FAILED " + std::to_string(r.failed)).c_str() : "");
      std::fflush(stdout);
      if (csv)
        std::fprintf(csv, "%d,%d,%s,%s,%s,%d,%g,%zu,%.4f,%.4f,%.4f,%.4f,%.0f,%.0f,%.3e,%d,%d,%d,"
                          "%.3e,%.3e\n", bench.tets(), bench.dofs(), csvField(setup.label).c_str(),
                     preconditioner, backend,
                     setup.threads, setup.tolerance, r.stepMs.size(), quantile(r.stepMs, 0.5),
                     quantile(r.stepMs, 0.99), quantile(r.stepMs, 1.0),
                     quantile(r.contactMs, 0.5), quantile(r.iterations, 0.5),
                     quantile(r.iterations, 1.0), quantile(r.residuals, 0.5), r.factorizations,
                     r.refused, r.failed, quantile(r.errors, 0.5), quantile(r.errors, 1.0));
      if (csv) std::fflush(csv);
    }
  }
  if (csv) std::fclose(csv);
  return 0;
}

int main(int argc, char** argv) {
  try {
    return runAll(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_implicit_step: %s\n", e.what());
    return 2;
  }
}
