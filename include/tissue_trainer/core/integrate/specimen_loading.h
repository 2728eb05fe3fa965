#pragma once
// Quasi-static material tests of a specimen, as in "Adamss: Advanced Anisotropic Mass-Spring
// System", Secs. 2.6 and 2.8.1: the faces at both ends of one axis are clamped by fixation and
// control tags, the upper face is moved in small steps, and each step is brought to
// equilibrium (equilibrium.h) before the reaction force is read.
//
// Uniaxial stretch along axis a: the lower face (least coordinate a) is fixed in x, y and z,
// the upper face (greatest a) is fixed in the two lateral directions and controlled along a.
// The specimen's other faces are free.
//
// Simple shear: the face with normal n at the lower end is fixed in x, y and z; the face at
// the upper end is moved along the direction d (d != n) by gamma times the height H (the
// extent along n) and held in the other two directions; the lateral faces are free.
//
// The system's existing fixation tags and controlled sets are replaced. Each step starts
// from the last equilibrium with the free nodes moved by the step's affine increment (a
// predictor that keeps Newton's first step small).
#include <functional>
#include <string>
#include <vector>

#include "tissue_trainer/core/solve/equilibrium.h"
#include "tissue_trainer/core/system.h"

namespace tt {

// The nodes of the two faces normal to an axis (within 1e-6 of the extent of the extreme
// coordinate) and their rest areas (the boundary triangles with all three nodes on the face).
struct SpecimenFaces {
  std::vector<int> lower, upper;
  double lowerArea = 0.0, upperArea = 0.0;
  double height = 0.0;  // extent along the axis (m)
};
// Throws std::invalid_argument when the mesh has no extent along the axis or an end face has
// no area (the specimen does not end in a flat face).
SpecimenFaces specimenFaces(const Mesh& mesh, int axis);

struct StretchRow {
  double strain = 0.0;   // (L - L0) / L0
  double stretch = 1.0;  // L / L0
  double force = 0.0;    // N: the controlled face's reaction along the axis
  double stress = 0.0;   // Pa: force / the face's rest area (first Piola-Kirchhoff)
};

struct ShearRow {
  double shear = 0.0;   // gamma: displacement of the upper face / H
  double work = 0.0;    // J: Eq. 2.151 summed (Eq. 2.152) from gamma = 0
  double energy = 0.0;  // J: the models' potential energy
};

struct SpecimenRun {
  bool ok = true;
  std::string failure;  // the step and the solver's reason when !ok
  EquilibriumReport last;  // of the last step solved
};

// steps >= 1 equal steps from strain 0 to maxStrain (> -1): steps + 1 rows, the first at
// strain 0 (after its own equilibrium, which differs from rest for an active material).
// `row` is called after each step; the run stops at the first step that does not converge.
SpecimenRun stretchSpecimen(System& system, int axis, double maxStrain, int steps,
                            const EquilibriumParams& params,
                            const std::function<void(const StretchRow&)>& row);
SpecimenRun shearSpecimen(System& system, int normal, int direction, double maxShear, int steps,
                          const EquilibriumParams& params,
                          const std::function<void(const ShearRow&)>& row);

}  // namespace tt
