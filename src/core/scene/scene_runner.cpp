#include "tissue_trainer/core/scene/scene_runner.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <stdexcept>

#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/mesh/quality.h"

namespace tt {
namespace {

namespace fs = std::filesystem;

std::string frameFileName(const std::string& name, int frame) {
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "_%06d.vtu", frame);
  return name + buffer;
}

// The columns after `halvings` came later; readers of the earlier ones are unaffected.
// One column per model observable: NAME_K, K counting the models that report NAME.
void writeCsvHeader(std::ofstream& csv, const System& system) {
  csv << "frame,time,kinetic_energy,elastic_energy,load_energy,volume_ratio,max_displacement,substeps,"
         "rejected,newton_iterations,linear_iterations,error_estimate,step_wall_s,ok,halvings,"
         "barycentre_x,barycentre_y,barycentre_z,volume";
  std::map<std::string, int> reported;
  for (const auto& model : system.models)
    for (int k = 0; k < model->observableCount(); ++k) {
      const std::string name = model->observableName(k);
      csv << "," << name << "_" << reported[name]++;
    }
  csv << "\n";
}

void writeCsvLine(std::ofstream& csv, const FrameLog& f) {
  char line[512];
  std::snprintf(line, sizeof line,
                "%d,%.9g,%.9g,%.9g,%.9g,%.12g,%.9g,%d,%d,%d,%d,%.6g,%.6g,%d,%d,%.12g,%.12g,%.12g,%.12g",
                f.frame, f.time, f.kineticEnergy, f.elasticEnergy, f.loadEnergy, f.volumeRatio,
                f.maxDisplacement, f.step.substeps, f.step.rejected, f.step.newtonIterations,
                f.step.linearIterations, f.step.errorEstimate, f.step.wallSeconds, f.step.ok,
                f.guard.halvings, f.barycentre.x(), f.barycentre.y(), f.barycentre.z(), f.volume);
  csv << line;
  for (double v : f.observables) {
    std::snprintf(line, sizeof line, ",%.12g", v);
    csv << line;
  }
  csv << "\n";
}

// a = f / m at the state (f the total force: models, damping, external force); zero on the
// constrained DOFs, whose motion is prescribed, and on massless DOFs (nodes of no element).
Eigen::VectorXd accelerationOf(const System& system, const Eigen::VectorXd& force) {
  Eigen::VectorXd a = Eigen::VectorXd::Zero(force.size());
  for (Eigen::Index k = 0; k < a.size(); ++k)
    if (system.mass[k] > 0.0) a[k] = force[k] / system.mass[k];
  for (int dof : system.constrainedDofs) a[dof] = 0.0;
  return a;
}

// The frame's time is a sum of frame times: a frame ending at stop_not_before up to round-off
// counts.
bool kineticEnergyStops(const Scene& scene, const FrameLog& log) {
  const auto& stop = scene.kineticEnergyStop;
  return stop && log.time >= stop->notBefore - 1e-9 * scene.frameTime &&
         log.kineticEnergy < stop->below;
}

}  // namespace

const char* stopReasonName(StopReason reason) {
  switch (reason) {
    case StopReason::kDuration: return "duration";
    case StopReason::kKineticEnergy: return "kinetic_energy";
    case StopReason::kInterrupt: return "interrupt";
    case StopReason::kFailure: return "failure";
  }
  return "?";
}

FrameLog measureFrame(const System& system, int frame, const StepReport& step) {
  FrameLog log;
  log.frame = frame;
  log.time = system.state.t;
  log.kineticEnergy = system.kineticEnergy(system.state.v);
  for (const auto& model : system.models)
    (model->isBodyLoad() ? log.loadEnergy : log.elasticEnergy) += model->energy(system.state.x);
  const Eigen::Map<const Eigen::Matrix3Xd> x(system.state.x.data(), 3, system.numNodes());
  double restVolume = 0.0;
  for (const Tet& t : system.mesh.tets) {
    restVolume += tetVolume(system.mesh.rest, t);
    log.volume += tetVolume(x, t);
  }
  for (const Hex& h : system.mesh.hexes) {
    restVolume += hexVolume(system.mesh.rest, h);
    log.volume += hexVolume(x, h);
  }
  log.volumeRatio = log.volume / restVolume;
  log.maxDisplacement = (x - system.mesh.rest).colwise().norm().maxCoeff();
  const Eigen::Map<const Eigen::Matrix3Xd> m(system.mass.data(), 3, system.numNodes());
  log.barycentre = m.cwiseProduct(x).rowwise().sum().cwiseQuotient(m.rowwise().sum());
  for (const auto& model : system.models)
    for (int k = 0; k < model->observableCount(); ++k)
      log.observables.push_back(model->observable(k, system.state.x));
  log.step = step;
  return log;
}

RunSummary runScene(Scene& scene, const RunOptions& options) {
  RunSummary summary;
  const double duration = options.duration >= 0.0 ? options.duration : scene.duration;
  const int frames = static_cast<int>(std::ceil(duration / scene.frameTime - 1e-9));
  const bool writeFiles = !options.outDir.empty();
  std::ofstream csv, pvd;
  if (writeFiles) {
    fs::create_directories(options.outDir);
    if (scene.output.csv) {
      const std::string path = (fs::path(options.outDir) / (scene.name + ".csv")).string();
      csv.open(path);
      if (!csv) throw InputError(path, 0, "cannot write the CSV log");
      writeCsvHeader(csv, scene.system);
      summary.files.push_back(path);
    }
  }
  std::vector<std::pair<double, std::string>> vtuFiles;
  // `last`: the frame the run ends on early, written whatever vtu_every says.
  auto writeFrame = [&](int frame, bool last = false) {
    if (!writeFiles || scene.output.vtuEvery <= 0) return;
    if (frame % scene.output.vtuEvery != 0 && !last) return;
    const std::string name = frameFileName(scene.name, frame);
    Eigen::VectorXd force;
    scene.system.computeForce(scene.system.state.x, scene.system.state.v, force);
    const Eigen::VectorXd acceleration = accelerationOf(scene.system, force);
    VtuFields fields;
    fields.positions = &scene.system.state.x;
    fields.pointPositions = true;
    fields.velocity = &scene.system.state.v;
    fields.acceleration = &acceleration;
    fields.force = &force;
    writeVtu((fs::path(options.outDir) / name).string(), scene.system.mesh, fields);
    vtuFiles.emplace_back(scene.system.state.t, name);
  };

  std::vector<double> stepWall;
  const StabilityGuard* guard = guardOf(*scene.integrator);
  const auto start = std::chrono::steady_clock::now();
  writeFrame(0);
  for (int frame = 1; frame <= frames; ++frame) {
    const StepReport step = scene.integrator->advance(scene.system, scene.frameTime);
    FrameLog log = measureFrame(scene.system, frame, step);
    if (guard) {
      log.guard = guard->lastFrame();
      summary.guard.add(log.guard);
    }
    stepWall.push_back(step.wallSeconds);
    if (csv.is_open()) writeCsvLine(csv, log);
    summary.frames = frame;
    summary.last = log;
    if (options.onFrame) options.onFrame(log);
    if (!step.ok) {
      summary.ok = false;
      summary.failure = "frame " + std::to_string(frame) + ": " + step.failure;
      summary.stop = StopReason::kFailure;
    } else if (kineticEnergyStops(scene, log)) {
      summary.stop = StopReason::kKineticEnergy;
    } else if (options.stopRequested && options.stopRequested()) {
      summary.stop = StopReason::kInterrupt;
    }
    writeFrame(frame, summary.stop == StopReason::kKineticEnergy ||
                          summary.stop == StopReason::kInterrupt);
    if (summary.stop != StopReason::kDuration) break;
  }
  summary.wallSeconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  summary.simulatedTime = scene.system.state.t;
  if (!stepWall.empty()) {
    std::vector<double> sorted = stepWall;
    std::nth_element(sorted.begin(), sorted.begin() + sorted.size() / 2, sorted.end());
    summary.stepWallMedian = sorted[sorted.size() / 2];
    summary.stepWallMax = *std::max_element(stepWall.begin(), stepWall.end());
  }
  if (!vtuFiles.empty()) {
    const std::string path = (fs::path(options.outDir) / (scene.name + ".pvd")).string();
    pvd.open(path);
    pvd.precision(12);
    pvd << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\">\n"
           "  <Collection>\n";
    for (const auto& [time, name] : vtuFiles)
      pvd << "    <DataSet timestep=\"" << time << "\" file=\"" << name << "\"/>\n";
    pvd << "  </Collection>\n</VTKFile>\n";
    summary.files.push_back(path);
    for (const auto& entry : vtuFiles)
      summary.files.push_back((fs::path(options.outDir) / entry.second).string());
  }
  return summary;
}

SettleSummary settleScene(Scene& scene, double seconds, double frame) {
  if (!(std::isfinite(frame) && frame > 0.0))
    throw std::invalid_argument("settle: expected a frame > 0 (s), got " + std::to_string(frame));
  if (!(std::isfinite(seconds) && seconds >= 0.0))
    throw std::invalid_argument("settle: expected a time >= 0 (s), got " + std::to_string(seconds));
  SettleSummary summary;
  const auto start = std::chrono::steady_clock::now();
  const double t0 = scene.system.state.t, end = t0 + seconds;
  while (scene.system.state.t < end - 1e-12) {
    const double step = std::min(frame, end - scene.system.state.t);
    const StepReport report = scene.integrator->advance(scene.system, step);
    ++summary.frames;
    if (!report.ok) {
      summary.ok = false;
      summary.failure = report.failure;
      break;
    }
  }
  summary.simulatedTime = scene.system.state.t - t0;
  summary.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return summary;
}

}  // namespace tt
