#pragma once
// The muscle tissue that bench_work_precision and bench_stability_sweep run beside the
// registry's presets: the force model `muscle_groups` with the teran_muscle law (M. Bao,
// "Derivation of Quasistatics and Landmark Optimization for Muscles", Sec. 4.3, Eq. 10) and one
// muscle over every element, its fibres along each element's fibre axis, at a fixed activation.
// Three variants of the law's options:
//   teran_muscle                 no inversion handling (J > 0 only)
//   teran_muscle_inversion       inversion_threshold 0.25 (PhysBAM's value)
//   teran_muscle_inversion_psd   the same, the element tangents projected to PSD
// For Young's modulus E and Poisson's ratio nu the law's constants give the same small-strain
// response as the isotropic material: shear modulus mu = 2 (A + B) with A = 3 B (FACE_3D's
// ratio 6e4 : 2e4), bulk modulus K = E / (3 (1 - 2 nu)); the peak stress sigma_max = mu.
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/model/muscle_groups.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace muscle_bench {

inline const std::vector<std::string>& modelNames() {
  static const std::vector<std::string> names = {"teran_muscle", "teran_muscle_inversion",
                                                 "teran_muscle_inversion_psd"};
  return names;
}

inline bool isMuscleModel(const std::string& name) {
  for (const std::string& n : modelNames())
    if (n == name) return true;
  return false;
}

inline TeranMuscleLaw::Constants constantsFor(double young, double poisson) {
  const double mu = young / (2.0 * (1.0 + poisson));
  TeranMuscleLaw::Constants k;
  k.A = 0.375 * mu;
  k.B = 0.125 * mu;
  k.K = young / (3.0 * (1.0 - 2.0 * poisson));
  k.sigmaMax = mu;
  return k;
}

inline LawOptions optionsOf(const std::string& name) {
  LawOptions o;
  if (name != "teran_muscle") o.inversionThreshold = 0.25;
  o.psdProjection = name == "teran_muscle_inversion_psd";
  return o;
}

// Adds the variant `name` to s: one muscle "block" over every tet at `activation`.
inline void addModel(System& s, const std::string& name, double young, double poisson,
                     double activation) {
  s.mesh.fillDefaults();
  MuscleGroup block;
  block.name = "block";
  block.activation = activation;
  for (int e = 0; e < s.mesh.numTets(); ++e) block.elements.push_back(e);
  s.models.push_back(std::make_unique<MuscleGroupsModel>(
      s.mesh, std::vector<TeranMuscleLaw::Constants>{constantsFor(young, poisson)},
      std::vector<MuscleGroup>{block}, optionsOf(name)));
}

}  // namespace muscle_bench
}  // namespace tt
