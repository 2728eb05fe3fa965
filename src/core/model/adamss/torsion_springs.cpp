#include "tissue_trainer/core/model/adamss/torsion_springs.h"

#include <algorithm>
#include <cmath>

namespace tt {
namespace adamss {
namespace {

struct PairState {
  double theta = 0.0;            // the measure minus its rest value
  Eigen::Vector3d dThetaDl, dThetaDm;  // its gradient in zeta_l and zeta_m
};

PairState pairState(const Eigen::Vector3d& zl, const Eigen::Vector3d& zm, double restCosine,
                    bool cosine) {
  const double nl = zl.norm(), nm = zm.norm();
  const Eigen::Vector3d ul = zl / nl, um = zm / nm;
  const double c = std::clamp(ul.dot(um), -1.0, 1.0);
  PairState s;
  s.dThetaDl = (um - c * ul) / nl;  // d cos / d zeta_l
  s.dThetaDm = (ul - c * um) / nm;
  if (cosine) {
    s.theta = c - restCosine;
  } else {
    s.theta = std::acos(c) - std::acos(std::clamp(restCosine, -1.0, 1.0));
    const double sine = std::sqrt(std::max(1.0 - c * c, 1e-300));
    s.dThetaDl /= -sine;
    s.dThetaDm /= -sine;
  }
  return s;
}

// psi = sum_i k_i theta^i and the energy sum_i k_i theta^(i+1) / (i+1).
void polynomial(const std::array<double, 3>& k, double theta, double& psi, double& energy) {
  psi = energy = 0.0;
  double power = theta;
  for (int i = 1; i <= 3; ++i) {
    psi += k[i - 1] * power;
    energy += k[i - 1] * power * theta / (i + 1);
    power *= theta;
  }
}

}  // namespace

TorsionSpringModel::TorsionSpringModel(const Mesh& mesh,
                                       const TorsionSpringParameters& parameters)
    : elements_(mesh), parameters_(parameters) {}

double TorsionSpringModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                    Eigen::VectorXd& f) const {
  const TorsionSpringParameters& p = parameters_;
  return elements_.addForces(x, f, [&](const Eigen::Matrix3d& zeta, const auto& r, double& energy) {
    Eigen::Matrix3d g = Eigen::Matrix3d::Zero();  // column l: the force at q_2l
    for (int k = 0; k < TorsionSpringParameters::kPairs; ++k) {
      const int l = TorsionSpringParameters::pair[k][0], m = TorsionSpringParameters::pair[k][1];
      const PairState s = pairState(zeta.col(l), zeta.col(m), r.restCosine[k], p.cosine);
      double psi = 0.0, e = 0.0;
      polynomial(p.k[k], s.theta, psi, e);
      if (p.gradient) {
        const double scale = p.areaForm ? r.volume : 1.0;
        g.col(l) -= scale * psi * s.dThetaDl;
        g.col(m) -= scale * psi * s.dThetaDm;
        energy += scale * e;
      } else {  // Eqs. 2.40-2.41 (2.44-2.45 for the cosine), area form 2.51-2.55
        g.col(l) -= (p.areaForm ? r.area[l] : 1.0) * psi * zeta.col(m).normalized();
        g.col(m) -= (p.areaForm ? r.area[m] : 1.0) * psi * zeta.col(l).normalized();
      }
    }
    return g;
  });
}

double TorsionSpringModel::energy(const Eigen::VectorXd& x) const {
  if (!parameters_.gradient) return 0.0;
  const TorsionSpringParameters& p = parameters_;
  return elements_.energy(x, [&](const Eigen::Matrix3d& zeta, const auto& r) {
    double energy = 0.0;
    for (int k = 0; k < TorsionSpringParameters::kPairs; ++k) {
      const int l = TorsionSpringParameters::pair[k][0], m = TorsionSpringParameters::pair[k][1];
      double psi = 0.0, e = 0.0;
      polynomial(p.k[k], pairState(zeta.col(l), zeta.col(m), r.restCosine[k], p.cosine).theta,
                 psi, e);
      energy += (p.areaForm ? r.volume : 1.0) * e;
    }
    return energy;
  });
}

}  // namespace adamss
}  // namespace tt
