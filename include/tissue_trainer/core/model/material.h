#pragma once
// Elastic material constants of one region. Transversely isotropic tissue adds
// longitudinal Lame constants (lambdaL, muL) along the fibre direction a0; isotropic
// material has lambdaL == lambda and muL == mu.
namespace tt {

struct Material {
  double lambda = 0.0;   // Pa
  double mu = 0.0;       // Pa
  double lambdaL = 0.0;  // Pa, along the fibre
  double muL = 0.0;      // Pa, along the fibre
  double density = 1000.0;  // kg/m^3

  // Lame constants from Young's modulus E (Pa) and Poisson ratio nu in (-1, 0.5).
  static Material isotropic(double E, double nu, double density);
  // Transverse (E_T, nu_T) and longitudinal (E_L, nu_L) values, as in the muscle of Jeffrey,
  // "A non-linear anisotropic Finite Element Method for surgical simulation".
  static Material transverselyIsotropic(double ET, double nuT, double EL, double nuL,
                                        double density);

  // Coefficient of the fibre term (a0^T E a0)^2 in the StVK energy density (Jeffrey's Eq 24,
  // whose printed lambda^T, mu^T must read lambda^L, mu^L): c = (lambdaL - lambda)/2 + (muL - mu).
  double fibreCoefficient() const { return 0.5 * (lambdaL - lambda) + (muL - mu); }
};

inline double lameLambda(double E, double nu) { return E * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)); }
inline double lameMu(double E, double nu) { return E / (2.0 * (1.0 + nu)); }

inline Material Material::isotropic(double E, double nu, double density) {
  Material m;
  m.lambda = m.lambdaL = lameLambda(E, nu);
  m.mu = m.muL = lameMu(E, nu);
  m.density = density;
  return m;
}

inline Material Material::transverselyIsotropic(double ET, double nuT, double EL, double nuL,
                                                double density) {
  Material m;
  m.lambda = lameLambda(ET, nuT);
  m.mu = lameMu(ET, nuT);
  m.lambdaL = lameLambda(EL, nuL);
  m.muL = lameMu(EL, nuL);
  m.density = density;
  return m;
}

}  // namespace tt
