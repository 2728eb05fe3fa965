#pragma once
// The spindle-muscle scene shared by bench_muscle_demo and bench_force_threshold (Jeffrey, "A
// non-linear anisotropic Finite Element Method for surgical simulation", Sec. 3): 861 nodes,
// 2400 tets, E_L 150 kPa / nu 0.4 along the fibres, E_T 20 kPa / nu 0.4 across, density 1060,
// tendon end layers fixed, mass-proportional damping 10 / s; the belly node on the +x side is
// pulled 1 cm along +x over 0.1 s and back over 0.1 s.
#include <Eigen/Core>
#include <cmath>
#include <functional>
#include <memory>
#include <vector>

#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace muscle_scene {

constexpr double kPeak = 0.1, kEnd = 0.2;  // s
constexpr double kPull = 0.01;             // m
constexpr double kDampingRate = 10.0;      // 1/s

using ModelMaker =
    std::function<std::unique_ptr<ForceModel>(const Mesh&, const std::vector<Material>&)>;

// The belly node on the +x side at mid-length.
inline int bellyNode(const Mesh& mesh) {
  int best = 0;
  const Eigen::Vector3d target(1.0, 0.0, 0.05);
  for (int a = 0; a < mesh.numNodes(); ++a)
    if ((mesh.rest.col(a) - Eigen::Vector3d(0, 0, 0.05)).dot(target) >
        (mesh.rest.col(best) - Eigen::Vector3d(0, 0, 0.05)).dot(target) - 1e-12 &&
        std::abs(mesh.rest(2, a) - 0.05) < 1e-9)
      best = a;
  return best;
}

inline std::unique_ptr<System> muscle(const ModelMaker& make) {
  Mesh mesh = spindleMuscle(SpindleShape{});
  const std::vector<Material> materials = {
      Material::transverselyIsotropic(20e3, 0.4, 150e3, 0.4, 1060.0)};
  const int belly = bellyNode(mesh);
  auto s = std::make_unique<System>(mesh, materials);
  s->damping = kDampingRate * s->mass;
  s->models.push_back(make(s->mesh, materials));
  s->controlled.push_back({{belly},
                           {{0.0, kPeak, kEnd},
                            {Eigen::Vector3d::Zero(), Eigen::Vector3d(kPull, 0, 0),
                             Eigen::Vector3d::Zero()}}});
  s->updateConstraints();
  return s;
}

// Largest omega of M^-1 (-K) at rest on the free DOFs, by power iteration.
inline double omegaMax(const System& s) {
  SparseMatrix K;
  s.assembleStiffness(s.state.x, K);
  Eigen::VectorXd w = Eigen::VectorXd::Ones(s.numDofs()), y;
  const Eigen::VectorXd invSqrtM = s.mass.cwiseSqrt().cwiseInverse();
  double lambda = 0.0;
  for (int it = 0; it < 300; ++it) {
    s.zeroConstrained(w);
    w.normalize();
    y = -(invSqrtM.asDiagonal() * (K * (invSqrtM.asDiagonal() * w)));
    s.zeroConstrained(y);
    lambda = w.dot(y);
    w = y;
  }
  return std::sqrt(lambda);
}

}  // namespace muscle_scene
}  // namespace tt
