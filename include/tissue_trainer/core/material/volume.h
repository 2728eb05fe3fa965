#pragma once
// Volume term of the Adamss mass-spring system (the thesis chapter "Adamss: Advanced
// Anisotropic Mass-Spring System", Secs. 2.4.2.3-2.4.2.4, Eqs. 2.86 and 2.101), written in F:
//   psi = p (J - r)^2,   J = det F,   P = 2 p (J - r) cof F,   cof F = J F^-T,
//   dP = 2 p [ (cof F : dF) cof F + (J - r) d(cof F) ].
// The printed table of Eq. 2.100 has (2 E_kk - 1) where (2 E_kk + 1) belongs; this is the exact
// derivative, S = F^-1 P = 2 p J (J - r) C^-1. It is a polynomial in F, so it is
// defined for inverted elements too (cof F is built from cross products of F's columns).
// r = 1 keeps the rest volume (Eq. 2.86); r = V_inf / V0 drives it towards V_inf.
#include <Eigen/Core>
#include <Eigen/Geometry>

namespace tt {

struct VolumeLaw {
  static constexpr const char* kName = "volume";
  static constexpr bool kIsotropic = true;

  struct Constants {
    double stiffness = 0.0;  // p, Pa
    double ratio = 1.0;      // r
  };
  using Parameters = Constants;

  static bool restStressFree(const Constants& k) { return k.ratio == 1.0; }
  static Parameters parameters(const Constants& k, const Eigen::Matrix3d&) { return k; }

  static Eigen::Matrix3d cofactor(const Eigen::Matrix3d& F) {
    Eigen::Matrix3d C;
    C.col(0) = F.col(1).cross(F.col(2));
    C.col(1) = F.col(2).cross(F.col(0));
    C.col(2) = F.col(0).cross(F.col(1));
    return C;
  }

  static double energy(const Parameters& p, const Eigen::Matrix3d& F) {
    const double d = F.determinant() - p.ratio;
    return p.stiffness * d * d;
  }
  static Eigen::Matrix3d stress(const Parameters& p, const Eigen::Matrix3d& F) {
    return (2.0 * p.stiffness * (F.determinant() - p.ratio)) * cofactor(F);
  }
  static Eigen::Matrix3d stressDifferential(const Parameters& p, const Eigen::Matrix3d& F,
                                            const Eigen::Matrix3d& dF) {
    const Eigen::Matrix3d C = cofactor(F);
    Eigen::Matrix3d dC;
    dC.col(0) = dF.col(1).cross(F.col(2)) + F.col(1).cross(dF.col(2));
    dC.col(1) = dF.col(2).cross(F.col(0)) + F.col(2).cross(dF.col(0));
    dC.col(2) = dF.col(0).cross(F.col(1)) + F.col(0).cross(dF.col(1));
    const double dJ = (C.array() * dF.array()).sum();
    return 2.0 * p.stiffness * (dJ * C + (F.determinant() - p.ratio) * dC);
  }
};

}  // namespace tt
