#pragma once
// Shared by the landmark-fit tests: the block of three muscle layers with crossed fibres of
// config/scenes/three_muscle_block.yaml, and node landmarks taken from one of its equilibria.
#include <string>
#include <vector>

#include "../scene/scene_test_util.h"
#include "tissue_trainer/core/fit/landmark_fit.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/scene/scene.h"

namespace tt {
namespace testutil {

// config/scenes/three_muscle_block.yaml
inline std::string threeMuscleBlockPath() {
  return std::string(TT_SOURCE_DIR) + "/config/scenes/three_muscle_block.yaml";
}

inline Scene loadThreeMuscleBlock() {
  return loadScene(threeMuscleBlockPath());
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
inline std::vector<Landmark> nodeLandmarks(const System& s, const Eigen::VectorXd& x, int stride,
                                           bool includeConstrained = false) {
  std::vector<Landmark> out;
  for (int n = 0; n < s.numNodes(); n += stride) {
    if (s.isConstrained[3 * n] && !includeConstrained) continue;
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
