#pragma once
// Strain of a deformed mesh for the tissue status: the Frobenius norm of the Green-Lagrange
// strain E = (F^T F - I) / 2 per tet, its maximum, and the rest volume of the tets whose
// strain norm exceeds a damage threshold (tissue counted as overstretched or crushed).
#include <Eigen/Core>

#include "tissue_trainer/core/mesh/mesh.h"

namespace tt {

struct StrainSummary {
  double maxStrain = 0.0;       // largest |E|_F over the tets
  double strainedVolume = 0.0;  // rest volume of the tets with |E|_F > damageStrain (m^3)
  int strainedTets = 0;
};

// x: deformed positions (3n). Degenerate rest tets are skipped.
StrainSummary measureStrain(const Mesh& mesh, const Eigen::VectorXd& x, double damageStrain);

}  // namespace tt
