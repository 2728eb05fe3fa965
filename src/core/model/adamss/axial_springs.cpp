#include "tissue_trainer/core/model/adamss/axial_springs.h"

#include <cmath>

namespace tt {
namespace adamss {
namespace {

// One axis's spring in terms of its length: energy, force magnitude phi = dE/d|zeta| and
// dphi/d|zeta|.
struct AxisSpring {
  double energy = 0.0, phi = 0.0, slope = 0.0;
};

template <int N>
AxisSpring axisSpring(const AxialSpringParameters& p, int l, double length,
                      const AxisSpringRest<N>& r) {
  const double L0 = r.length0[l];
  const double scale = p.areaForm ? r.area[l] : 1.0;       // A_l or 1
  const double dArg = p.areaForm ? 1.0 / L0 : 1.0;         // d(argument)/d|zeta|
  const double arg = p.areaForm ? length / L0 - 1.0 : length - L0;
  AxisSpring s;
  double power = 1.0;  // arg^(i-1)
  for (int i = 1; i <= AxialSpringParameters::kMaxOrder; ++i) {
    const double k = p.k[l][i - 1];
    s.slope += i * k * power;
    power *= arg;
    s.phi += k * power;
    s.energy += k * power * arg / (i + 1);
  }
  s.energy *= scale / dArg;
  s.phi *= scale;
  s.slope *= scale * dArg;
  return s;
}

}  // namespace

double AxialSpringModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                  Eigen::VectorXd& f) const {
  return elements_.addForces(x, f, [&](const Eigen::Matrix3d& zeta, const auto& r, double& energy) {
    Eigen::Matrix3d g;
    for (int l = 0; l < kAxes; ++l) {
      const double length = zeta.col(l).norm();
      const AxisSpring s = axisSpring(parameters_, l, length, r);
      g.col(l) = (-s.phi / length) * zeta.col(l);  // Eq. 2.35: -phi zeta_hat
      energy += s.energy;
    }
    return g;
  });
}

double AxialSpringModel::energy(const Eigen::VectorXd& x) const {
  return elements_.energy(x, [&](const Eigen::Matrix3d& zeta, const auto& r) {
    double energy = 0.0;
    for (int l = 0; l < kAxes; ++l) energy += axisSpring(parameters_, l, zeta.col(l).norm(), r).energy;
    return energy;
  });
}

namespace {

// d2E/dzeta2: per axis phi' u u^T + phi / |zeta| (I - u u^T), u = zeta_hat.
template <int N>
Matrix9d axialHessian(const AxialSpringParameters& p, const Eigen::Matrix3d& zeta,
                      const AxisSpringRest<N>& r) {
  Matrix9d H = Matrix9d::Zero();
  for (int l = 0; l < kAxes; ++l) {
    const double length = zeta.col(l).norm();
    const Eigen::Vector3d u = zeta.col(l) / length;
    const AxisSpring s = axisSpring(p, l, length, r);
    const Eigen::Matrix3d uu = u * u.transpose();
    H.block<3, 3>(3 * l, 3 * l) = s.slope * uu + (s.phi / length) * (Eigen::Matrix3d::Identity() - uu);
  }
  return H;
}

}  // namespace

void AxialSpringModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                    const SparsePattern& pattern, SparseMatrix& K) const {
  elements_.addStiffness(x, scale, pattern, K, [&](const Eigen::Matrix3d& zeta, const auto& r) {
    return axialHessian(parameters_, zeta, r);
  });
}

void AxialSpringModel::addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                         double scale, Eigen::VectorXd& out) const {
  elements_.addStiffnessTimes(x, d, scale, out, [&](const Eigen::Matrix3d& zeta, const auto& r) {
    return axialHessian(parameters_, zeta, r);
  });
}

}  // namespace adamss
}  // namespace tt
