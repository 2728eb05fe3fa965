// The iteration-count step control of backward Euler ("Adamss: Advanced Anisotropic
// Mass-Spring System", Sec. 2.5.5, Fig. 2.21) on an active-tension twitch, and what the
// iteration count does on the way to an instability.
//
//   bench_iteration_control [--scene FILE] [--out DIR] [--quick] [--twitch-only]
//                           [--lower N] [--upper N]
//
// The scene (default config/scenes/muscle_twitch.yaml; its variants are loaded from a copy in
// DIR, so files it names must be given by absolute paths) runs with its integrator replaced by
// backward Euler with `adaptive: true`, GMRES and one linearised step (the chapter's), once
// with the analytic Jacobians, once with finite-difference ones (coloured) and once with the
// analytic ones and GMRES started from zero (no warm start, as PETSc's default). Every step
// attempt is recorded as the controller judged it: its start, the sum over the free nodes of
// the magnitudes of the active-tension forces there (normalised to its largest value over the
// run, the chapter's "normalized active forces sum"), the GMRES iterations, the step length
// and whether it was redone.
//   -> DIR/iteration_control.csv   jacobian,t,active_force,iterations,step,rejected
// Printed: the Pearson correlation of the iteration count with the active force over the
// kept steps, and the step lengths the controller chose.
//
// Then the twitch is driven towards instability, one knob at a time, up a ladder: the peak
// tension; the same at a fixed step of 0.25 ms (the count recorded, not obeyed); the Young's
// modulus (with the peak at a tenth of it); the iteration limits at a peak of 1000 kPa (lower =
// upper / 3: a higher upper limit lets the steps grow). Each rung runs the first 0.4 s (the
// twitch's rise, peak and decay), at most 60 s of CPU time. A run ends at the first frame that
// fails (the integrator reports a failure or a non-finite state, or an element inverts or
// goes flat, the stability guard's volume test, for models that cannot take inversion). For
// each rung it prints whether and when the run failed, the median and largest iteration
// count, the largest of the last ten attempts, the last and the shortest step, the
// correlation of the count and of log(step) with the active force, and, for a run that failed,
// whether the stability guard (the same run under StabilityGuard) gets through.
//   -> DIR/iteration_instability.csv   ladder,value,t,active_force,iterations,step,rejected
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/corrupt_elements.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace {

// The step control of the runs (--lower, --upper): the chapter gives no limits. At these the
// twitch runs at 1 ms (GMRES(30) with Jacobi to 1e-8 needs about 20 iterations there).
int lowerLimit = 10, upperLimit = 30;
constexpr double kInitialStep = 1e-3, kMinStep = 1e-6, kMaxStep = 0.01;  // s

struct StepRow {
  double t, activeForce, step;
  int iterations;
  bool rejected;
};

// The frame loop judges a step before it becomes the state: system.state is then the step's
// start, and the models have had beginStep for it, so the active force read here is the one
// the step used.
class RecordingControl final : public HalvingDoublingControl {
 public:
  RecordingControl(const HalvingDoublingParams& p, const System& system, std::vector<StepRow>& rows)
      : HalvingDoublingControl(p), system_(system), rows_(rows) {
    for (const auto& m : system.models)
      if (std::string(m->name()) == "adamss_active_tension") active_.push_back(m.get());
  }

 protected:
  double afterKeep(double h, const StepMeasure& m, bool last) override {
    record(h, m, false);
    return HalvingDoublingControl::afterKeep(h, m, last);
  }
  double afterReject(double h, const StepMeasure& m) override {
    record(h, m, true);
    return HalvingDoublingControl::afterReject(h, m);
  }

 private:
  void record(double h, const StepMeasure& m, bool rejected) {
    const State& s = system_.state;
    force_.setZero(s.x.size());
    for (const ForceModel* model : active_) model->addForce(s.x, s.v, force_);
    system_.zeroConstrained(force_);
    const double sum = force_.reshaped(3, system_.mesh.numNodes()).colwise().norm().sum();
    rows_.push_back({s.t, sum, h, m.iterations, rejected});
  }

  const System& system_;
  std::vector<StepRow>& rows_;
  std::vector<const ForceModel*> active_;
  Eigen::VectorXd force_;
};

struct Variant {
  double peak = 0.0, young = 0.0;  // 0: the scene's value
  bool differences = false;        // finite-difference Jacobians
  bool warmStart = true;           // GMRES from the previous dv
  double duration = 0.0;           // 0: the scene's
  double fixedStep = 0.0;  // > 0: every step this long, the count recorded but not obeyed
  int upper = 0;           // > 0: this upper limit and lower = upper / 3 (else --lower, --upper)
};

std::string readFile(const std::string& path) {
  std::ifstream in(path);
  if (!in) {
    std::fprintf(stderr, "bench_iteration_control: cannot read %s\n", path.c_str());
    std::exit(1);
  }
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// Replaces the value of the first `key: number` in the scene text.
void setNumber(std::string& text, const std::string& key, double value) {
  const std::regex pattern(key + R"(:\s*[-+0-9.eE]+)");
  if (!std::regex_search(text, pattern)) {
    std::fprintf(stderr, "bench_iteration_control: the scene has no numeric %s\n", key.c_str());
    std::exit(1);
  }
  std::ostringstream number;
  number << key << ": " << value;
  text = std::regex_replace(text, pattern, number.str(), std::regex_constants::format_first_only);
}

// The scene with the variant's values, loaded through a copy in `dir`.
Scene loadVariant(const std::string& scenePath, const Variant& v, const std::string& dir) {
  std::string text = readFile(scenePath);
  if (v.peak > 0.0) setNumber(text, "peak", v.peak);
  if (v.young > 0.0) setNumber(text, "young_modulus", v.young);
  const std::string copy = dir + "/iteration_control_scene.yaml";
  std::ofstream(copy) << text;
  Scene scene = loadScene(copy);
  std::filesystem::remove(copy);
  if (v.duration > 0.0) scene.duration = v.duration;
  return scene;
}

BackwardEulerParams controlParams(const Variant& v) {
  BackwardEulerParams p = bench::jacobiBackwardEuler();
  p.adaptive = true;
  p.linearSolver = BackwardEulerParams::LinearSolver::kGmres;
  p.newtonIterations = 1;
  p.lowerIterations = lowerLimit;
  p.upperIterations = upperLimit;
  p.initialStep = kInitialStep;
  p.minStep = kMinStep;
  p.maxStep = kMaxStep;
  if (v.upper > 0) {
    p.upperIterations = v.upper;
    p.lowerIterations = v.upper / 3;
  }
  if (v.fixedStep > 0.0) {
    p.lowerIterations = 0;
    p.upperIterations = 1 << 30;
    p.initialStep = p.minStep = p.maxStep = v.fixedStep;
  }
  p.warmStart = v.warmStart;
  if (v.differences) p.jacobian = BackwardEulerParams::Jacobian::kFiniteDifference;
  return p;
}

struct RunResult {
  std::vector<StepRow> rows;
  bool failed = false;
  double failedAt = 0.0;
  std::string failure;
  int unconvergedLinear = 0;
  double cpuSeconds = 0.0;
  bool stopped = false;  // at the CPU time limit
};

constexpr double kCpuLimit = 60.0;  // s per run

// The first corrupt element (inverted or flat, the guard's volume test), or "".
std::string corruption(const System& s, const CorruptElementCheck& check) {
  const auto bad = check.find(s.state.x.reshaped(3, s.mesh.numNodes()),
                              StabilityGuardParams{}.minVolumeRatio);
  return bad.empty() ? "" : describeCorrupt(bad.front());
}

RunResult runRecorded(const std::string& scenePath, const Variant& v, const std::string& dir) {
  Scene scene = loadVariant(scenePath, v, dir);
  System& s = scene.system;
  RunResult out;
  const BackwardEulerParams params = controlParams(v);
  BackwardEulerIntegrator integrator(
      params, std::make_unique<RecordingControl>(iterationStepControl(params), s, out.rows));
  const CorruptElementCheck check(s.mesh);
  const bool volumes = !std::all_of(s.models.begin(), s.models.end(),
                                    [](const auto& m) { return m->toleratesInversion(); });
  const int frames = static_cast<int>(std::lround(scene.duration / scene.frameTime));
  const double cpu0 = bench::cpuSeconds();
  for (int f = 0; f < frames; ++f) {
    const StepReport r = integrator.advance(s, scene.frameTime);
    std::string problem = r.ok ? "" : r.failure;
    if (problem.empty() && !(s.state.x.allFinite() && s.state.v.allFinite()))
      problem = "non-finite state";
    if (problem.empty() && volumes) problem = corruption(s, check);
    if (!problem.empty()) {
      out.failed = true;
      out.failedAt = s.state.t;
      out.failure = problem;
      break;
    }
    if (bench::cpuSeconds() - cpu0 > kCpuLimit) {
      out.stopped = true;
      out.failedAt = s.state.t;
      break;
    }
  }
  out.cpuSeconds = bench::cpuSeconds() - cpu0;
  out.unconvergedLinear = integrator.diagnostics().unconvergedLinear;
  double peak = 0.0;
  for (const StepRow& row : out.rows) peak = std::max(peak, row.activeForce);
  if (peak > 0.0)
    for (StepRow& row : out.rows) row.activeForce /= peak;
  return out;
}

// The same run under the stability guard: whether it reaches the end.
std::string guardedOutcome(const std::string& scenePath, const Variant& v, const std::string& dir) {
  Scene scene = loadVariant(scenePath, v, dir);
  StabilityGuard guard(std::make_unique<BackwardEulerIntegrator>(controlParams(v)));
  const int frames = static_cast<int>(std::lround(scene.duration / scene.frameTime));
  for (int f = 0; f < frames; ++f) {
    const StepReport r = guard.advance(scene.system, scene.frameTime);
    if (!r.ok) {
      char text[600];
      std::snprintf(text, sizeof text, "guard failed at t = %.4g s (%ld halvings): %s",
                    scene.system.state.t, guard.stats().halvings, r.failure.c_str());
      return text;
    }
  }
  char text[200];
  std::snprintf(text, sizeof text, "guard reached the end (%ld recoveries, %ld halvings)",
                guard.stats().recoveries, guard.stats().halvings);
  return text;
}

double pearson(const std::vector<double>& a, const std::vector<double>& b) {
  const Eigen::Map<const Eigen::ArrayXd> x(a.data(), a.size()), y(b.data(), b.size());
  const Eigen::ArrayXd dx = x - x.mean(), dy = y - y.mean();
  return (dx * dy).sum() / std::sqrt((dx * dx).sum() * (dy * dy).sum());
}

void writeRows(std::ofstream& csv, const std::string& label, const std::vector<StepRow>& rows) {
  for (const StepRow& r : rows)
    csv << label << ',' << r.t << ',' << r.activeForce << ',' << r.iterations << ',' << r.step
        << ',' << (r.rejected ? 1 : 0) << '\n';
}

std::ofstream openCsv(const std::string& path, const char* header) {
  std::ofstream csv(path);
  if (!csv) {
    std::fprintf(stderr, "bench_iteration_control: cannot write %s\n", path.c_str());
    std::exit(1);
  }
  csv.precision(9);
  csv << header << '\n';
  return csv;
}

std::string outcome(const RunResult& r) {
  char text[600];
  if (r.failed)
    std::snprintf(text, sizeof text, "FAILED at t = %.6f s: %s", r.failedAt, r.failure.c_str());
  else if (r.stopped)
    std::snprintf(text, sizeof text, "stopped at the CPU limit at t = %.6f s", r.failedAt);
  else
    std::snprintf(text, sizeof text, "ran to the end");
  return text;
}

// Fig. 2.21: the twitch with both Jacobians.
void twitch(const std::string& scenePath, const std::string& dir, bool quick) {
  std::ofstream csv = openCsv(dir + "/iteration_control.csv",
                              "jacobian,t,active_force,iterations,step,rejected");
  for (const char* label : {"analytic", "finite_difference", "analytic_cold_start"}) {
    Variant v;
    v.differences = std::string(label) == "finite_difference";
    v.warmStart = std::string(label) != "analytic_cold_start";
    if (quick) v.duration = 0.5;
    const RunResult r = runRecorded(scenePath, v, dir);
    writeRows(csv, label, r.rows);
    std::vector<double> force, iterations, steps;
    int rejected = 0;
    for (const StepRow& row : r.rows) {
      rejected += row.rejected;
      if (row.rejected) continue;
      force.push_back(row.activeForce);
      iterations.push_back(row.iterations);
      steps.push_back(row.step);
    }
    if (steps.empty()) {
      std::printf("[twitch] %-17s %s before the first step was kept\n", label,
                  outcome(r).c_str());
      continue;
    }
    const auto [hMin, hMax] = std::minmax_element(steps.begin(), steps.end());
    const auto [nMin, nMax] = std::minmax_element(iterations.begin(), iterations.end());
    std::printf("[twitch] %-17s %s, %zu steps kept, %d redone, CPU %.2f s; iterations %g..%g "
                "(median %g), step %.3g..%.3g s (median %.3g); correlation of iterations with "
                "active force %.3f, of step with active force %.3f; unconverged GMRES solves %d\n",
                label, outcome(r).c_str(),
                force.size(), rejected, r.cpuSeconds, *nMin, *nMax, bench::median(iterations),
                *hMin, *hMax, bench::median(steps), pearson(iterations, force),
                pearson(steps, force), r.unconvergedLinear);
  }
}

struct Rung {
  std::string ladder;
  double value;
  Variant variant;
};

std::vector<Rung> ladders(bool quick) {
  std::vector<Rung> rungs;
  const double duration = quick ? 0.15 : 0.4;  // the rise, the peak and the decay
  for (double peak : quick ? std::vector<double>{3, 30, 300}
                           : std::vector<double>{3, 10, 30, 100, 300, 1000, 3000}) {
    Variant v;
    v.peak = peak;
    v.duration = duration;
    rungs.push_back({"peak_tension_kPa", peak, v});
  }
  for (double peak :
       quick ? std::vector<double>{300, 3000} : std::vector<double>{300, 1000, 3000}) {
    Variant v;  // the same twitches at a fixed step: the count as it comes
    v.peak = peak;
    v.duration = duration;
    v.fixedStep = 2.5e-4;
    rungs.push_back({"peak_tension_kPa_fixed_step", peak, v});
  }
  for (double young : quick ? std::vector<double>{300, 30000}
                            : std::vector<double>{300, 3000, 30000, 300000}) {
    Variant v;
    v.young = young;
    v.peak = young / 10.0;  // the same 10 % contraction, at a stiffer matrix
    v.duration = duration;
    rungs.push_back({"young_modulus_kPa", young, v});
  }
  for (int upper : quick ? std::vector<int>{30, 120} : std::vector<int>{30, 60, 120, 240}) {
    Variant v;  // longer steps: the limits raised together (lower = upper / 3)
    v.peak = 1000;
    v.upper = upper;
    v.duration = duration;
    rungs.push_back({"upper_iterations_at_1000kPa", static_cast<double>(upper), v});
  }
  return rungs;
}


void towardsInstability(const std::string& scenePath, const std::string& dir, bool quick) {
  std::ofstream csv = openCsv(dir + "/iteration_instability.csv",
                              "ladder,value,t,active_force,iterations,step,rejected");
  for (const Rung& rung : ladders(quick)) {
    const RunResult r = runRecorded(scenePath, rung.variant, dir);
    std::ostringstream label;
    label << rung.ladder << ',' << rung.value;
    writeRows(csv, label.str(), r.rows);
    std::vector<double> all, force, iterations, logStep;
    for (const StepRow& row : r.rows) {
      all.push_back(row.iterations);
      if (row.rejected) continue;
      force.push_back(row.activeForce);
      iterations.push_back(row.iterations);
      logStep.push_back(std::log(row.step));
    }
    const size_t tail = std::min<size_t>(10, all.size());
    const double lastMax = tail ? *std::max_element(all.end() - tail, all.end()) : 0.0;
    const double runMax = all.empty() ? 0.0 : *std::max_element(all.begin(), all.end());
    const double lastStep = r.rows.empty() ? 0.0 : r.rows.back().step;
    std::printf("[ladder] %-20s %8g: %s; %zu attempts, iterations median %g max %g, last 10 "
                "attempts max %g, last step %.3g s, shortest %.3g s, unconverged GMRES %d; "
                "correlation with the active force: iterations %.3f, log step %.3f; %s\n",
                rung.ladder.c_str(), rung.value,
                outcome(r).c_str(),
                all.size(), bench::median(all), runMax, lastMax, lastStep,
                logStep.empty() ? NAN : std::exp(*std::min_element(logStep.begin(), logStep.end())),
                r.unconvergedLinear,
                pearson(iterations, force), pearson(logStep, force),
                r.failed ? guardedOutcome(scenePath, rung.variant, dir).c_str() : "");
    std::fflush(stdout);
  }
}

}  // namespace
}  // namespace tt

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  tt::tools::CommandLine options(argc, argv,
                                 "bench_iteration_control [--scene FILE] [--out DIR] [--quick] "
                                 "[--twitch-only] [--lower N] [--upper N]");
  const std::string scene = options.text("--scene", "config/scenes/muscle_twitch.yaml");
  const std::string out = options.text("--out", "docs/report");
  const bool quick = options.flag("--quick");
  const bool twitchOnly = options.flag("--twitch-only");
  tt::lowerLimit = options.positiveInteger("--lower", tt::lowerLimit);
  tt::upperLimit = options.positiveInteger("--upper", tt::upperLimit);
  options.finish();
  if (tt::lowerLimit >= tt::upperLimit) {
    std::fprintf(stderr, "bench_iteration_control: --lower (%d) must be below --upper (%d)\n",
                 tt::lowerLimit, tt::upperLimit);
    return 2;
  }
  std::error_code made;
  std::filesystem::create_directories(out, made);
  if (made) {
    std::fprintf(stderr, "bench_iteration_control: cannot create %s: %s\n", out.c_str(),
                 made.message().c_str());
    return 2;
  }
  tt::setThreadCount(1);
  try {
    tt::twitch(scene, out, quick);
    if (!twitchOnly) tt::towardsInstability(scene, out, quick);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_iteration_control: %s\n", e.what());
    return 1;
  }
  std::printf("wrote %s/iteration_control.csv and iteration_instability.csv\n", out.c_str());
  return 0;
}
