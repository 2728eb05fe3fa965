#include "tissue_trainer/core/model/strain.h"

#include <cmath>

#include "tissue_trainer/core/mesh/tet_geometry.h"

namespace tt {

StrainSummary measureStrain(const Mesh& mesh, const Eigen::VectorXd& x, double damageStrain) {
  StrainSummary s;
  for (const Tet& t : mesh.tets) {
    const TetRest rest = tetRest(mesh.rest, t);
    if (!(std::abs(rest.volume) > 0.0) || !rest.grad.allFinite()) continue;
    const Eigen::Matrix3d F = deformationGradient(x, t, rest);
    const double strain =
        (0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity())).norm();
    if (!std::isfinite(strain)) continue;
    if (strain > s.maxStrain) s.maxStrain = strain;
    if (strain > damageStrain) {
      s.strainedVolume += std::abs(rest.volume);
      ++s.strainedTets;
    }
  }
  return s;
}

}  // namespace tt
