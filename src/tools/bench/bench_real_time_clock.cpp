// What the simulation node's real-time clock (scene/real_time_clock.h) costs in accuracy, and
// what it saves, on the scripted liver palpation: the palpation scene (config/scenes/
// liver_palpation.yaml, the contact per unit area as on the refined livers of
// scripts/bench_training) on a given liver mesh, a 6 mm sphere whose front is at the closed jaw
// tips (18 mm beyond the tool tip along the shaft) moved along the task script
// (config/tasks/liver_palpation.yaml, its keyframe tips, no hand in the loop), one
// thread as the node has on two cores. Three runs of the same task:
//   reference   frames of 10 ms, the tool at the task's position at the simulated time: what a
//               machine fast enough for 10 ms frames would show;
//   real_time   the node's rule: the tool at the task's position at the wall time (a trainee
//               moves in real time), frames from RealTimeClock (nominal 10 ms, up to
//               max_frame_time) and the tool through the contact's ToolProxy;
//   fixed_10ms  the rule before it: frames of 10 ms back to back when they overrun, the tool
//               at the wall time: simulated time falls behind the hand.
// Each frame records the device time (the task time of the tool's position), the contact force
// on the tool and the position of a probe node (the liver's node nearest the first palpation
// site's surface point). The real-time runs are compared with the reference at the same device time
// (linear interpolation between its 10 ms frames): what the trainee sees and feels at a moment
// against what the fast machine would give then.
//   bench_real_time_clock [--quick] [--mesh FILE] [--max-frame-time S] [--tool-max-speed M_PER_S]
//                         [--csv FILE] [--seconds S]
// --mesh: a liver mesh in liver.msh's coordinates (e.g. a TetGen refinement, docs/real_time.md;
// default liver.msh itself). --max-frame-time (default 0.1 s) and --tool-max-speed (default
// 0.1 m/s): the node's max_frame_time and the ToolProxy's speed limit. --csv: every frame of the
// three runs. --seconds: play only the script's first S (default all of it, and 1 s of its last
// pose; --quick: the first 5.5 s).
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "common/command_line.h"
#include "common/liver_bench_scene.h"
#include "tissue_trainer/core/contact/tissue_contact.h"
#include "tissue_trainer/core/contact/tool_proxy.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/operator/task_script.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/scene/real_time_clock.h"
#include "tissue_trainer/core/scene/scene.h"

namespace {

using namespace tt;
using Clock = std::chrono::steady_clock;

constexpr double kFrame = 0.01;        // s, the node's nominal frame (100 Hz)
constexpr double kToolRadius = 0.006;  // m, as bench_implicit_step's sphere
constexpr double kJawLength = 0.018;   // m, the closed jaws beyond the tip (grasper.urdf)
const Eigen::Vector3d kTrocar(-0.035, 0.075, 0.20);  // the task's trocar (liver_palpation.yaml)
constexpr double kTail = 1.0;          // s of the script's last pose after its end
constexpr double kQuickSeconds = 5.5;  // --quick: the first palpation

double now() { return std::chrono::duration<double>(Clock::now().time_since_epoch()).count(); }

enum class Mode { kReference, kRealTime, kFixed };
const char* modeName(Mode m) {
  return m == Mode::kReference ? "reference" : m == Mode::kRealTime ? "real_time" : "fixed_10ms";
}

struct Sample {
  double deviceTime, simTime, force, step, wall;
  Eigen::Vector3d probe;
};

struct Run {
  std::vector<Sample> samples;
  double wallSeconds = 0.0, simulated = 0.0, dropped = 0.0, maxLag = 0.0;
  int failed = 0;
};

// The palpation scene on `mesh`, its contact per unit area (as scripts/bench_training).
std::string writeScene(const std::string& mesh) {
  const std::string path = "/tmp/tt_bench_real_time_clock.yaml";
  bench::writeLiverSceneWithMesh(mesh, path, {{"  stiffness: 300          # N/m per contact point",
                                               "  stiffness_per_area: 1e7  # N/m^3"}});
  return path;
}

// The liver node nearest the first palpation site's rest surface point (where the shaft meets
// the liver, config/tasks/liver_palpation.yaml).
int probeNode(const System& system) {
  const Eigen::Vector3d site(-0.035, 0.075, 0.0652);
  int best = 0;
  for (int a = 1; a < system.numNodes(); ++a)
    if ((system.state.x.segment<3>(3 * a) - site).norm() < (system.state.x.segment<3>(3 * best) - site).norm())
      best = a;
  return best;
}

Run play(Mode mode, const std::string& scenePath, const TaskScript& task, double end, double maxFrame,
         double maxSpeed) {
  Scene scene = loadScene(scenePath);
  System& system = scene.system;
  // As the simulation node: the guard may spend 3 frames of wall time on one frame.
  if (mode != Mode::kReference)
    if (auto* guard = dynamic_cast<StabilityGuard*>(scene.integrator.get())) guard->setWallBudget(3 * kFrame);
  ToolShape sphere;
  sphere.type = ToolShape::Type::kSphere;
  sphere.radius = kToolRadius;
  sphere.link = "tip";
  TissueContact contact(system, *scene.contact, {sphere});
  const int probe = probeNode(system);
  RealTimeClock clock(kFrame, maxFrame);
  ToolProxy proxy(maxSpeed);
  Run run;
  const double wall0 = now();
  for (long frame = 0;; ++frame) {
    const double frameStart = now();
    const double deviceTime = mode == Mode::kReference ? system.state.t : frameStart - wall0;
    if (deviceTime > end) break;
    double h = kFrame;
    if (mode == Mode::kRealTime) {
      const ClockStep s = clock.next(frameStart);
      h = s.step;
      run.dropped += s.dropped;
    }
    Eigen::Vector3d tip = task.sample(deviceTime).tip;
    if (mode == Mode::kRealTime) {
      tip = proxy.follow(tip, h);
      run.maxLag = std::max(run.maxLag, proxy.lag());
    }
    const Eigen::Vector3d shaft = (tip - kTrocar).normalized();
    const Eigen::Isometry3d pose(Eigen::Translation3d{tip + (kJawLength - kToolRadius) * shaft});
    contact.setTool(pose, {pose}, 1.0, system.state.t);
    const double force = contact.update().f0.norm();
    const Eigen::Vector3d probePosition = system.state.x.segment<3>(3 * probe);
    const double t0 = system.state.t;
    const StepReport report = scene.integrator->advance(system, h);
    if (!report.ok) ++run.failed;
    clock.advanced(system.state.t - t0);
    run.samples.push_back({deviceTime, t0, force, system.state.t - t0, now() - frameStart, probePosition});
    if (mode == Mode::kRealTime) {
      const double wait = clock.nextStart() - now();
      if (wait > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    } else if (mode == Mode::kFixed) {
      const double wait = wall0 + (frame + 1) * kFrame - now();  // the old fixed-rate timer
      if (wait > 0.0) std::this_thread::sleep_for(std::chrono::duration<double>(wait));
    }
  }
  run.wallSeconds = now() - wall0;
  run.simulated = system.state.t;
  return run;
}

// The reference's sample at device time t, linear between its frames.
Sample at(const std::vector<Sample>& ref, double t) {
  auto hi = std::lower_bound(ref.begin(), ref.end(), t,
                             [](const Sample& s, double v) { return s.deviceTime < v; });
  if (hi == ref.begin()) return ref.front();
  if (hi == ref.end()) return ref.back();
  const Sample& a = *(hi - 1);
  const Sample& b = *hi;
  const double w = (t - a.deviceTime) / (b.deviceTime - a.deviceTime);
  Sample s = a;
  s.force = (1 - w) * a.force + w * b.force;
  s.probe = (1 - w) * a.probe + w * b.probe;
  return s;
}

void report(const char* name, const Run& run, const Run* reference) {
  std::vector<double> steps, walls;
  double peak = 0.0, forceMax = 0.0, forceSq = 0.0, probeMax = 0.0, probeSq = 0.0;
  for (const Sample& s : run.samples) {
    steps.push_back(s.step);
    walls.push_back(s.wall);
    peak = std::max(peak, s.force);
    if (!reference) continue;
    const Sample r = at(reference->samples, s.deviceTime);
    const double df = std::abs(s.force - r.force), dp = (s.probe - r.probe).norm();
    forceMax = std::max(forceMax, df);
    forceSq += df * df;
    probeMax = std::max(probeMax, dp);
    probeSq += dp * dp;
  }
  const double n = static_cast<double>(run.samples.size());
  std::printf("%-11s frames %6zu  wall %6.2f s  simulated %6.2f s  rtf %5.3f  step p50/max %5.1f/%5.1f ms  "
              "frame wall p50/max %6.1f/%6.1f ms  dropped %.2f s  failed %d  peak force %.3f N  proxy lag max %.1f mm",
              name, run.samples.size(), run.wallSeconds, run.simulated, run.simulated / run.wallSeconds,
              1e3 * bench::quantile(steps, 0.5), 1e3 * bench::quantile(steps, 1.0), 1e3 * bench::quantile(walls, 0.5),
              1e3 * bench::quantile(walls, 1.0), run.dropped, run.failed, peak, 1e3 * run.maxLag);
  if (reference)
    std::printf("\n            against the reference at the same device time: force error max %.3f N, rms %.3f N; "
                "probe node error max %.2f mm, rms %.2f mm",
                forceMax, std::sqrt(forceSq / n), 1e3 * probeMax, 1e3 * std::sqrt(probeSq / n));
  std::printf("\n");
}

}  // namespace

int main(int argc, char** argv) {
  tools::CommandLine options(argc, argv,
                             "bench_real_time_clock [--quick] [--mesh FILE] [--max-frame-time S] "
                             "[--tool-max-speed M_PER_S] [--csv FILE] [--seconds S]");
  const bool quick = options.flag("--quick");
  const std::string mesh =
      options.text("--mesh", bench::sourceDir() + "/config/meshes/liver.msh");
  const double maxFrame = options.positiveNumber("--max-frame-time", 0.1);
  const double maxSpeed = options.positiveNumber("--tool-max-speed", 0.1);
  const std::string csvPath = options.text("--csv", "");
  const double seconds = options.positiveNumber("--seconds", quick ? kQuickSeconds : 0.0);
  options.finish();
  try {
    setThreadCount(1);
    const std::string scenePath = writeScene(mesh);
    const TaskScript task = TaskScript::load(bench::sourceDir() + "/config/tasks/liver_palpation.yaml");
    const double end = seconds > 0.0 ? seconds : task.duration() + kTail;
    std::printf("bench_real_time_clock: %s (%d tets), task %s (the first %.1f s), 6 mm sphere, frames of %.0f ms, "
                "max_frame_time %.3f s, tool_max_speed %.3f m/s, 1 thread\n",
                mesh.c_str(), loadScene(scenePath).system.mesh.numTets(), task.name().c_str(), end,
                1e3 * kFrame, maxFrame, maxSpeed);
    const Run reference = play(Mode::kReference, scenePath, task, end, maxFrame, maxSpeed);
    report("reference", reference, nullptr);
    const Run realTime = play(Mode::kRealTime, scenePath, task, end, maxFrame, maxSpeed);
    report("real_time", realTime, &reference);
    const Run fixed = play(Mode::kFixed, scenePath, task, end, maxFrame, maxSpeed);
    report("fixed_10ms", fixed, &reference);
    if (!csvPath.empty()) {
      std::ofstream csv(csvPath);
      csv << "run,device_time,simulated_time,step,frame_wall,contact_force,probe_x,probe_y,probe_z\n";
      for (Mode m : {Mode::kReference, Mode::kRealTime, Mode::kFixed}) {
        const Run& r = m == Mode::kReference ? reference : m == Mode::kRealTime ? realTime : fixed;
        for (const Sample& s : r.samples)
          csv << modeName(m) << ',' << s.deviceTime << ',' << s.simTime << ',' << s.step << ',' << s.wall << ','
              << s.force << ',' << s.probe.x() << ',' << s.probe.y() << ',' << s.probe.z() << '\n';
      }
    }
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_real_time_clock: %s\n", e.what());
    return 1;
  }
  return 0;
}
