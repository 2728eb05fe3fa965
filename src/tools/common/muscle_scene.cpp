#include "common/muscle_scene.h"

#include <cmath>

#include "tissue_trainer/core/mesh/generators.h"

namespace tt {
namespace muscle_scene {

int bellyNode(const Mesh& mesh) {
  int best = 0;
  const Eigen::Vector3d target(1.0, 0.0, 0.05);
  for (int a = 0; a < mesh.numNodes(); ++a)
    if ((mesh.rest.col(a) - Eigen::Vector3d(0, 0, 0.05)).dot(target) >
        (mesh.rest.col(best) - Eigen::Vector3d(0, 0, 0.05)).dot(target) - 1e-12 &&
        std::abs(mesh.rest(2, a) - 0.05) < 1e-9)
      best = a;
  return best;
}

std::unique_ptr<System> muscle(const ModelMaker& make) {
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

double omegaMax(const System& s) {
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
