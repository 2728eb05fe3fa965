// bench_fitting: landmark fitting on synthetic ground truth (docs/muscles.md, "Landmark
// fitting"), with target noise 0, 0.1 and 1 mm: recovered parameters against the truth,
// iterations, wall time and final RMS residual, as tables.
//   block:  the activations of the three-muscle block (config/scenes/three_muscle_block.yaml);
//   tongue: the three muscles of config/scenes/tongue_muscles.yaml, then with a jaw transform,
//           from the EMA-like markers of config/scenes/tongue_ema_landmarks.txt.
// Usage: bench_fitting [--only block|tongue] [--quick] [--out DIR]
//        bench_fitting --tongue-targets   (prints the markers' targets at the tongue's truth)
//        bench_fitting --tongue-sensitivity   (marker motion per unit activation there)
// --quick: the tongue's activations without noise only. --out DIR writes DIR/fitting_block.csv and
// DIR/fitting_tongue.csv besides the Markdown tables on stdout.
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>

#include <Eigen/SVD>

#include "bench_fitting_tongue.h"
#include "common/command_line.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/scene/scene.h"

namespace {

const std::string kRoot = TT_SOURCE_ROOT;

void setActivations(tt::System& s, const double* a) {
  const char* names[3] = {"lower", "middle", "upper"};
  for (int i = 0; i < 3; ++i) {
    const tt::ActivationRef ref = s.findActivation(names[i]);
    ref.model->setActivation(ref.index, a[i]);
  }
}

int block(std::FILE* csv) {
  const std::string path = kRoot + "/config/scenes/three_muscle_block.yaml";
  const double truth[3] = {0.3, 0.6, 0.45};
  tt::EquilibriumParams eq;
  eq.preconditioner = tt::EquilibriumParams::Preconditioning::kCholesky;
  eq.absoluteTolerance = 1e-12;
  eq.relativeTolerance = 1e-14;
  std::printf("| landmarks | noise (mm) | lower | middle | upper | max error | iterations | stop | residual (m) | time (ms) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|\n");
  if (csv) std::fprintf(csv, "landmarks,noise_mm,lower,middle,upper,max_error,iterations,stop,residual_m,time_ms\n");
  for (int stride : {4, 1})
  for (double noise : {0.0, 1e-4, 1e-3}) {
    tt::Scene scene = tt::loadScene(path);
    tt::System& s = scene.system;
    const Eigen::VectorXd rest = s.state.x;
    setActivations(s, truth);
    const tt::EquilibriumReport truthSolve = tt::solveEquilibrium(s, eq);
    if (!truthSolve.converged()) {
      std::fprintf(stderr, "bench_fitting: the ground truth's equilibrium failed: %s\n",
                   truthSolve.reason.c_str());
      return 3;
    }
    std::mt19937 rng(7);
    std::normal_distribution<double> gauss(0.0, noise > 0 ? noise : 1.0);
    std::vector<tt::Landmark> landmarks;
    for (int n = 0; n < s.numNodes(); n += stride) {
      if (s.isConstrained[3 * n]) continue;
      tt::Landmark l;
      l.nodes = {n, n, n, n};
      l.weights = Eigen::Vector4d(1, 0, 0, 0);
      l.target = s.state.x.segment<3>(3 * n);
      if (noise > 0) l.target += Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
      landmarks.push_back(l);
    }
    const double zero[3] = {0, 0, 0};
    setActivations(s, zero);
    s.state.x = rest;
    tt::FitParams params;
    params.equilibrium = eq;
    params.residualTolerance = 1e-12;
    params.stepTolerance = 1e-9;
    tt::LandmarkFit fit(s, landmarks, params);
    const auto start = std::chrono::steady_clock::now();
    const tt::FitResult r = fit.run();
    const double ms = 1e3 * std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    const Eigen::VectorXd a = fit.parameters();
    double maxError = 0;
    for (int i = 0; i < 3; ++i) maxError = std::max(maxError, std::abs(a[i] - truth[i]));
    std::printf("| %zu | %g | %.6f | %.6f | %.6f | %.2e | %zu | %s | %.3e | %.0f |\n", landmarks.size(), 1e3 * noise, a[0],
                a[1], a[2], maxError, r.iterations.size(), tt::stopName(r.stop), r.residual, ms);
    if (csv)
      std::fprintf(csv, "%zu,%g,%.9f,%.9f,%.9f,%.3e,%zu,%s,%.6e,%.1f\n", landmarks.size(), 1e3 * noise,
                   a[0], a[1], a[2], maxError, r.iterations.size(), tt::stopName(r.stop), r.residual, ms);
  }
  std::printf("truth: lower %.2f, middle %.2f, upper %.2f; %s\n\n", truth[0], truth[1], truth[2],
              "landmarks: every 4th free node, or every free node; Gaussian noise of the given standard deviation per coordinate");
  return 0;
}

// Activations only, then with a 3 degree jaw opening about the condyles and a 1 mm translation
// (down and forward).
std::vector<tt::bench::TongueTruth> tongueTruths() {
  tt::bench::TongueTruth activations;
  activations.activations = Eigen::Vector3d(0.1, 0.4, 0.3);
  tt::bench::TongueTruth jaw = activations;
  jaw.jaw = true;
  jaw.jawAngleDeg = -3.0;
  jaw.translation = Eigen::Vector3d(0.0, -0.0007, -0.0007);
  return {activations, jaw};
}

std::string tongueLandmarksPath() { return kRoot + "/config/scenes/tongue_ema_landmarks.txt"; }

int tongue(std::FILE* csv, bool quick) {
  tt::Scene scene = tt::loadScene(kRoot + "/config/scenes/tongue_muscles.yaml");
  const std::vector<tt::Landmark> landmarks = tt::readLandmarks(tongueLandmarksPath(), scene.system.mesh);
  std::printf("| truth | noise (mm) | superior_longitudinal | transverse | genioglossus | max activation error | jaw angle (deg) | jaw node error (mm) | iterations | stop | RMS residual (mm) | time (s) | CPU (s) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
  if (csv)
    std::fprintf(csv, "truth,noise_mm,superior_longitudinal,transverse,genioglossus,max_activation_error,"
                      "jaw_angle_deg,jaw_matrix_error,jaw_node_error_mm,iterations,stop,residual_mm,time_s,cpu_s\n");
  for (const tt::bench::TongueTruth& truth : tongueTruths()) {
    if (quick && truth.jaw) continue;
    const std::vector<Eigen::Vector3d> y = tt::bench::tongueTruthLandmarks(scene, landmarks, truth);
    const char* label = truth.jaw ? "activations + jaw" : "activations";
    for (double noise : {0.0, 1e-4, 1e-3}) {
      if (quick && noise > 0) continue;
      const tt::bench::TongueRow row = tt::bench::fitTongue(scene, landmarks, y, truth, noise, 20);
      const double error = (row.activations - truth.activations).cwiseAbs().maxCoeff();
      char jawAngle[32] = "-", jawError[32] = "-";
      if (truth.jaw) {
        std::snprintf(jawAngle, sizeof jawAngle, "%.4f", row.jawAngleDeg);
        std::snprintf(jawError, sizeof jawError, "%.2e", 1e3 * row.jawNodeError);
      }
      std::printf("| %s | %g | %.6f | %.6f | %.6f | %.2e | %s | %s | %d | %s | %.3e | %.1f | %.1f |\n",
                  label, 1e3 * noise, row.activations[0], row.activations[1], row.activations[2],
                  error, jawAngle, jawError, row.iterations, row.stop, 1e3 * row.residual,
                  row.seconds, row.cpuSeconds);
      std::fflush(stdout);
      if (csv)
        std::fprintf(csv, "%s,%g,%.9f,%.9f,%.9f,%.3e,%.6f,%.3e,%.3e,%d,%s,%.6e,%.2f,%.2f\n", label,
                     1e3 * noise, row.activations[0], row.activations[1], row.activations[2], error,
                     truth.jaw ? row.jawAngleDeg : 0.0, row.jawMatrixError,
                     truth.jaw ? 1e3 * row.jawNodeError : 0.0, row.iterations, row.stop,
                     1e3 * row.residual, row.seconds, row.cpuSeconds);
    }
  }
  const tt::bench::TongueTruth jaw = tongueTruths()[1];
  std::printf("truth: superior_longitudinal %.2f, transverse %.2f, genioglossus %.2f; jaw %.1f deg "
              "about x through the condyles (0, %.0f, %.0f) mm, then (%.1f, %.1f, %.1f) mm; %zu "
              "landmarks of %s (%zu jaw nodes); Gaussian noise per coordinate\n",
              jaw.activations[0], jaw.activations[1], jaw.activations[2], jaw.jawAngleDeg,
              1e3 * jaw.condyle[1], 1e3 * jaw.condyle[2], 1e3 * jaw.translation[0],
              1e3 * jaw.translation[1], 1e3 * jaw.translation[2], landmarks.size(),
              "config/scenes/tongue_ema_landmarks.txt", scene.jawNodes.size());
  return 0;
}

// The markers of the landmarks file with the targets of the activations-only truth.
int printTongueTargets() {
  tt::Scene scene = tt::loadScene(kRoot + "/config/scenes/tongue_muscles.yaml");
  const std::vector<tt::Landmark> landmarks = tt::readLandmarks(tongueLandmarksPath(), scene.system.mesh);
  const std::vector<Eigen::Vector3d> y =
      tt::bench::tongueTruthLandmarks(scene, landmarks, tongueTruths()[0]);
  for (size_t l = 0; l < landmarks.size(); ++l)
    std::printf("node %d %.9f %.9f %.9f\n", scene.system.mesh.numbering.nodeToFile(landmarks[l].nodes[0]),
                y[l][0], y[l][1], y[l][2]);
  return 0;
}

// How far the markers move per unit of each activation at the activations-only truth: the RMS
// over the markers of the columns of dy/da (Eq. 6), in mm. Noise of that size per coordinate
// makes the activation uncertain by about one unit over sqrt(3 L) coordinates.
int printTongueSensitivity() {
  tt::Scene scene = tt::loadScene(kRoot + "/config/scenes/tongue_muscles.yaml");
  const std::vector<tt::Landmark> landmarks = tt::readLandmarks(tongueLandmarksPath(), scene.system.mesh);
  const tt::bench::TongueTruth truth = tongueTruths()[0];
  tt::bench::tongueTruthLandmarks(scene, landmarks, truth);
  tt::FitParams params;
  params.equilibrium = tt::bench::tongueEquilibrium();
  tt::LandmarkFit fit(scene.system, landmarks, params);
  Eigen::VectorXd y;
  Eigen::MatrixXd J;
  if (!fit.evaluate(truth.activations, y, &J)) throw std::runtime_error(fit.failure());
  const double perMarker = 1.0 / std::sqrt(static_cast<double>(landmarks.size()));
  for (int i = 0; i < 3; ++i)
    std::printf("%s: RMS marker motion per unit activation %.3f mm\n", tt::bench::kTongueMuscles[i],
                1e3 * perMarker * J.col(i).norm());
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd(J);
  std::printf("singular values of dy/da (mm): %.4f %.4f %.4f\n", 1e3 * svd.singularValues()[0],
              1e3 * svd.singularValues()[1], 1e3 * svd.singularValues()[2]);
  return 0;
}

int run(int argc, char** argv) {
  tt::tools::CommandLine options(
      argc, argv,
      "bench_fitting [--only block|tongue] [--quick] [--out DIR] | --tongue-targets | "
      "--tongue-sensitivity");
  if (options.flag("--tongue-targets")) return printTongueTargets();
  if (options.flag("--tongue-sensitivity")) return printTongueSensitivity();
  const bool quick = options.flag("--quick");
  const std::string only = options.text("--only", "");
  const std::string out = options.text("--out", "");
  options.finish();
  if (!only.empty() && only != "block" && only != "tongue")
    options.fail("--only expects block or tongue, got '" + only + "'");
  const auto open = [&](const char* name) -> std::FILE* {
    if (out.empty()) return nullptr;
    std::filesystem::create_directories(out);
    return std::fopen((out + "/" + name).c_str(), "w");
  };
  if (only.empty() || only == "block") {
    std::FILE* csv = open("fitting_block.csv");
    const int status = block(csv);
    if (csv) std::fclose(csv);
    if (status != 0) return status;
  }
  if (only.empty() || only == "tongue") {
    std::FILE* csv = open("fitting_tongue.csv");
    const int status = tongue(csv, quick);
    if (csv) std::fclose(csv);
    if (status != 0) return status;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_fitting: %s\n", e.what());
    return 3;
  }
}
