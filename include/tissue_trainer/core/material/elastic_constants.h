#pragma once
// The Lame constants the St Venant-Kirchhoff family and the Neo-Hookean law read (laws stvk and
// neo_hookean; models tensor_mass, edge_length, stvk_displacement). Transversely isotropic
// tissue adds longitudinal Lame constants (lambdaL, muL) along the fibre direction a0;
// isotropic material has lambdaL == lambda and muL == mu.
namespace tt {

struct ElasticConstants {
  double lambda = 0.0;   // Pa
  double mu = 0.0;       // Pa
  double lambdaL = 0.0;  // Pa, along the fibre
  double muL = 0.0;      // Pa, along the fibre

  // From Young's modulus E (Pa) and Poisson ratio nu in (-1, 0.5).
  static ElasticConstants isotropic(double E, double nu);
  // Transverse (E_T, nu_T) and longitudinal (E_L, nu_L) values, as in the muscle of Jeffrey,
  // "A non-linear anisotropic Finite Element Method for surgical simulation".
  static ElasticConstants transverselyIsotropic(double ET, double nuT, double EL, double nuL);

  // Coefficient of the fibre term (a0^T E a0)^2 in the StVK energy density (Jeffrey's Eq 24,
  // whose printed lambda^T, mu^T must read lambda^L, mu^L): c = (lambdaL - lambda)/2 + (muL - mu).
  double fibreCoefficient() const { return 0.5 * (lambdaL - lambda) + (muL - mu); }
};

// Young's modulus E (Pa) and Poisson ratio nu of an isotropic material.
struct IsotropicModuli {
  double young = 0.0;
  double poisson = 0.0;

  // From the Lame constants: nu = lambda / (2 (lambda + mu)), E = 2 mu (1 + nu).
  static IsotropicModuli fromLame(double lambda, double mu) {
    const double nu = lambda / (2.0 * (lambda + mu));
    return {2.0 * mu * (1.0 + nu), nu};
  }
};

inline double lameLambda(double E, double nu) { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
inline double lameMu(double E, double nu) { return E / (2.0 * (1.0 + nu)); }

inline ElasticConstants ElasticConstants::isotropic(double E, double nu) {
  return transverselyIsotropic(E, nu, E, nu);
}

inline ElasticConstants ElasticConstants::transverselyIsotropic(double ET, double nuT, double EL,
                                                                double nuL) {
  ElasticConstants k;
  k.lambda = lameLambda(ET, nuT);
  k.mu = lameMu(ET, nuT);
  k.lambdaL = lameLambda(EL, nuL);
  k.muL = lameMu(EL, nuL);
  return k;
}

}  // namespace tt
