#pragma once
// The tongue experiment of bench_fitting (docs/muscles.md, "Fitting the tongue"): synthetic
// ground truth on config/scenes/tongue_muscles.yaml, the EMA-like markers of
// config/scenes/tongue_ema_landmarks.txt as landmarks, target noise 0, 0.1 and 1 mm, fitted
// from zero activations (and the identity jaw).
#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace bench {

inline const char* const kTongueMuscles[3] = {"superior_longitudinal", "transverse", "genioglossus"};

// The ground truth of one row set: activations, and a jaw rotation about the lateral (x) axis
// through the condyles followed by a translation: x -> R (x - c) + c + d = R x + (c - R c + d).
struct TongueTruth {
  Eigen::Vector3d activations;
  bool jaw = false;
  double jawAngleDeg = 0.0;                                  // about +x: negative opens the jaw
  Eigen::Vector3d condyle = Eigen::Vector3d(0, 0.03, 0.02);  // m, behind and above the root
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();     // m
  Eigen::Matrix3d M() const {
    return Eigen::AngleAxisd(jawAngleDeg * M_PI / 180.0, Eigen::Vector3d::UnitX()).toRotationMatrix();
  }
  Eigen::Vector3d t() const { return condyle - M() * condyle + translation; }
};

struct TongueRow {
  double noise = 0.0;  // m, standard deviation per coordinate
  Eigen::Vector3d activations;
  double jawAngleDeg = 0.0;       // of the fitted M (atan2(M21, M11))
  double jawNodeError = 0.0;      // m, max over the jaw nodes of |M x0 + t - (M* x0 + t*)|
  double jawMatrixError = 0.0;    // max |M - M*|
  int iterations = 0;
  const char* stop = "";
  double residual = 0.0;          // m, RMS landmark distance
  double seconds = 0.0;           // wall time of the fit
  double cpuSeconds = 0.0;        // process CPU time of the fit
};

inline void setTongueActivations(System& s, const Eigen::Vector3d& a) {
  for (int i = 0; i < 3; ++i) {
    const ActivationRef ref = s.findActivation(kTongueMuscles[i]);
    if (!ref.model) throw std::runtime_error(std::string("no muscle ") + kTongueMuscles[i]);
    ref.model->setActivation(ref.index, a[i]);
  }
}

inline EquilibriumParams tongueEquilibrium() {
  EquilibriumParams eq;
  eq.preconditioner = EquilibriumParams::Preconditioning::kCholesky;
  eq.absoluteTolerance = 1e-11;
  eq.relativeTolerance = 1e-12;
  return eq;
}

// Solves the truth's equilibrium from the rest shape, with the jaw nodes moved by the truth's
// jaw transform; returns the landmark positions there. The system is left at that equilibrium.
inline std::vector<Eigen::Vector3d> tongueTruthLandmarks(Scene& scene,
                                                         const std::vector<Landmark>& landmarks,
                                                         const TongueTruth& truth) {
  System& s = scene.system;
  s.state.x = Eigen::Map<const Eigen::VectorXd>(s.mesh.rest.data(), s.numDofs());
  setTongueActivations(s, truth.activations);
  if (truth.jaw)
    for (int n : scene.jawNodes)
      s.state.x.segment<3>(3 * n) = truth.M() * s.mesh.rest.col(n) + truth.t();
  const EquilibriumReport r = solveEquilibrium(s, tongueEquilibrium());
  if (!r.converged()) throw std::runtime_error("the ground truth's equilibrium failed: " + r.reason);
  std::vector<Eigen::Vector3d> y;
  for (const Landmark& l : landmarks) {
    Eigen::Vector3d p = Eigen::Vector3d::Zero();
    for (int k = 0; k < 4; ++k) p += l.weights[k] * s.state.x.segment<3>(3 * l.nodes[k]);
    y.push_back(p);
  }
  return y;
}

// One fit from zero activations and the identity jaw at the rest shape, to the truth's
// landmarks with Gaussian noise (fixed seed).
inline TongueRow fitTongue(Scene& scene, std::vector<Landmark> landmarks,
                           const std::vector<Eigen::Vector3d>& truthY, const TongueTruth& truth,
                           double noise, int maxIterations) {
  System& s = scene.system;
  std::mt19937 rng(7);
  std::normal_distribution<double> gauss(0.0, noise > 0 ? noise : 1.0);
  for (size_t l = 0; l < landmarks.size(); ++l) {
    landmarks[l].target = truthY[l];
    if (noise > 0) landmarks[l].target += Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng));
  }
  s.state.x = Eigen::Map<const Eigen::VectorXd>(s.mesh.rest.data(), s.numDofs());
  setTongueActivations(s, Eigen::Vector3d::Zero());
  FitParams params;
  params.equilibrium = tongueEquilibrium();
  params.residualTolerance = 1e-12;
  params.stepTolerance = 1e-9;
  params.maxIterations = maxIterations;
  params.fitJaw = truth.jaw;
  if (truth.jaw) params.jawNodes = scene.jawNodes;
  LandmarkFit fit(s, landmarks, params);
  const double wall0 = wallSeconds(), cpu0 = cpuSeconds();
  const FitResult r = fit.run();
  TongueRow row;
  row.seconds = wallSeconds() - wall0;
  row.cpuSeconds = cpuSeconds() - cpu0;
  row.noise = noise;
  row.activations = fit.parameters().head<3>();
  const Eigen::Matrix3d M = fit.jawMatrix();
  const Eigen::Vector3d t = fit.jawTranslation();
  row.jawAngleDeg = std::atan2(M(2, 1), M(1, 1)) * 180.0 / M_PI;
  row.jawMatrixError = (M - (truth.jaw ? truth.M() : Eigen::Matrix3d::Identity())).cwiseAbs().maxCoeff();
  if (truth.jaw)
    for (int n : scene.jawNodes) {
      const Eigen::Vector3d x0 = s.mesh.rest.col(n);
      row.jawNodeError = std::max(row.jawNodeError, (M * x0 + t - truth.M() * x0 - truth.t()).norm());
    }
  row.iterations = static_cast<int>(r.iterations.size());
  row.stop = stopName(r.stop);
  row.residual = r.residual;
  return row;
}

}  // namespace bench
}  // namespace tt
