// A peer, side by side: Bullet's deformable bodies (Debian's libbullet-dev 3.24, the
// double-precision build libBullet*-float64) on the beam problems of bench_work_precision,
// measured in the same process as our stvk_displacement + backward_euler pair at the same steps:
//   cantilever_static      damped to rest under 1 % of gravity; error of the tip deflection
//                          against Euler-Bernoulli, discrete error against our model's static
//                          solution of the same mesh (Newton, sparse Cholesky)
//   cantilever_vibration   free vibration in the first bending mode of the mesh; error of the
//                          first frequency against Euler-Bernoulli (and against the mesh mode)
//   beam_large_deflection  the soft beam falling under full gravity; error against the
//                          edge_length (StVK) Radau IIA reference, which for Bullet's models
//                          includes the difference of the material laws
// The problems, meshes, masses, damping, initial states and error measures are those of
// work_precision_problems.h; only the stepping differs.
//
// How Bullet is configured (read from its 3.24 headers, checked by the runs; the code is in
// bullet_deformable.h, shared with bench_bullet_liver):
//   - btDeformableMultiBodyDynamicsWorld with a btDeformableBodySolver, setImplicit(true) on
//     both, no line search. The implicit step is backward Euler in the velocity
//     increment: (M - h D - h^2 K) dv = h f(x_n + h v), x_{n+1} = x_n + h v_{n+1}, where the
//     explicit force of x_n is applied first as the initial guess. The Newton loop stops when
//     the 2-norm of the residual (N s) is below its tolerance, checked from the second pass
//     on (see Newton below).
//   - Projection on (setUseProjection(true)): the linear solve is Bullet's projected conjugate
//     gradients. With Bullet's default (no projection, conjugate residual with Lagrange
//     multipliers) the implicit step leaves the clamped beam at rest: its velocity increment
//     stays zero (recorded once per model as bullet_backward_euler_no_projection, stable = 0).
//   - Krylov solver: default 300 iterations and an absolute max-norm residual tolerance of
//     1e-8 N s. The step sweep runs these defaults; a second sweep caps the iterations
//     (10 ... 300) at a tight tolerance (1e-15 N s) at the middle step.
//   - Newton: Bullet's default of at most 5 passes. Its stopping test (2-norm of the residual
//     below 1e-4 N s) is met after 2 passes in free vibration; under gravity every step ran
//     all 5 passes.
//   - One btSoftBody built from our mesh's nodes and tets (node arrays, appendTetra,
//     initializeDmInverse), node masses = our lumped masses, clamped nodes mass 0, no collision,
//     no self collision, no drag, deactivation disabled.
//   - bullet_linear_elasticity: btDeformableLinearElasticityForce, which is corotated (polar
//     rotation of F, small strain in the rotated frame), mu = E / (2 (1 + nu)),
//     lambda = E nu / ((1 + nu) (1 - 2 nu)), its own damping off (alpha = beta = 0).
//   - bullet_neohookean: btDeformableNeoHookeanForce, the stable Neo-Hookean energy
//     mu/2 (I_C - 3) + lambda/2 (J - 1 - 3 mu / (4 lambda))^2 - mu/2 log(I_C + 1). Its small-
//     strain moduli are 3/4 mu and lambda - 5/8 mu, so it gets mu' = 4/3 mu and
//     lambda' = lambda + 5/6 mu to have the same E and nu at rest (with Bullet's own
//     setYoungsModulus/setPoissonRatio its shear modulus at rest would be 3/4 of ours); damping off.
//   - Damping: our mass-proportional damping -c m v (the problem's rate c) as a small
//     btDeformableLagrangianForce of this file (force, velocity differential, diagonal), so
//     both Bullet models and ours damp alike. The same force counts the solver's calls.
//   - Gravity: btDeformableGravityForce with the problem's g; world gravity zero.
//   - Counts: steps = stepSimulation substeps; newton_iterations = residual evaluations less
//     the explicit predictor's one per step (checked: 1 per step with 1 pass); linear_iterations = matrix-vector products of the linear solver.
//   - Bullet replaces a NaN velocity increment by zero; a run whose state is not finite or
//     moves more than 10 body sizes is recorded stable = 0.
// Writes DIR/bullet_peer.csv (the columns of work_precision.csv; Bullet's rows and the pair's
// rows of this run) and prints a table with the ratios to the pair at the same step.
//   bench_bullet_peer [--quick] [--out DIR] [--pair MODEL] [--problems a,b] [--time-limit S]
//                     [--bullet-newton N]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "bullet_deformable.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "common/work_precision/csv.h"
#include "common/work_precision/problem.h"
#include "tissue_trainer/core/parallel.h"

namespace {

using namespace tt;
using namespace tt::work_precision;
using BulletSettings = bullet::Settings;

// --- runs ------------------------------------------------------------------------------------

struct Options {
  bool quick = false;
  std::string out = "docs/report", pair = "stvk_displacement";
  std::vector<std::string> problems;
  double timeLimit = 20.0;  // s of CPU time per run
  int bulletNewton = 5;     // Bullet's default Newton passes
};

struct Row {
  std::string problem, model, integrator, parameterName;
  double parameter;
  RunResult r;
};

// What one frame of a run did.
struct Frame {
  bool ok = true;
  std::string failure;
  long steps = 0, newton = 0, linear = 0;
};

// The frame loop shared by both sides: advance(frame) steps one frame and fills x, v.
RunResult runFrames(const Problem& p, const std::string& evaluateAs, const System& start,
                    double frame, double timeLimit,
                    const std::function<Frame(Eigen::VectorXd&, Eigen::VectorXd&)>& advance) {
  RunResult r;
  r.tets = start.mesh.numTets();
  const Eigen::VectorXd rest = start.mesh.rest.reshaped();
  Eigen::VectorXd x = start.state.x, v = start.state.v;
  Trajectory t;
  t.t.push_back(0.0);
  t.x.push_back(x);
  t.v.push_back(v);
  const int frames = static_cast<int>(std::lround(p.duration / frame));
  const double cpu0 = bench::cpuSeconds(), wall0 = bench::wallSeconds();
  for (int f = 0; f < frames && r.stable; ++f) {
    const Frame done = advance(x, v);
    r.steps += done.steps;
    r.newton += done.newton;
    r.linear += done.linear;
    const std::string problem = done.ok ? blowUp(x, v, rest, p.bodySize) : done.failure;
    if (!problem.empty()) {
      r.stable = false;
      r.errors.note = problem;
    }
    t.t.push_back((f + 1) * frame);
    t.x.push_back(x);
    t.v.push_back(v);
    if (bench::cpuSeconds() - cpu0 > timeLimit && f + 1 < frames) {
      r.errors.note = "stopped at the time limit (t = " + std::to_string((f + 1) * frame) + " s)";
      break;
    }
  }
  r.cpu = bench::cpuSeconds() - cpu0;
  r.wall = bench::wallSeconds() - wall0;
  if (r.stable && r.errors.note.empty()) r.errors = p.evaluate(evaluateAs, t);
  return r;
}

// The problem's load and damping rate, read back from the System it builds (the elastic force
// is zero at rest, so the force at rest and zero velocity is the gravity m g).
void loadAndDamping(const System& s, double& gravity, double& dampingRate) {
  Eigen::VectorXd f;
  s.computeForce(s.mesh.rest.reshaped(), Eigen::VectorXd::Zero(s.numDofs()), f);
  int free = 0;
  while (s.isConstrained[3 * free]) ++free;
  gravity = -f[3 * free + 2] / s.mass[3 * free + 2];
  dampingRate = s.damping[3 * free] / s.mass[3 * free];
}

RunResult runBullet(const Problem& p, const std::string& pair, const BulletSettings& settings,
                    double h, int substeps, double timeLimit) {
  auto s = p.build(pair);
  double gravity = 0.0, dampingRate = 0.0;
  loadAndDamping(*s, gravity, dampingRate);
  bullet::Body beam(*s, settings, {Eigen::Vector3d(0, 0, -gravity), dampingRate, {}});
  const bool largeDeformation = p.name == "beam_large_deflection";
  RunResult r = runFrames(p, pair, *s, h * substeps, timeLimit,
                          [&](Eigen::VectorXd& x, Eigen::VectorXd& v) {
                            Frame f;
                            const long res0 = beam.residuals(), mv0 = beam.products();
                            for (int k = 0; k < substeps; ++k) f.steps += beam.step(h);
                            // The explicit predictor of each step calls the same routine once.
                            f.newton = beam.residuals() - res0 - f.steps;
                            f.linear = beam.products() - mv0;
                            beam.read(x, v);
                            if (f.steps != substeps) {
                              f.ok = false;
                              f.failure = "Bullet took a different number of substeps";
                            }
                            return f;
                          });
  // No exact solution of Bullet's own models here: the discrete error is against ours.
  if (largeDeformation) r.errors.discrete = kNaN;
  return r;
}

RunResult runOurs(const Problem& p, const std::string& model, double h, int substeps,
                  double timeLimit) {
  auto s = p.build(model);
  BackwardEulerParams params = bench::jacobiBackwardEuler();
  params.substeps = substeps;
  params.newtonIterations = 1;
  params.linearMaxIterations = 2000;
  BackwardEulerIntegrator integrator(params);
  const double frame = h * substeps;
  return runFrames(p, model, *s, frame, timeLimit, [&](Eigen::VectorXd& x, Eigen::VectorXd& v) {
    const StepReport step = integrator.advance(*s, frame);
    x = s->state.x;
    v = s->state.v;
    Frame f;
    f.ok = step.ok;
    f.failure = step.failure;
    f.steps = step.substeps;
    f.newton = step.newtonIterations;
    f.linear = step.linearIterations;
    return f;
  });
}

// --- output ----------------------------------------------------------------------------------

void writeRow(FILE* csv, const Row& row) {
  writeRunRow(csv, row.problem, row.model, row.integrator, row.parameterName, row.parameter, row.r);
}

Options parseOptions(int argc, char** argv) {
  tools::CommandLine options(argc, argv,
                             "bench_bullet_peer [--quick] [--out DIR] [--pair MODEL] "
                             "[--problems a,b] [--time-limit S] [--bullet-newton N]");
  Options o;
  o.quick = options.flag("--quick");
  o.out = options.text("--out", o.out);
  o.pair = options.text("--pair", o.pair);
  o.problems = options.list("--problems", {});
  o.timeLimit = options.positiveNumber("--time-limit", o.quick ? 5.0 : o.timeLimit);
  o.bulletNewton = options.positiveInteger("--bullet-newton", o.bulletNewton);
  options.finish();
  bench::requireKnown("bench_bullet_peer", "--pair model", {o.pair}, bench::elasticModelNames());
  return o;
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const Options o = parseOptions(argc, argv);
  setThreadCount(1);

  const std::vector<std::string> names = {"cantilever_static", "cantilever_vibration",
                                          "beam_large_deflection"};
  bench::requireKnown("bench_bullet_peer", "problem", o.problems, names);
  std::vector<std::unique_ptr<Problem>> problems;
  for (const std::string& name : names)
    if (bench::selected(o.problems, name)) problems.push_back(makeProblem(name, o.quick));
  std::filesystem::create_directories(o.out);  // after the names were checked

  const std::string csvPath = o.out + "/bullet_peer.csv";
  FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "bench_bullet_peer: cannot write %s\n", csvPath.c_str());
    return 1;
  }
  std::fprintf(csv, "%s\n", kCsvHeader);
  const std::vector<std::string> bulletModels = {"bullet_linear_elasticity", "bullet_neohookean"};
  std::printf("%-22s %-25s %-18s %10s %10s %9s %10s %9s %8s %8s\n", "problem", "model", "parameter",
              "error", "discrete", "cpu s", "our error", "our cpu s", "err/our", "cpu/our");
  int rows = 0;
  for (auto& p : problems) {
    const double wall0 = bench::wallSeconds();
    p->prepare({o.pair});
    std::printf("# prepared %s in %.1f s\n", p->name.c_str(), bench::wallSeconds() - wall0);
    std::vector<double> steps = p->implicitSteps;
    if (o.quick) steps.resize(std::min<size_t>(2, steps.size()));
    // The Krylov iteration sweep at the middle step of the sweep, tight tolerance.
    const double capStep = steps[steps.size() / 2];
    const std::vector<int> caps = o.quick ? std::vector<int>{20} : std::vector<int>{10, 30, 100, 300};
    for (double step : steps) {
      const double frame = std::max(step, p->sampleInterval);
      const int substeps = static_cast<int>(std::lround(frame / step));
      const double h = frame / substeps;
      Row ours{p->name, o.pair, "backward_euler", "h", h, runOurs(*p, o.pair, h, substeps, o.timeLimit)};
      writeRow(csv, ours);
      ++rows;
      std::vector<Row> peers;
      for (const std::string& model : bulletModels) {
        BulletSettings settings;
        settings.model = model;
        settings.newtonPasses = o.bulletNewton;
        if (step == steps.front() && p->name == "cantilever_static") {
          // Bullet's default linear solve (conjugate residual, no projection) with mass-0 nodes.
          BulletSettings plain = settings;
          plain.projection = false;
          Row row{p->name, model, "bullet_backward_euler_no_projection", "h", h,
                  runBullet(*p, o.pair, plain, h, substeps, o.timeLimit)};
          if (row.r.stable && row.r.errors.error > 0.999) {
            row.r.stable = false;
            row.r.errors.note = "the body stays at rest (velocity increment zero)";
          }
          peers.push_back(row);
        }
        peers.push_back({p->name, model, "bullet_backward_euler", "h", h,
                         runBullet(*p, o.pair, settings, h, substeps, o.timeLimit)});
        if (step == capStep)
          for (int cap : caps) {
            settings.krylovIterations = cap;
            settings.krylovTolerance = 1e-15;
            peers.push_back({p->name, model, "bullet_backward_euler", "cg_max_iterations", double(cap),
                             runBullet(*p, o.pair, settings, h, substeps, o.timeLimit)});
          }
      }
      std::printf("%-22s %-25s h = %-14.4g %10.3g %10.3g %9.3g %10s %9s %8s %8s  (%ld steps, %ld lin)\n",
                  p->name.c_str(), o.pair.c_str(), h, ours.r.errors.error, ours.r.errors.discrete,
                  ours.r.cpu, "", "", "", "", ours.r.steps, ours.r.linear);
      for (const Row& row : peers) {
        writeRow(csv, row);
        ++rows;
        char parameter[64];
        std::snprintf(parameter, sizeof parameter, "%s = %.4g", row.parameterName == "h" ? "h" : "cg its",
                      row.parameter);
        std::printf("%-22s %-25s %-18s %10.3g %10.3g %9.3g %10.3g %9.3g %8.3g %8.3g  (%ld steps, %ld "
                    "newton, %ld lin) %s%s\n",
                    "", row.model.c_str(), parameter, row.r.errors.error, row.r.errors.discrete, row.r.cpu,
                    ours.r.errors.error, ours.r.cpu, row.r.errors.error / ours.r.errors.error,
                    row.r.cpu / ours.r.cpu, row.r.steps, row.r.newton, row.r.linear,
                    row.r.stable ? "" : " unstable: ", row.r.errors.note.c_str());
      }
    }
  }
  std::fclose(csv);
  std::printf("wrote %s (%d rows)\n", csvPath.c_str(), rows);
  return 0;
}
