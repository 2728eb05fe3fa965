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

// The Hessian of theta in (zeta_l, zeta_m), blocks ll, lm, mm (ml = lm^T). With
// c = u_l . u_m, g_l = dc/dzeta_l = (u_m - c u_l) / |zeta_l|, P_l = I - u_l u_l^T:
//   d2c/dzeta_l2      = -(u_l g_l^T + g_l u_l^T) / |zeta_l| - c P_l / |zeta_l|^2
//   d2c/dzeta_l dzeta_m = (P_m / |zeta_m| - u_l g_m^T) / |zeta_l|
// and for the angle a = acos(c), with s = sin a: d2a = -d2c / s - (c / s^3) dc dc^T.
struct PairHessian {
  Eigen::Matrix3d ll, lm, mm;
};

PairHessian pairHessian(const Eigen::Vector3d& zl, const Eigen::Vector3d& zm, bool cosine) {
  const double nl = zl.norm(), nm = zm.norm();
  const Eigen::Vector3d ul = zl / nl, um = zm / nm;
  const double c = std::clamp(ul.dot(um), -1.0, 1.0);
  const Eigen::Vector3d gl = (um - c * ul) / nl, gm = (ul - c * um) / nm;
  const Eigen::Matrix3d I = Eigen::Matrix3d::Identity();
  PairHessian h;
  h.ll = -(ul * gl.transpose() + gl * ul.transpose()) / nl -
         c * (I - ul * ul.transpose()) / (nl * nl);
  h.mm = -(um * gm.transpose() + gm * um.transpose()) / nm -
         c * (I - um * um.transpose()) / (nm * nm);
  h.lm = ((I - um * um.transpose()) / nm - ul * gm.transpose()) / nl;
  if (cosine) return h;
  const double sine = std::sqrt(std::max(1.0 - c * c, 1e-300));
  const double curvature = c / (sine * sine * sine);
  h.ll = -h.ll / sine - curvature * gl * gl.transpose();
  h.mm = -h.mm / sine - curvature * gm * gm.transpose();
  h.lm = -h.lm / sine - curvature * gl * gm.transpose();
  return h;
}

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

// d psi / d theta = sum_i i k_i theta^(i-1).
double polynomialSlope(const std::array<double, 3>& k, double theta) {
  return k[0] + 2.0 * k[1] * theta + 3.0 * k[2] * theta * theta;
}

// The Hessian in zeta of the gradient form's energy s sum_pairs sum_i k_i theta^(i+1) / (i+1):
// s (psi' grad theta grad theta^T + psi d2 theta) per pair.
Matrix9d torsionHessian(const TorsionSpringParameters& p, const Eigen::Matrix3d& zeta,
                        const Eigen::Vector3d& restCosine, double scale) {
  Matrix9d H = Matrix9d::Zero();
  for (int k = 0; k < TorsionSpringParameters::kPairs; ++k) {
    const int l = TorsionSpringParameters::pair[k][0], m = TorsionSpringParameters::pair[k][1];
    const PairState s = pairState(zeta.col(l), zeta.col(m), restCosine[k], p.cosine);
    const PairHessian h = pairHessian(zeta.col(l), zeta.col(m), p.cosine);
    double psi = 0.0, e = 0.0;
    polynomial(p.k[k], s.theta, psi, e);
    const double slope = polynomialSlope(p.k[k], s.theta);
    H.block<3, 3>(3 * l, 3 * l) +=
        scale * (slope * s.dThetaDl * s.dThetaDl.transpose() + psi * h.ll);
    H.block<3, 3>(3 * m, 3 * m) +=
        scale * (slope * s.dThetaDm * s.dThetaDm.transpose() + psi * h.mm);
    const Eigen::Matrix3d lm = scale * (slope * s.dThetaDl * s.dThetaDm.transpose() + psi * h.lm);
    H.block<3, 3>(3 * l, 3 * m) += lm;
    H.block<3, 3>(3 * m, 3 * l) += lm.transpose();
  }
  return H;
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

void TorsionSpringModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                      const SparsePattern& pattern, SparseMatrix& K) const {
  elements_.addStiffness(x, scale, pattern, K, [&](const Eigen::Matrix3d& zeta, const auto& r) {
    return torsionHessian(parameters_, zeta, r.restCosine, parameters_.areaForm ? r.volume : 1.0);
  });
}

void TorsionSpringModel::addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                           double scale, Eigen::VectorXd& out) const {
  elements_.addStiffnessTimes(x, d, scale, out, [&](const Eigen::Matrix3d& zeta, const auto& r) {
    return torsionHessian(parameters_, zeta, r.restCosine, parameters_.areaForm ? r.volume : 1.0);
  });
}

}  // namespace adamss
}  // namespace tt
