// Bullet's deformable solver beside ours on the refined liver of bench_implicit_step, in the
// same run: time per step and error, both from the same state under the same load.
//
// The state (bench_bullet_liver_state, run first in a process of its own): the liver
// palpation scene on its liver refined by TetGen (--tetgen q1.4a0.1: 10,771 tets; none: the
// scene's 596-tet liver), sagged to rest under gravity by our edge_length model; and the
// contact force of a 6 mm sphere pressed 6 mm into the anterior face (our TissueContact at
// the pressed state of bench_implicit_step).
// The contact is that force field held constant on the nodes, the same for both simulators
// (ours: System::externalForce; Bullet: a constant force applied as it applies gravity).
// Bullet's own deformable-rigid contact would be a different law (velocity constraints with
// friction against a signed-distance field, not our penalty), and our contact cannot run in
// this process (it links the single-precision Bullet), so the load is the one thing both
// can be given exactly.
//
// Both start from the sagged state at rest with the same nodes, tets, lumped masses, fixed
// nodes (the scene's box), gravity, mass damping (2/s) and material (E = 8 kPa, nu = 0.45),
// and take N steps of h = 10 ms on one thread:
//   ours    edge_length (the scene's model) and hyperelastic_neo_hookean, linearised backward
//           Euler as the scene runs it (CG on a Cholesky factor, CHOLMOD, tolerance 1e-3);
//           reference: the same step solved to 1e-10 (Jacobi-PCG, as bench_implicit_step).
//   Bullet  btDeformableLinearElasticityForce (corotated linear) and btDeformableNeoHookeanForce
//           (stable Neo-Hookean, its moduli set for our E and nu at rest), implicit,
//           projection on, configured as in bench_bullet_peer (bullet_deformable.h): its
//           defaults (5 Newton passes, CG up to 300 iterations at 1e-8), one Newton pass (a
//           linearised step, as ours) with CG up to 300 and up to 50 iterations; reference: 10
//           Newton passes, CG up to 1000 iterations at 1e-14 (a reference of 20 passes and
//           3000 iterations at 1e-16 changed no error of the table by more than 1 %). Bullet's
//           Newton stopping test (residual 2-norm below 1e-4 N s) never passed here: every
//           step runs all its passes.
// Per run: the wall time of each step (p50, p99 of N; ours: the first step factors the
// matrix), the Newton passes and linear iterations per step, the largest node displacement
// after N steps, the error after N steps against the same model's reference,
// max |x - x_ref| / max |x_ref - x_0| over the DOFs, and the same difference to our
// edge_length and hyperelastic_neo_hookean references. Between different models that
// difference includes the difference of the material laws (and of their sag: the start is
// the edge_length model's rest, which the other laws leave), and for Bullet's Newton passes
// that of a nonlinear against a linearised step.
// --no-load leaves the contact force out: how far each law moves from the start by itself.
// Writes DIR/bullet_liver.csv and prints the table.
//   bench_bullet_liver [--tetgen SWITCHES|none] [--steps N] [--out DIR] [--work DIR] [--no-load]
#include <Eigen/Core>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "bullet_deformable.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/scene.h"
#include "common/liver_bench_scene.h"

namespace {

using namespace tt;
namespace fs = std::filesystem;
using Clock = std::chrono::steady_clock;
using bench::quantile;

constexpr double kStep = 0.01;

struct Options {
  std::string tetgen = "q1.4a0.1";
  int steps = 20;
  bool noLoad = false;  // the contact force left out: how far each law leaves the start alone
  std::string out = "docs/report", work = "/tmp/tt_bench_bullet_liver";
};

// What bench_bullet_liver_state wrote.
struct Start {
  std::string scene;
  Eigen::VectorXd x, force;
};

struct Run {
  std::string simulator, model, setting;
  bool reference = false;
  std::vector<double> stepMs;
  double newtonPerStep = NAN, linearPerStep = NAN;
  Eigen::VectorXd x;  // after the last step
  std::string failure;
};

double msSince(Clock::time_point t0) {
  return 1e3 * std::chrono::duration<double>(Clock::now() - t0).count();
}

// max |a - b| / max |ref - x0| over the DOFs.
double relativeDifference(const Eigen::VectorXd& a, const Eigen::VectorXd& b,
                          const Eigen::VectorXd& ref, const Eigen::VectorXd& x0) {
  const double scale = (ref - x0).lpNorm<Eigen::Infinity>();
  if (a.size() == 0 || b.size() == 0 || scale < 1e-9) return NAN;  // the reference stays put
  return (a - b).lpNorm<Eigen::Infinity>() / scale;
}

// --- the start --------------------------------------------------------------------------------

// Runs bench_bullet_liver_state (beside this executable) and reads what it wrote.
Start prepareStart(const Options& o) {
  const fs::path helper = fs::read_symlink("/proc/self/exe").parent_path() / "bench_bullet_liver_state";
  const fs::path dir = fs::path(o.work) / o.tetgen;
  const std::string command =
      "'" + helper.string() + "' --out '" + dir.string() + "' --tetgen '" + o.tetgen + "'";
  if (std::system(command.c_str()) != 0) throw std::runtime_error("failed: " + command);
  std::ifstream in(dir / "state.txt");
  Start s;
  std::string key;
  int nodes = 0;
  in >> key >> s.scene >> key >> nodes;
  if (!in || nodes <= 0) throw std::runtime_error("unreadable " + (dir / "state.txt").string());
  s.x.resize(3 * nodes);
  s.force.resize(3 * nodes);
  for (int n = 0; n < nodes; ++n)
    in >> s.x[3 * n] >> s.x[3 * n + 1] >> s.x[3 * n + 2] >> s.force[3 * n] >> s.force[3 * n + 1] >>
        s.force[3 * n + 2];
  if (!in) throw std::runtime_error("truncated " + (dir / "state.txt").string());
  return s;
}

// The start's scene with our `model` (a preset: edge_length, hyperelastic_<law>), at the start
// state, the contact force applied.
Scene loadOurs(const Start& start, const std::string& model) {
  std::string path = start.scene;
  if (model != "edge_length") {
    std::ifstream in(start.scene);
    std::stringstream text;
    text << in.rdbuf();
    std::string scene = text.str();
    const std::string from = "  - type: edge_length";
    const size_t at = scene.find(from);
    if (at == std::string::npos || model.rfind("hyperelastic_", 0) != 0)
      throw std::runtime_error("cannot set the model " + model + " in " + start.scene);
    scene.replace(at, from.size(), "  - {type: hyperelastic, law: " + model.substr(13) + "}");
    path = start.scene + "." + model + ".yaml";
    std::ofstream(path) << scene;
  }
  Scene scene = loadScene(path);
  System& s = scene.system;
  if (s.numDofs() != start.x.size()) throw std::runtime_error(path + ": not the start's mesh");
  s.state.x = start.x;
  s.state.v.setZero();
  s.externalForce = start.force;
  return scene;
}

// Gravity and the mass damping rate of the scene, read back from its System: at rest with zero
// velocity the only force on a free node is its weight m g.
bullet::Loads sceneLoads(const System& system, const Eigen::VectorXd& contactForce) {
  const Eigen::VectorXd rest = system.mesh.rest.reshaped(), zero = Eigen::VectorXd::Zero(system.numDofs());
  Eigen::VectorXd f = zero;
  for (const auto& model : system.models) model->addForce(rest, zero, f);  // not the contact force
  int free = 0;
  while (system.isConstrained[3 * free]) ++free;
  bullet::Loads loads;
  loads.gravity = f.segment<3>(3 * free) / system.mass[3 * free];
  loads.dampingRate = system.damping[3 * free] / system.mass[3 * free];
  loads.nodalForce = contactForce;
  return loads;
}

// --- runs ---------------------------------------------------------------------------------------

Run runOurs(const Start& start, const std::string& model, const BackwardEulerParams& params,
            const std::string& setting, bool reference, int steps) {
  Scene scene = loadOurs(start, model);
  BackwardEulerIntegrator integrator(params);
  Run r;
  r.simulator = "ours", r.model = model, r.setting = setting, r.reference = reference;
  long linear = 0;
  for (int s = 0; s < steps && r.failure.empty(); ++s) {
    const auto t0 = Clock::now();
    const StepReport report = integrator.advance(scene.system, kStep);
    r.stepMs.push_back(msSince(t0));
    linear += report.linearIterations;
    if (!report.ok) r.failure = report.failure;
  }
  r.newtonPerStep = params.newtonIterations;
  r.linearPerStep = static_cast<double>(linear) / steps;
  r.x = scene.system.state.x;
  return r;
}

Run runBullet(const Start& start, const bullet::Settings& settings, const std::string& setting,
              bool reference, int steps) {
  Scene scene = loadOurs(start, "edge_length");  // the mesh, masses, constraints and state
  bullet::Body body(scene.system, settings, sceneLoads(scene.system, start.force));
  Run r;
  r.simulator = "bullet", r.model = settings.model, r.setting = setting, r.reference = reference;
  for (int s = 0; s < steps && r.failure.empty(); ++s) {
    const auto t0 = Clock::now();
    const int substeps = body.step(kStep);
    r.stepMs.push_back(msSince(t0));
    if (substeps != 1) r.failure = "Bullet took " + std::to_string(substeps) + " substeps";
  }
  // The explicit predictor of each step evaluates the forces once more (bench_bullet_peer).
  r.newtonPerStep = static_cast<double>(body.residuals() - steps) / steps;
  r.linearPerStep = static_cast<double>(body.products()) / steps;
  r.x.resize(start.x.size());
  Eigen::VectorXd v(start.x.size());
  body.read(r.x, v);
  if (!r.x.allFinite()) r.failure = "state not finite";
  return r;
}

std::vector<Run> runAll(const Start& start, int steps) {
  BackwardEulerParams scene;  // liver_palpation.yaml
  scene.preconditioner = BackwardEulerParams::Preconditioning::kCholesky;
  scene.linearTolerance = 1e-3;
  const BackwardEulerParams tight = bench::tightBackwardEuler();  // bench_implicit_step's reference
  std::vector<Run> runs;
  for (const std::string model : {"edge_length", "hyperelastic_neo_hookean"}) {
    runs.push_back(runOurs(start, model, tight, "jacobi 1e-10", true, steps));
    runs.push_back(runOurs(start, model, scene, "cholesky 1e-3 (scene)", false, steps));
  }
  for (const std::string model : {"bullet_linear_elasticity", "bullet_neohookean"}) {
    bullet::Settings settings;
    settings.model = model;
    bullet::Settings tightBullet = settings;
    tightBullet.newtonPasses = 10;
    tightBullet.krylovIterations = 1000;
    tightBullet.krylovTolerance = 1e-14;
    runs.push_back(runBullet(start, tightBullet, "newton 10 + cg 1000 x 1e-14", true, steps));
    runs.push_back(runBullet(start, settings, "newton 5 + cg 300 x 1e-8 (defaults)", false, steps));
    bullet::Settings onePass = settings;
    onePass.newtonPasses = 1;
    runs.push_back(runBullet(start, onePass, "newton 1 + cg 300 x 1e-8", false, steps));
    onePass.krylovIterations = 50;
    runs.push_back(runBullet(start, onePass, "newton 1 + cg 50 x 1e-8", false, steps));
  }
  return runs;
}

// --- output ----------------------------------------------------------------------------------

struct Errors {
  double error = NAN, toEdgeLength = NAN, toNeoHookean = NAN, displacement = NAN;
};

Errors errorsOf(const Run& run, const std::vector<Run>& runs, const Eigen::VectorXd& x0) {
  const auto differenceTo = [&](const std::string& model) {
    for (const Run& r : runs)
      if (r.reference && r.model == model) return relativeDifference(run.x, r.x, r.x, x0);
    return static_cast<double>(NAN);
  };
  Errors e;
  if (!run.failure.empty()) return e;
  if (!run.reference) e.error = differenceTo(run.model);
  e.toEdgeLength = differenceTo("edge_length");
  e.toNeoHookean = differenceTo("hyperelastic_neo_hookean");
  e.displacement = (run.x - x0).reshaped(3, x0.size() / 3).colwise().norm().maxCoeff();
  return e;
}

void report(const std::vector<Run>& runs, const Start& start, int tets, const Options& o) {
  const std::string path = o.out + "/bullet_liver.csv";
  FILE* csv = std::fopen(path.c_str(), "w");
  if (!csv) throw std::runtime_error("cannot write " + path);
  std::fprintf(csv, "tets,nodes,steps,h,simulator,model,setting,reference,step_ms_p50,step_ms_p99,"
                    "step_ms_max,newton_per_step,linear_per_step,max_displacement_m,error,"
                    "difference_to_edge_length,difference_to_neo_hookean,failure\n");
  std::printf("%-7s %-25s %-36s %8s %8s %6s %7s %9s %9s %9s %9s\n", "", "model", "setting",
              "p50 ms", "p99 ms", "newton", "lin its", "max disp", "error", "vs our EL", "vs our NH");
  for (const Run& r : runs) {
    const Errors e = errorsOf(r, runs, start.x);
    const double p50 = quantile(r.stepMs, 0.5), p99 = quantile(r.stepMs, 0.99);
    std::printf("%-7s %-25s %-36s %8.2f %8.2f %6.2f %7.1f %6.2f mm %9.2e %9.2e %9.2e%s%s\n",
                r.simulator.c_str(), r.model.c_str(), r.setting.c_str(), p50, p99, r.newtonPerStep,
                r.linearPerStep, 1e3 * e.displacement, e.error, e.toEdgeLength, e.toNeoHookean,
                r.reference ? "  (reference)" : "", r.failure.empty() ? "" : ("  FAILED: " + r.failure).c_str());
    std::fprintf(csv, "%d,%d,%d,%g,%s,%s,%s,%d,%.4f,%.4f,%.4f,%.3f,%.2f,%.6e,%.4e,%.4e,%.4e,%s\n", tets,
                 static_cast<int>(start.x.size() / 3), o.steps, kStep, r.simulator.c_str(),
                 r.model.c_str(), r.setting.c_str(), r.reference ? 1 : 0, p50, p99,
                 quantile(r.stepMs, 1.0), r.newtonPerStep, r.linearPerStep, e.displacement,
                 e.error, e.toEdgeLength, e.toNeoHookean, r.failure.c_str());
  }
  std::fclose(csv);
  std::printf("wrote %s\n", path.c_str());
}

Options parseOptions(int argc, char** argv) {
  tools::CommandLine options(argc, argv,
                             "bench_bullet_liver [--tetgen SWITCHES|none] [--steps N] [--out DIR] "
                             "[--work DIR] [--no-load]");
  Options o;
  o.tetgen = options.text("--tetgen", o.tetgen);
  o.steps = options.positiveInteger("--steps", o.steps);
  o.out = options.text("--out", o.out);
  o.work = options.text("--work", o.work);
  o.noLoad = options.flag("--no-load");
  options.finish();
  if (o.tetgen.empty() || o.tetgen.find_first_of("'/ ") != std::string::npos)
    options.fail("--tetgen expects TetGen switches such as q1.4a0.1, got '" + o.tetgen + "'");
  return o;
}

int run(const Options& o) {
  setThreadCount(1);
  fs::create_directories(o.out);
  const auto t0 = Clock::now();
  Start start = prepareStart(o);
  if (o.noLoad) start.force.setZero();
  const int tets = loadScene(start.scene).system.mesh.numTets();
  std::printf("bench_bullet_liver: liver_palpation.yaml, %d tets, %zu nodes, %s; %d steps of %g "
              "ms from the sagged state, one thread (start prepared in %.1f s)\n", tets,
              static_cast<size_t>(start.x.size() / 3),
              o.noLoad ? "no contact force (--no-load)" : "the contact force held constant",
              o.steps, 1e3 * kStep, msSince(t0) / 1e3);
  report(runAll(start, o.steps), start, tets, o);
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const Options o = parseOptions(argc, argv);
  try {
    return run(o);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_bullet_liver: %s\n", e.what());
    return 1;
  }
}
