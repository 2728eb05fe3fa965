// Work-precision benchmark: every elastic force model the factory offers x every integrator x
// a sweep of step sizes (explicit and backward Euler) or tolerances (Radau IIA, abm3,
// rk4_adaptive), on
//   1. cantilever_static      small deflection under a body load, damped to steady state;
//                             error against the Euler-Bernoulli tip deflection
//      cantilever_static_mesh mesh convergence of the same (static Newton, no integrator)
//   2. cantilever_vibration   free vibration in the first bending mode; error of the first
//                             natural frequency against Euler-Bernoulli
//   3. beam_large_deflection  the soft beam falling under gravity, and
//      spindle_pull           the spindle muscle pulled by one node; error against Radau IIA
//                             at a very tight tolerance
//   4. patch                  affine boundary motion; error against the affine field
//   5. uniaxial_stretch       a myocardium cube stretched 15 % along its fibres, for the two
//                             Adamss tissue presets only (common/work_precision/
//                             uniaxial_stretch.cpp); error of the end stress against the
//                             Hunter law
//   6. muscle_contraction     a muscle block contracting to equilibrium at activation 0.5, for
//                             the teran_muscle tissue presets only (work_precision_muscle.h);
//                             error against the equilibrium of the same model
// Problems 1 to 4 run the presets of the registry's models (one force model each); 5 and 6 the
// tissue presets they are written for.
// The static problems (1 and 6) also run the quasistatic solver: one frame, the equilibrium
// at a sweep of tolerances (Jacobi- and Cholesky-preconditioned CG); the mesh-refinement runs
// of 1 run it beside the bench's own static Newton.
// Each run's error and CPU / wall time are measured in this process (one thread). --quick: two
// presets (edge_length, tensor_mass) and the two Adamss models, one step or tolerance per
// integrator, looser references.
// Writes DIR/work_precision.csv (one row per run) and DIR/work_precision_facts.csv (the
// analytic values, references and their accuracy).
//   bench_work_precision [--quick] [--out DIR] [--problems a,b] [--models a,b]
//                        [--integrators a,b] [--time-limit S] [--repeats N]
// --integrators: the runs of these integrators only (static_newton: the mesh-refinement runs;
// quasistatic_cholesky also runs them).
// --time-limit: CPU seconds per run (default 20; 3 with --quick); a run past it stops and is
// listed without an error.
// --repeats: each run N times (default 1); the row is the run of the median CPU time.
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
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/abm3.h"
#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/integrate/rk4_adaptive.h"
#include "common/work_precision/csv.h"
#include "common/work_precision/problem.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/registry/registry.h"

namespace {

using namespace tt;
using namespace tt::work_precision;

struct Options {
  bool quick = false;
  std::string out = "docs/report";
  std::vector<std::string> problems, models;  // empty: all
  std::vector<std::string> integrators;       // empty: all
  double timeLimit = 20.0;                    // s of CPU time per run
  int repeats = 1;
};

struct IntegratorSpec {
  std::string integrator, parameterName;
  double parameter = 0.0;  // the step actually taken (s) or the relative tolerance
  double frame = 0.0;      // s per advance() call
  std::function<std::unique_ptr<Integrator>()> make;
};

// --- the sweeps ------------------------------------------------------------------------------

// Explicit methods: fractions of the stability limit 2 / omega_max, as equal substeps of the
// sample interval.
std::vector<IntegratorSpec> explicitSweep(const Problem& p, bool quick) {
  const std::vector<double> fractions =
      quick ? std::vector<double>{0.5} : std::vector<double>{1.5, 0.9, 0.5, 0.25, 0.125};
  std::vector<IntegratorSpec> specs;
  for (const char* name : {"newtonian", "symplectic_euler", "explicit_euler"})
    for (double fraction : fractions) {
      const double frame = p.sampleInterval;
      const double h = frame / std::ceil(frame / (fraction * p.stableStep) * (1 - 1e-12));
      const std::string integrator = name;
      auto make = [integrator, h]() -> std::unique_ptr<Integrator> {
        if (integrator == "newtonian") return std::make_unique<NewtonianIntegrator>(NewtonianParams{h});
        return std::make_unique<ExplicitEulerIntegrator>(
            ExplicitEulerParams{h, integrator == "symplectic_euler"});
      };
      specs.push_back({integrator, "h", h, frame, make});
    }
  return specs;
}

// Backward Euler, linearised ("Adamss: Advanced Anisotropic Mass-Spring System",
// Eqs. 2.142-2.148) and with full Newton: steps longer than the sample
// interval are one step per frame, shorter ones equal substeps of it.
std::vector<IntegratorSpec> backwardEulerSweep(const Problem& p, bool quick) {
  std::vector<double> steps = p.implicitSteps;
  if (quick) steps.resize(std::min<size_t>(2, steps.size()));
  std::vector<IntegratorSpec> specs;
  for (int newton : {1, 8})
    for (double step : steps) {
      const double frame = std::max(step, p.sampleInterval);
      BackwardEulerParams params = bench::jacobiBackwardEuler();
      params.substeps = static_cast<int>(std::lround(frame / step));
      params.newtonIterations = newton;
      params.linearMaxIterations = 2000;
      const double h = frame / params.substeps;
      specs.push_back({newton == 1 ? "backward_euler" : "backward_euler_newton", "h", h, frame,
                       [params] { return std::make_unique<BackwardEulerIntegrator>(params); }});
    }
  return specs;
}

std::vector<IntegratorSpec> radauSweep(const Problem& p, bool quick) {
  const std::vector<double> tolerances =
      quick ? std::vector<double>{1e-3} : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
  std::vector<IntegratorSpec> specs;
  for (double tol : tolerances) {
    const RadauOptions options = radauOptions(p, tol);
    specs.push_back({"radau_iia", "rtol", tol, p.sampleInterval,
                     [options] { return std::make_unique<RadauIIA>(options); }});
  }
  return specs;
}

// An explicit method with its own error control (abm3: the predictor-corrector difference;
// rk4_adaptive: the step-doubling estimate), held at the tolerances Radau IIA gets.
template <class Params, class Method>
std::vector<IntegratorSpec> explicitAdaptiveSweep(const char* name, const Problem& p, bool quick) {
  const std::vector<double> tolerances =
      quick ? std::vector<double>{1e-3} : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7};
  std::vector<IntegratorSpec> specs;
  for (double tol : tolerances) {
    const RadauOptions radau = radauOptions(p, tol);
    Params params;
    params.absTol = radau.absTol;
    params.absTolVelocity = radau.absTolVelocity;
    params.relTol = radau.relTol;
    params.timeStep = std::min(radau.initialStep, 0.5 * p.stableStep);
    specs.push_back({name, "rtol", tol, p.sampleInterval,
                     [params] { return std::make_unique<Method>(params); }});
  }
  return specs;
}

// The Adams-Bashforth-Moulton predictor-corrector with its halving/doubling control.
std::vector<IntegratorSpec> abm3Sweep(const Problem& p, bool quick) {
  return explicitAdaptiveSweep<Abm3Params, Abm3Integrator>("abm3", p, quick);
}

// The classical Runge-Kutta method with step doubling (Jeffrey, Appendix A, after Numerical
// Recipes Sec. 16.2).
std::vector<IntegratorSpec> rk4AdaptiveSweep(const Problem& p, bool quick) {
  return explicitAdaptiveSweep<Rk4AdaptiveParams, Rk4AdaptiveIntegrator>("rk4_adaptive", p, quick);
}

// ---- backward Euler under the iteration-count step control -------------------------------------
// "Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.5.5: GMRES, one linearised step, the
// step halved when the Krylov iterations reach upper_iterations and doubled at lower_iterations
// = upper / 4 or below, from the shortest step of the backward Euler sweep, in frames of the
// sample interval (which bound the step). The sweep is over the upper limit: a higher one
// lets the steps grow longer.
std::vector<IntegratorSpec> iterationControlSweep(const Problem& p, bool quick) {
  const std::vector<int> uppers =
      quick ? std::vector<int>{40} : std::vector<int>{10, 20, 40, 80, 160};
  const double shortest = *std::min_element(p.implicitSteps.begin(), p.implicitSteps.end());
  std::vector<IntegratorSpec> specs;
  for (int upper : uppers) {
    BackwardEulerParams params = bench::jacobiBackwardEuler();
    params.adaptive = true;
    params.linearSolver = BackwardEulerParams::LinearSolver::kGmres;
    params.linearMaxIterations = 2000;
    params.upperIterations = upper;
    params.lowerIterations = upper / 4;
    params.maxStep = p.sampleInterval;
    params.initialStep = std::min(shortest, p.sampleInterval);
    params.minStep = 1e-3 * params.initialStep;
    specs.push_back({"backward_euler_adaptive", "upper_iterations", static_cast<double>(upper),
                     p.sampleInterval,
                     [params] { return std::make_unique<BackwardEulerIntegrator>(params); }});
  }
  return specs;
}

// The quasistatic solver on a static problem: one frame over the whole duration, converged at
// a relative tolerance rtol of the residual at the start (the absolute one out of the way),
// each CG solve to 1e-2 rtol (at least 1e-12), with Jacobi or sparse Cholesky preconditioning.
EquilibriumParams quasistaticParams(double tol, bool cholesky) {
  EquilibriumParams params;
  params.relativeTolerance = tol;
  params.absoluteTolerance = 1e-300;
  params.linearTolerance = std::max(1e-12, 1e-2 * tol);
  params.preconditioner = cholesky ? EquilibriumParams::Preconditioning::kCholesky
                                   : EquilibriumParams::Preconditioning::kJacobi;
  return params;
}

std::vector<IntegratorSpec> quasistaticSweep(const Problem& p, bool quick) {
  const std::vector<double> tolerances =
      quick ? std::vector<double>{1e-6}
            : std::vector<double>{1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8, 1e-10};
  std::vector<IntegratorSpec> specs;
  for (bool cholesky : {false, true})
    for (double tol : tolerances) {
      const EquilibriumParams params = quasistaticParams(tol, cholesky);
      specs.push_back({cholesky ? "quasistatic_cholesky" : "quasistatic", "rtol", tol, p.duration,
                       [params] { return std::make_unique<QuasistaticIntegrator>(params); }});
    }
  return specs;
}

std::vector<IntegratorSpec> allIntegrators(const Problem& p, bool quick) {
  std::vector<IntegratorSpec> specs = explicitSweep(p, quick);
  for (auto& s : backwardEulerSweep(p, quick)) specs.push_back(s);
  for (auto& s : radauSweep(p, quick)) specs.push_back(s);
  for (auto& s : abm3Sweep(p, quick)) specs.push_back(s);
  for (auto& s : rk4AdaptiveSweep(p, quick)) specs.push_back(s);
  for (auto& s : iterationControlSweep(p, quick)) specs.push_back(s);
  if (p.isStatic)
    for (auto& s : quasistaticSweep(p, quick)) specs.push_back(s);
  return specs;
}

// --- one run -----------------------------------------------------------------------------------

void record(Trajectory& t, const State& s) {
  t.t.push_back(s.t);
  t.x.push_back(s.x);
  t.v.push_back(s.v);
}

void addReport(RunResult& r, const StepReport& step) {
  r.steps += step.substeps;
  r.rejected += step.rejected;
  r.newton += step.newtonIterations;
  r.linear += step.linearIterations;
}

RunResult runOnce(const Problem& p, const std::string& model, const IntegratorSpec& spec,
                  double timeLimit) {
  auto system = p.build(model);
  auto integrator = spec.make();
  RunResult r;
  r.tets = system->mesh.numTets();
  Trajectory trajectory;
  record(trajectory, system->state);
  const int frames = static_cast<int>(std::lround(p.duration / spec.frame));
  const double cpu0 = bench::cpuSeconds(), wall0 = bench::wallSeconds();
  for (int f = 0; f < frames && r.stable; ++f) {
    const StepReport step = integrator->advance(*system, spec.frame);
    addReport(r, step);
    const State& state = system->state;
    const std::string problem =
        step.ok ? blowUp(state.x, state.v, system->mesh.rest.reshaped(), p.bodySize) : step.failure;
    if (!problem.empty()) {
      r.stable = false;
      r.errors.note = problem;
    }
    record(trajectory, system->state);
    if (bench::cpuSeconds() - cpu0 > timeLimit && f + 1 < frames) {
      r.errors.note = "stopped at the time limit (t = " + std::to_string(system->state.t) + " s)";
      break;
    }
  }
  r.cpu = bench::cpuSeconds() - cpu0;
  r.wall = bench::wallSeconds() - wall0;
  if (r.stable && r.errors.note.empty()) r.errors = p.evaluate(model, trajectory);
  return r;
}

// The run of the median CPU time among `repeats` runs of `once` (the upper median of an even
// count).
RunResult medianRun(int repeats, const std::function<RunResult()>& once) {
  std::vector<RunResult> runs;
  for (int k = 0; k < repeats; ++k) runs.push_back(once());
  std::sort(runs.begin(), runs.end(),
            [](const RunResult& a, const RunResult& b) { return a.cpu < b.cpu; });
  return runs[runs.size() / 2];
}

// --- output ------------------------------------------------------------------------------------

void progress(int done, int total, const std::string& what, const RunResult& r) {
  std::printf("progress %d/%d %s: error %.3g, cpu %.3g s%s%s\n", done, total, what.c_str(),
              r.errors.error, r.cpu, r.stable ? "" : ", unstable: ",
              r.stable ? "" : r.errors.note.c_str());
}

// --- cantilever mesh convergence (static Newton with a sparse Cholesky solve) ------------------

// integrator: static_newton (the bench's own Newton, sparse Cholesky) or
// quasistatic_cholesky (the quasistatic solver at rtol 1e-8, one frame: 1e-10 is below the
// round-off of the residual on these beams).
struct MeshRun {
  int cellsAcross;
  std::string model, integrator;
};

RunResult meshConvergenceRun(const MeshRun& run) {
  Beam beam;
  beam.cellsAcross = run.cellsAcross;
  const double g = 0.0981;
  auto s = beamSystem(beam, run.model, g, 0.0);
  RunResult r;
  r.tets = s->mesh.numTets();
  Eigen::VectorXd x = s->mesh.rest.reshaped();
  const double cpu0 = bench::cpuSeconds(), wall0 = bench::wallSeconds();
  if (run.integrator == "static_newton") {
    const int iterations = staticEquilibrium(*s, x, 1e-14);
    r.steps = 1;
    if (iterations == kNoEquilibrium) {
      r.stable = false;
      r.errors.note = "static_newton: no solution from rest (a singular factorisation, or no "
                      "convergence in 50 Newton iterations)";
    } else {
      r.newton = r.linear = iterations;
    }
  } else {
    QuasistaticIntegrator quasistatic(quasistaticParams(1e-8, true));
    const StepReport step = quasistatic.advance(*s, 1.0);
    addReport(r, step);
    x = s->state.x;
    if (!step.ok) {
      r.stable = false;
      r.errors.note = step.failure;
    }
  }
  r.cpu = bench::cpuSeconds() - cpu0;
  r.wall = bench::wallSeconds() - wall0;
  if (!r.stable) return r;
  const double tip = -meanOf(x, s->mesh.rest, tipNodes(s->mesh, beam.length)).z();
  r.errors.error = relative(tip, beam.tipDeflection(g));
  r.errors.note = "tip deflection " + std::to_string(tip) + " m";
  return r;
}

// --- main --------------------------------------------------------------------------------------

// Whether `model` is the preset of one registered force model (not a tissue preset).
bool isModelPreset(const std::string& model) {
  static const std::vector<std::string> names = bench::elasticModelNames();
  return std::find(names.begin(), names.end(), model) != names.end();
}

// The chosen models a problem runs: its own (tissue presets), or else the models' presets.
std::vector<std::string> modelsOf(const Problem& p, const std::vector<std::string>& chosen) {
  std::vector<std::string> out;
  for (const std::string& m : chosen)
    if (p.models.empty() ? isModelPreset(m) : bench::selected(p.models, m)) out.push_back(m);
  return out;
}

Options parseOptions(int argc, char** argv) {
  tools::CommandLine options(argc, argv,
                             "bench_work_precision [--quick] [--repeats N] [--out DIR] "
                             "[--problems a,b] [--models a,b] [--integrators a,b] [--time-limit S]");
  Options o;
  o.quick = options.flag("--quick");
  o.repeats = options.positiveInteger("--repeats", o.repeats);
  o.out = options.text("--out", o.out);
  o.problems = options.list("--problems", {});
  o.models = options.list("--models", {});
  o.integrators = options.list("--integrators", {});
  o.timeLimit = options.positiveNumber("--time-limit", o.quick ? 3.0 : o.timeLimit);
  options.finish();
  bench::requireKnown("bench_work_precision", "integrator", o.integrators,
                      {"newtonian", "symplectic_euler", "explicit_euler", "backward_euler",
                       "backward_euler_newton", "radau_iia", "abm3", "rk4_adaptive",
                       "backward_euler_adaptive",
                       "static_newton", "quasistatic", "quasistatic_cholesky"});
  if (o.quick && o.models.empty())
    o.models = {"edge_length", "tensor_mass", "adamss_hunter", "adamss_springs",
                "teran_muscle_inversion_psd"};
  return o;
}

std::vector<std::unique_ptr<Problem>> makeProblems(const Options& o) {
  std::vector<std::string> names = {"cantilever_static_mesh"};  // the mesh-refinement runs
  for (const std::string& name : problemNames()) names.push_back(name);
  bench::requireKnown("bench_work_precision", "problem", o.problems, names);
  std::vector<std::unique_ptr<Problem>> chosen;
  for (const std::string& name : problemNames())
    if (bench::selected(o.problems, name)) chosen.push_back(makeProblem(name, o.quick));
  return chosen;
}

void writeFacts(const std::string& path, const std::vector<std::unique_ptr<Problem>>& problems) {
  FILE* f = std::fopen(path.c_str(), "w");
  std::fprintf(f, "problem,quantity,value,unit,meaning\n");
  for (const auto& p : problems)
    for (const Fact& fact : p->facts)
      std::fprintf(f, "%s,%s,%.9g,%s,%s\n", p->name.c_str(), fact.quantity.c_str(), fact.value,
                   fact.unit.c_str(), csvText(fact.meaning).c_str());
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  const Options options = parseOptions(argc, argv);
  setThreadCount(1);
  std::vector<std::string> models = registry().presetNames();
  bench::keepOnly("bench_work_precision", "model", models, options.models);
  auto problems = makeProblems(options);  // names checked before anything is written
  std::filesystem::create_directories(options.out);

  for (auto& p : problems) {
    const double wall0 = bench::wallSeconds();
    p->prepare(modelsOf(*p, models));
    std::printf("prepared %s in %.1f s\n", p->name.c_str(), bench::wallSeconds() - wall0);
  }
  std::vector<MeshRun> meshRuns;
  if (bench::selected(options.problems, "cantilever_static_mesh"))
    for (const char* integrator : {"static_newton", "quasistatic_cholesky"})
      if (bench::selected(options.integrators, integrator))
        for (int cells : options.quick ? std::vector<int>{1, 2} : std::vector<int>{1, 2, 3, 4, 6, 8})
          for (const std::string& m : models)
            if (isModelPreset(m))
              meshRuns.push_back({cells, m, integrator});

  struct Task {
    const Problem* problem;
    std::string model;
    IntegratorSpec spec;
  };
  std::vector<Task> tasks;
  for (const auto& p : problems)
    for (const std::string& m : modelsOf(*p, models))
      for (const IntegratorSpec& spec : allIntegrators(*p, options.quick))
        if (bench::selected(options.integrators, spec.integrator))
          tasks.push_back({p.get(), m, spec});

  const std::string csvPath = options.out + "/work_precision.csv";
  FILE* csv = std::fopen(csvPath.c_str(), "w");
  if (!csv) {
    std::fprintf(stderr, "bench_work_precision: cannot write %s\n", csvPath.c_str());
    return 1;
  }
  std::fprintf(csv, "%s\n", kCsvHeader);
  const int total = static_cast<int>(tasks.size() + meshRuns.size());
  int done = 0;
  for (const Task& task : tasks) {
    const RunResult r = medianRun(options.repeats, [&] {
      return runOnce(*task.problem, task.model, task.spec, options.timeLimit);
    });
    writeRunRow(csv, task.problem->name, task.model, task.spec.integrator, task.spec.parameterName,
             task.spec.parameter, r);
    char what[256];
    std::snprintf(what, sizeof what, "%s %s %s %s=%.3g", task.problem->name.c_str(),
                  task.model.c_str(), task.spec.integrator.c_str(),
                  task.spec.parameterName.c_str(), task.spec.parameter);
    progress(++done, total, what, r);
  }
  for (const MeshRun& run : meshRuns) {
    const RunResult r = medianRun(options.repeats, [&] { return meshConvergenceRun(run); });
    writeRunRow(csv, "cantilever_static_mesh", run.model, run.integrator, "cells_across",
             run.cellsAcross, r);
    progress(++done, total,
             "cantilever_static_mesh " + run.model + " " + run.integrator +
                 " cells_across=" + std::to_string(run.cellsAcross), r);
  }
  std::fclose(csv);
  writeFacts(options.out + "/work_precision_facts.csv", problems);
  std::printf("wrote %s (%d rows) and work_precision_facts.csv\n", csvPath.c_str(), total);
  return 0;
}
