#pragma once
// What every material of a scene has: its density (the lumped masses read it). The constants of
// a material law are the law's own, read by the law from the `materials` entry when the scene
// creates it (hunter its hunter map, teran_muscle its teran_muscle map, volume its
// volume_stiffness). The Lame constants are the one set five laws and models share (stvk,
// neo_hookean, tensor_mass, edge_length, stvk_displacement): outside a scene they are given
// here; in a scene the loader sets them once a model has read them from the entry
// (ModelContext::elastic), and leaves them unset for a material whose laws read others.
#include <optional>
#include <stdexcept>

#include "tissue_trainer/core/material/elastic_constants.h"

namespace tt {

struct Material {
  double density = 1000.0;                  // kg/m^3
  std::optional<ElasticConstants> elastic;  // unset: the material gives no Lame constants
  // Young's modulus and Poisson ratio, set by isotropic() (or by the caller): the tissue
  // presets scale a published law to them (registry.h, TissuePreset).
  std::optional<IsotropicModuli> moduli;

  // Lame constants from Young's modulus E (Pa) and Poisson ratio nu in (-1, 0.5).
  static Material isotropic(double E, double nu, double density);
  // Transverse (E_T, nu_T) and longitudinal (E_L, nu_L) values (ElasticConstants).
  static Material transverselyIsotropic(double ET, double nuT, double EL, double nuL,
                                        double density);
  static Material withConstants(const ElasticConstants& k, double density);

  // The Lame constants; std::invalid_argument when unset (a scene checks before, at the entry).
  const ElasticConstants& elasticConstants() const {
    if (!elastic)
      throw std::invalid_argument(
          "the material gives no Lame constants (young_modulus/poisson_ratio or lambda/mu)");
    return *elastic;
  }
};

inline Material Material::withConstants(const ElasticConstants& k, double density) {
  Material m;
  m.elastic = k;
  m.density = density;
  return m;
}

inline Material Material::isotropic(double E, double nu, double density) {
  Material m = withConstants(ElasticConstants::isotropic(E, nu), density);
  m.moduli = IsotropicModuli{E, nu};
  return m;
}

inline Material Material::transverselyIsotropic(double ET, double nuT, double EL, double nuL,
                                                double density) {
  return withConstants(ElasticConstants::transverselyIsotropic(ET, nuT, EL, nuL), density);
}

}  // namespace tt
