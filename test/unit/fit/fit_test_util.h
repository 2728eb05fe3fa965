#pragma once
// Shared by the landmark-fit tests: a block of three muscle layers with crossed fibres, fixed
// on its bottom face, and node landmarks taken from one of its equilibria.
#include <string>
#include <vector>

#include "../scene/scene_test_util.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace testutil {

inline const char* threeMuscleBlock() {
  return R"(name: three_muscles
mesh: {generator: box, nodes: [5, 5, 4], size: [0.02, 0.02, 0.015]}
materials:
  - young_modulus: 20
    poisson_ratio: 0.45
    stress_unit: kPa
    teran_muscle: {mooney_rivlin: [6, 2], bulk: 60, peak_stress: 4}
force_models:
  - type: muscle_groups
    law: teran_muscle
    muscles:
      - name: lower
        region: {box: {min: [-1, -1, -1], max: [1, 1, 0.005]}}
        fibres: {direction: [1, 0, 0]}
      - name: middle
        region: {box: {min: [-1, -1, 0.005], max: [1, 1, 0.01]}}
        fibres: {direction: [0, 1, 0]}
      - name: upper
        region: {box: {min: [-1, -1, 0.01], max: [1, 1, 1]}}
        fibres: {direction: [1, 1, 0]}
integrator: {type: quasistatic}
boundary:
  fixed:
    - {box: {min: [-1, -1, -0.001], max: [1, 1, 0.001]}}
run: {frame_time: 1, duration: 1}
)";
}

inline Scene loadThreeMuscleBlock() {
  return loadScene(writeScene("three_muscles.yaml", threeMuscleBlock()));
}

inline void setActivations(System& s, const std::vector<double>& a) {
  const char* names[3] = {"lower", "middle", "upper"};
  for (int i = 0; i < 3; ++i) {
    const ActivationRef ref = s.findActivation(names[i]);
    ref.model->setActivation(ref.index, a[i]);
  }
}

inline EquilibriumParams tightEquilibrium() {
  EquilibriumParams p;
  p.absoluteTolerance = 1e-12;
  p.relativeTolerance = 1e-14;
  p.preconditioner = EquilibriumParams::Preconditioning::kCholesky;
  return p;
}

// Node landmarks at every `stride`-th free node of the current state x.
inline std::vector<Landmark> nodeLandmarks(const System& s, const Eigen::VectorXd& x, int stride) {
  std::vector<Landmark> out;
  for (int n = 0; n < s.numNodes(); n += stride) {
    if (s.isConstrained[3 * n]) continue;
    Landmark l;
    l.nodes = {n, n, n, n};
    l.weights = Eigen::Vector4d(1, 0, 0, 0);
    l.target = x.segment<3>(3 * n);
    out.push_back(l);
  }
  return out;
}

}  // namespace testutil
}  // namespace tt
