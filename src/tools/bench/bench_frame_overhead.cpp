// What the simulation node spends per frame beside the physics step, against the step, as the
// mesh grows: the liver palpation scene (config/scenes/liver_palpation.yaml) on the SOFA
// liver (596 tets) and on TetGen quality refinements of it (tetgen -rq1.4a<volume>: the same
// surface, more tets; as bench_implicit_step and scripts/bench_training make them).
//
// Each size: the liver is released and stepped by the scene's own integrator (with its
// stability guard) for warm-up frames, then for the timed frames; after every timed frame the
// node's per-frame passes run on the state, each timed alone:
//   status    what the node's status message needs (tt::FrameMeter: energies, volume,
//             displacement, strain);
//   guard     the stability guard's checks after a frame (finite state, the corrupt-element
//             volume check when a model does not tolerate inversion, the energy balance's
//             measurements: kinetic energy, damping power, the models' energies and loads);
//   surface   the display surface's positions (tt::DisplaySurface) and their copy into a
//             message buffer, every frame (~surface_every 1);
//   marker    the triangle list of the RViz marker, at 2 Hz: its time / 50 per 100 Hz frame;
//   snapshot  the crash-survival state file, every 0.5 s: its time / 50 per frame.
// The sum of the passes is the overhead; printed per frame, per tet and as a share of the step
// (the budget: under 5 % of the step at every size). The contact query is not here:
// bench_scene_parts times it.
//
// Verdict: the overhead must grow linearly with the mesh. With overhead ~ tets^s fitted over
// the sizes (least squares in log-log), s above kMaxExponent means some pass does more than a
// constant amount of work per tet (a pass that copied every node position for every tet,
// tets x nodes, gave s = 2): the tool prints NOT LINEAR and exits 1. An overhead above 5 % of
// the step median at some size is printed as OVER BUDGET (exit 4 without --quick, where the
// sizes are those of the issue). Times are medians over the timed frames (steady clock, one
// thread), so on a shared machine run it when the load is low and quote it.
//   bench_frame_overhead [--quick] [--sizes 600,5000,...] [--frames N] [--csv FILE]
// --quick: 596, 5,000 and 10,000 tets, 5 timed frames (the pipeline and the verdict in about
// a minute). Default sizes 596, 5000, 10000, 50000, 100000 (target tet counts; 596 is the
// SOFA liver itself). Exit 2 on bad input, 3 when tetgen is missing or a mesh cannot be made.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "common/liver_bench_scene.h"
#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/mesh/corrupt_elements.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/display_surface.h"
#include "tissue_trainer/core/scene/frame_meter.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/scene/state_snapshot.h"

namespace {

using namespace tt;
using Clock = std::chrono::steady_clock;

constexpr const char* kTool = "bench_frame_overhead";
const std::string kWork = "/tmp/tt_bench_frame_overhead";
constexpr double kMaxExponent = 1.3;   // fitted exponent of overhead ~ tets^s above which: not linear
constexpr double kBudget = 0.05;       // of the step
constexpr int kFramesPerMarker = 50;   // 100 Hz frames per marker (2 Hz)
constexpr int kFramesPerSnapshot = 50; // 100 Hz frames per snapshot (0.5 s)
constexpr double kDamageStrain = 0.3;  // the node's ~damage_strain

[[noreturn]] void badInput(const std::string& message) {
  std::fprintf(stderr, "%s: %s\n", kTool, message.c_str());
  std::exit(2);
}

struct Options {
  bool quick = false;
  std::vector<int> sizes = {596, 5000, 10000, 50000, 100000};
  int frames = 10;
  std::string csv;
};

Options parseOptions(int argc, char** argv) {
  tools::CommandLine options(argc, argv,
                             "bench_frame_overhead [--quick] [--sizes 600,5000,...] [--frames N] "
                             "[--csv FILE]");
  Options o;
  o.quick = options.flag("--quick");
  const std::vector<std::string> sizes = options.list("--sizes", {});
  o.frames = options.positiveInteger("--frames", o.quick ? 5 : o.frames);
  o.csv = options.text("--csv", "");
  options.finish();
  if (o.quick) o.sizes = {596, 5000, 10000};
  if (!sizes.empty()) o.sizes.clear();
  for (const std::string& item : sizes) {
    char* end = nullptr;
    const long n = std::strtol(item.c_str(), &end, 10);
    if (*end != '\0' || n < 1 || n > 10000000)
      options.fail("--sizes expects positive whole numbers, got '" + item + "'");
    o.sizes.push_back(static_cast<int>(n));
  }
  if (o.sizes.size() < 2) options.fail("--sizes expects at least two sizes (the verdict compares them)");
  std::sort(o.sizes.begin(), o.sizes.end());
  return o;
}

double msSince(Clock::time_point t0) {
  return 1e3 * std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) { return bench::quantile(std::move(v), 0.5); }

// The stability guard's checks after a frame (StabilityGuard::check and its measurements),
// through the same public calls.
struct GuardChecks {
  CorruptElementCheck corrupt;
  bool checkVolumes = false;
  Eigen::VectorXd loads;

  explicit GuardChecks(const System& system) : corrupt(system.mesh) {
    checkVolumes = std::any_of(system.models.begin(), system.models.end(),
                               [](const auto& m) { return !m->toleratesInversion(); });
  }

  // A sum, so that nothing is optimised away.
  double run(const System& system) {
    const State& s = system.state;
    double sum = s.x.allFinite() && s.v.allFinite() ? 1.0 : 0.0;
    if (checkVolumes) {
      const Eigen::Map<const Eigen::Matrix3Xd> x(s.x.data(), 3, system.numNodes());
      sum += static_cast<double>(corrupt.find(x, 0.01).size());
    }
    loads = system.externalForce;
    for (const auto& model : system.models)
      if (!model->hasEnergy()) model->addForce(s.x, s.v, loads);
    for (Eigen::Index dof = 0; dof < s.v.size(); ++dof) {
      if (system.isConstrained[dof]) continue;
      sum += 0.5 * system.mass[dof] * s.v[dof] * s.v[dof] + system.damping[dof] * s.v[dof] * s.v[dof];
    }
    for (const auto& model : system.models)
      if (model->hasEnergy()) sum += model->energy(s.x);
    return sum + loads.sum();
  }
};

struct Row {
  int tets = 0, nodes = 0, surfaceVertices = 0, frames = 0, failedSteps = 0;
  double stepMs = 0.0, stepP90Ms = 0.0;
  double statusMs = 0.0, guardMs = 0.0, surfaceMs = 0.0, markerMs = 0.0, snapshotMs = 0.0;
  double overheadMs() const {
    return statusMs + guardMs + surfaceMs + markerMs / kFramesPerMarker + snapshotMs / kFramesPerSnapshot;
  }
  double share() const { return overheadMs() / stepMs; }
  double nsPerTet() const { return 1e6 * overheadMs() / tets; }
};

// The palpation scene on a mesh of about `target` tets (596: the SOFA liver itself).
std::string scenePath(int target) {
  if (target == 596) return bench::sourceDir() + "/config/scenes/liver_palpation.yaml";
  int tets = 0;
  const std::string mesh = bench::refinedLiver(kWork, target, tets);
  if (mesh.empty()) {
    std::fprintf(stderr, "%s: cannot refine the liver to %d tets (is tetgen installed? see %s)\n",
                 kTool, target, kWork.c_str());
    std::exit(3);
  }
  const std::string path = mesh + ".yaml";
  bench::writeLiverSceneWithMesh(mesh, path);
  return path;
}

Row measure(const std::string& path, int frames) {
  Scene scene = loadScene(path);
  System& system = scene.system;
  const DisplaySurface display(scene);
  const FrameMeter meter(system);
  GuardChecks guard(system);
  Row row;
  row.tets = system.mesh.numTets();
  row.nodes = system.numNodes();
  row.surfaceVertices = display.numVertices();
  row.frames = frames;
  const int warmUp = 3;
  for (int f = 0; f < warmUp; ++f) scene.integrator->advance(system, scene.frameTime);

  std::vector<double> step, status, checks, surface, marker, snapshot;
  Eigen::Matrix3Xd positions;
  std::vector<double> message;
  std::vector<double> points;
  const std::string snapshotPath = kWork + "/simulation.snapshot";
  const std::uint64_t fingerprint = sceneFingerprint(scene.name, system.mesh);
  double sink = 0.0;
  for (int f = 0; f < frames; ++f) {
    auto t0 = Clock::now();
    const StepReport report = scene.integrator->advance(system, scene.frameTime);
    step.push_back(msSince(t0));
    row.failedSteps += !report.ok;

    t0 = Clock::now();
    const FrameStatus s = meter.measure(system, f, report, kDamageStrain);
    status.push_back(msSince(t0));
    sink += s.frame.elasticEnergy + s.strain.maxStrain;

    t0 = Clock::now();
    sink += guard.run(system);
    checks.push_back(msSince(t0));

    t0 = Clock::now();
    display.positions(system.state.x, positions);
    message.assign(positions.data(), positions.data() + positions.size());
    surface.push_back(msSince(t0));

    t0 = Clock::now();
    points.clear();
    points.reserve(9 * display.triangles().size());
    for (const Triangle& t : display.triangles())
      for (int k : t) points.insert(points.end(), {positions(0, k), positions(1, k), positions(2, k)});
    marker.push_back(msSince(t0));

    t0 = Clock::now();
    writeStateSnapshot(snapshotPath, system.state, fingerprint);
    snapshot.push_back(msSince(t0));
  }
  if (!std::isfinite(sink)) std::printf("(the state is not finite)\n");
  row.stepMs = median(step);
  row.stepP90Ms = bench::quantile(step, 0.9);
  row.statusMs = median(status);
  row.guardMs = median(checks);
  row.surfaceMs = median(surface);
  row.markerMs = median(marker);
  row.snapshotMs = median(snapshot);
  return row;
}

// Least-squares slope of log(overhead) against log(tets).
double fittedExponent(const std::vector<Row>& rows) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(rows.size());
  for (const Row& r : rows) {
    const double x = std::log(r.tets), y = std::log(r.overheadMs());
    sx += x; sy += y; sxx += x * x; sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

void writeCsv(const std::string& path, const std::vector<Row>& rows) {
  std::ofstream out(path);
  out << "tets,nodes,surface_vertices,frames,failed_steps,step_ms,step_p90_ms,status_ms,guard_ms,"
         "surface_ms,marker_ms,snapshot_ms,overhead_ms,overhead_share,overhead_ns_per_tet\n";
  for (const Row& r : rows) {
    char line[512];
    std::snprintf(line, sizeof line, "%d,%d,%d,%d,%d,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g,%.6g\n",
                  r.tets, r.nodes, r.surfaceVertices, r.frames, r.failedSteps, r.stepMs, r.stepP90Ms,
                  r.statusMs, r.guardMs, r.surfaceMs, r.markerMs, r.snapshotMs, r.overheadMs(),
                  r.share(), r.nsPerTet());
    out << line;
  }
  if (!out) badInput("cannot write " + path);
}

}  // namespace

int main(int argc, char** argv) {
  const Options options = parseOptions(argc, argv);
  setThreadCount(1);
  if (std::system(("mkdir -p " + kWork).c_str()) != 0) badInput("cannot create " + kWork);
  std::printf("%s: the simulation node's per-frame passes beside the step, liver palpation scene, "
              "%d timed frames per size, one thread\n", kTool, options.frames);
  std::printf("%8s %7s %9s %9s | %9s %9s %9s %9s %9s | %9s %7s %8s\n", "tets", "nodes",
              "step_ms", "step_p90", "status", "guard", "surface", "marker/50", "snap/50",
              "overhead", "share", "ns/tet");
  std::vector<Row> rows;
  for (int target : options.sizes) {
    Row r;
    try {
      r = measure(scenePath(target), options.frames);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s: %s\n", kTool, e.what());
      return 3;
    }
    std::printf("%8d %7d %9.3f %9.3f | %9.4f %9.4f %9.4f %9.4f %9.4f | %9.4f %6.2f%% %8.1f%s\n",
                r.tets, r.nodes, r.stepMs, r.stepP90Ms, r.statusMs, r.guardMs, r.surfaceMs,
                r.markerMs / kFramesPerMarker, r.snapshotMs / kFramesPerSnapshot, r.overheadMs(),
                100.0 * r.share(), r.nsPerTet(), r.failedSteps ? "  (failed steps)" : "");
    std::fflush(stdout);
    rows.push_back(r);
  }
  if (!options.csv.empty()) writeCsv(options.csv, rows);

  const double exponent = fittedExponent(rows);
  const bool linear = exponent <= kMaxExponent;
  std::printf("overhead ~ tets^%.2f over %d to %d tets (linear: at most %.2f)\n", exponent,
              rows.front().tets, rows.back().tets, kMaxExponent);
  bool overBudget = false;
  for (const Row& r : rows)
    if (r.share() > kBudget) {
      overBudget = true;
      std::printf("OVER BUDGET: at %d tets the per-frame passes take %.1f %% of the step (budget %.0f %%)\n",
                  r.tets, 100.0 * r.share(), 100.0 * kBudget);
    }
  if (!linear) {
    std::printf("\n*** NOT LINEAR: the per-frame overhead grows as tets^%.2f (per tet %.0f ns at %d "
                "tets, %.0f ns at %d): some pass does work per tet that grows with the mesh ***\n",
                exponent, rows.front().nsPerTet(), rows.front().tets, rows.back().nsPerTet(),
                rows.back().tets);
    return 1;
  }
  std::printf("verdict: linear%s\n", overBudget ? ", over budget" : (", within budget"));
  return overBudget && !options.quick ? 4 : 0;
}
