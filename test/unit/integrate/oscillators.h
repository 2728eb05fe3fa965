#pragma once
// Test problems for the integrators: independent per-DOF oscillators, harmonic or Duffing,
// with a closed-form solution in the harmonic case.
#include <Eigen/Core>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <memory>
#include <vector>

#include "tissue_trainer/core/system.h"

namespace tt {
namespace oscillators {

constexpr double kPi = 3.14159265358979323846;

// f_i = -k_i (x_i - r_i) - q_i (x_i - r_i)^3 per DOF (q = 0: harmonic).
class DofPotential : public ForceModel {
 public:
  DofPotential(Eigen::VectorXd k, Eigen::VectorXd rest, Eigen::VectorXd q = {})
      : k_(std::move(k)), rest_(std::move(rest)),
        q_(q.size() ? std::move(q) : Eigen::VectorXd::Zero(k_.size())) {}
  const char* name() const override { return "dof_potential"; }
  double addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                  Eigen::VectorXd& f) const override {
    const Eigen::ArrayXd u = (x - rest_).array();
    f.array() -= k_.array() * u + q_.array() * u.cube();
    return energy(x);
  }
  double energy(const Eigen::VectorXd& x) const override {
    const Eigen::ArrayXd u = (x - rest_).array();
    return (0.5 * k_.array() * u.square() + 0.25 * q_.array() * u.square().square()).sum();
  }
  bool hasStiffness() const override { return true; }
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K) const override {
    const Eigen::ArrayXd u = (x - rest_).array();
    const Eigen::ArrayXd d = -(k_.array() + 3.0 * q_.array() * u.square());
    for (int node = 0; node < pattern.numNodes(); ++node)
      pattern.addNodeBlock(K, node, node,
                           Eigen::Matrix3d(scale * d.segment<3>(3 * node).matrix().asDiagonal()));
  }

 private:
  Eigen::VectorXd k_, rest_, q_;
};

inline Mesh unitTet() {
  Mesh m;
  m.rest.resize(3, 4);
  m.rest << 0, 1, 0, 0,
            0, 0, 1, 0,
            0, 0, 0, 1;
  m.tets = {{0, 1, 2, 3}};
  m.fillDefaults();
  return m;
}

inline Eigen::VectorXd restVector(const System& s) {
  return Eigen::Map<const Eigen::VectorXd>(s.mesh.rest.data(), s.numDofs());
}

// 12 independent oscillators m u'' + c u' + k u = 0 (u = x - rest), u(0) = u0, u'(0) = v0.
struct Oscillators {
  double m = 1.0, c = 0.0;
  Eigen::VectorXd k, q, u0, v0;

  System build() const {
    System s(unitTet(), {Material::isotropic(1e3, 0.3, 1000.0)});
    s.mass.setConstant(m);
    s.damping.setConstant(c);
    s.models.push_back(std::make_unique<DofPotential>(k, restVector(s), q));
    s.state.x = restVector(s) + u0;
    s.state.v = v0;
    return s;
  }
  // Closed form, underdamped: u = e^{-beta t} (A cos wd t + B sin wd t).
  double exact(int dof, double t) const {
    const double beta = c / (2.0 * m), wd = std::sqrt(k[dof] / m - beta * beta);
    const double A = u0[dof], B = (v0[dof] + beta * u0[dof]) / wd;
    return std::exp(-beta * t) * (A * std::cos(wd * t) + B * std::sin(wd * t));
  }
  double maxError(const System& s) const {
    double e = 0.0;
    const Eigen::VectorXd u = s.state.x - restVector(s);
    for (int dof = 0; dof < u.size(); ++dof)
      e = std::max(e, std::abs(u[dof] - exact(dof, s.state.t)));
    return e;
  }
};

inline Oscillators harmonic(double c) {
  Oscillators o;
  o.c = c;
  o.k = Eigen::VectorXd::Constant(12, 4.0 * kPi * kPi);  // period 1 s
  o.u0 = Eigen::VectorXd::LinSpaced(12, -0.1, 0.12);
  o.v0 = Eigen::VectorXd::LinSpaced(12, 0.3, -0.2);
  return o;
}

// Least-squares slope of log(y) against log(x): a measured order of accuracy.
inline double logSlope(const std::vector<double>& x, const std::vector<double>& y) {
  Eigen::MatrixXd A(x.size(), 2);
  Eigen::VectorXd b(x.size());
  for (size_t i = 0; i < x.size(); ++i) {
    A(i, 0) = std::log(x[i]);
    A(i, 1) = 1.0;
    b[i] = std::log(y[i]);
  }
  return A.colPivHouseholderQr().solve(b)[0];
}

}  // namespace oscillators
}  // namespace tt
