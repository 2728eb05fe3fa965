#include "tissue_trainer/core/model/adamss/active_tension.h"

#include <Eigen/Dense>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>
#include <type_traits>

namespace tt {
namespace adamss {
namespace {

Eigen::Matrix3d skew(const Eigen::Vector3d& a) {
  Eigen::Matrix3d s;
  s << 0.0, -a.z(), a.y(), a.z(), 0.0, -a.x(), -a.y(), a.x(), 0.0;
  return s;
}

// The element volume V = sum_g w_g det(J_g), J_g = xe G_g^T (G_g: dN/dxi at point g, column p
// for node p), exact for linear tets (one point) and trilinear hexes (2x2x2 Gauss).
template <int N, int P>
struct VolumeRule {
  std::array<Eigen::Matrix<double, 3, N>, P> G;
  double weight = 0.0;
};

const VolumeRule<4, 1>& tetRule() {
  static const VolumeRule<4, 1> rule = [] {
    VolumeRule<4, 1> r;
    r.G[0] << -1, 1, 0, 0, -1, 0, 1, 0, -1, 0, 0, 1;
    r.weight = 1.0 / 6.0;
    return r;
  }();
  return rule;
}

const VolumeRule<8, 8>& hexRule() {
  static const VolumeRule<8, 8> rule = [] {
    VolumeRule<8, 8> r;
    for (int g = 0; g < 8; ++g) r.G[g] = Hex8::referenceGradients(Hex8::gaussPoint(g));
    r.weight = 1.0;
    return r;
  }();
  return rule;
}

template <int N>
const auto& ruleFor() {
  if constexpr (N == 4) return tetRule();
  else return hexRule();
}

// V and dV/dx_p (column p): d det J = cof(J) : dJ, and the columns of cof(J) are
// j_1 x j_2, j_2 x j_0, j_0 x j_1.
template <int N>
double volumeGradient(const NodeMatrix<N>& xe, NodeMatrix<N>& grad) {
  const auto& rule = ruleFor<N>();
  double V = 0.0;
  grad.setZero();
  for (const auto& G : rule.G) {
    const Eigen::Matrix3d J = xe * G.transpose();
    Eigen::Matrix3d cof;
    cof << J.col(1).cross(J.col(2)), J.col(2).cross(J.col(0)), J.col(0).cross(J.col(1));
    V += rule.weight * J.col(0).dot(cof.col(0));
    grad.noalias() += rule.weight * cof * G;
  }
  return V;
}

// d2V/dx_p dx_q = -sum_g w_g skew(J_g (G_g,p x G_g,q)) (from d2 det / dj_a dj_b =
// -eps_abc skew(j_c)).
template <int N>
Eigen::Matrix<double, 3 * N, 3 * N> volumeHessian(const NodeMatrix<N>& xe) {
  const auto& rule = ruleFor<N>();
  Eigen::Matrix<double, 3 * N, 3 * N> H = Eigen::Matrix<double, 3 * N, 3 * N>::Zero();
  for (const auto& G : rule.G) {
    const Eigen::Matrix3d J = xe * G.transpose();
    for (int p = 0; p < N; ++p)
      for (int q = 0; q < N; ++q)
        if (p != q)
          H.template block<3, 3>(3 * p, 3 * q) -=
              rule.weight * skew(J * G.col(p).cross(G.col(q)));
  }
  return H;
}

}  // namespace

ActiveTensionModel::ActiveTensionModel(const Mesh& mesh, ActiveForm form, ActiveMode mode,
                                       TimeCurve curve)
    : form_(form), mode_(mode), curve_(std::move(curve)), tension_(curve_.value(0.0)) {
  if (form_ == ActiveForm::kAnisotropic) {
    axes_ = std::make_unique<AxisSpringElements>(mesh);
    return;
  }
  tets_ = mesh.tets;
  hexes_ = mesh.hexes;
  NodeMatrix<4> tetGrad;
  for (std::size_t e = 0; e < tets_.size(); ++e) {
    tetVolume0_.push_back(volumeGradient<4>(gatherNodes<4>(mesh.rest, tets_[e]), tetGrad));
    if (!(tetVolume0_.back() > 0.0))
      throw std::invalid_argument("tet " + std::to_string(e) + " has no positive rest volume");
  }
  NodeMatrix<8> hexGrad;
  for (std::size_t e = 0; e < hexes_.size(); ++e) {
    hexVolume0_.push_back(volumeGradient<8>(gatherNodes<8>(mesh.rest, hexes_[e]), hexGrad));
    if (!(hexVolume0_.back() > 0.0))
      throw std::invalid_argument("hex " + std::to_string(e) + " has no positive rest volume");
  }
}

// Anisotropic, g = -c u at q_0 with c = t k |det Z| / |zeta_0| (tension, k = V0 / |det Z^0|) or
// c = t V0 / |zeta_0^0| (force).
template <int N>
Eigen::Matrix3d ActiveTensionModel::fibreForce(const Eigen::Matrix3d& zeta,
                                               const AxisSpringRest<N>& r) const {
  const double length = zeta.col(0).norm();
  const double c = mode_ == ActiveMode::kTension
                       ? tension_ * r.volume * std::abs(zeta.determinant() / r.axisVolume) / length
                       : tension_ * r.volume / r.length0[0];
  Eigen::Matrix3d g = Eigen::Matrix3d::Zero();
  g.col(0) = -(c / length) * zeta.col(0);
  return g;
}

// -dg/dzeta (row block 0: g at q_0; column block m: axis m).
//   force:   -dg/dzeta_0 = c (I - u u^T) / |zeta_0|.
//   tension: g = -t k |det Z| w with w = zeta_0 / |zeta_0|^2, dw/dzeta_0 = (I - 2 u u^T) / |zeta_0|^2
//            and d|det Z|/dzeta_m = sign(det Z) cof(Z)_m.
template <int N>
Matrix9d ActiveTensionModel::fibreForceJacobian(const Eigen::Matrix3d& zeta,
                                                const AxisSpringRest<N>& r) const {
  Matrix9d H = Matrix9d::Zero();
  const double length = zeta.col(0).norm();
  const Eigen::Vector3d u = zeta.col(0) / length;
  const Eigen::Matrix3d across = Eigen::Matrix3d::Identity() - u * u.transpose();
  if (mode_ == ActiveMode::kForce) {
    const double c = tension_ * r.volume / r.length0[0];
    H.block<3, 3>(0, 0) = (c / length) * across;
    return H;
  }
  const double k = tension_ * r.volume / std::abs(r.axisVolume);
  const double det = zeta.determinant();
  const double sign = det < 0.0 ? -1.0 : 1.0;
  Eigen::Matrix3d cof;
  cof << zeta.col(1).cross(zeta.col(2)), zeta.col(2).cross(zeta.col(0)),
      zeta.col(0).cross(zeta.col(1));
  const Eigen::Vector3d w = u / length;
  for (int m = 0; m < kAxes; ++m) H.block<3, 3>(0, 3 * m) = k * sign * w * cof.col(m).transpose();
  H.block<3, 3>(0, 0) += k * std::abs(det) / (length * length) * (across - u * u.transpose());
  return H;
}

// The isotropic potential t phi(V): phi = V (tension) or 3 V0^(2/3) V^(1/3) (force). A flat or
// inverted element (V <= 0) takes the tension form.
void ActiveTensionModel::volumePotential(double V, double V0, double& phi, double& dphi,
                                         double& ddphi) const {
  if (mode_ == ActiveMode::kTension || V <= 0.0) {
    phi = V;
    dphi = 1.0;
    ddphi = 0.0;
    return;
  }
  const double ratio = std::cbrt(V0 * V0 / (V * V));  // (V0 / V)^(2/3)
  phi = 3.0 * ratio * V;
  dphi = ratio;
  ddphi = -2.0 / 3.0 * ratio / V;
}

template <int N>
void ActiveTensionModel::addVolumeForces(const std::vector<std::array<int, N>>& elements,
                                           const std::vector<double>& restVolume,
                                           const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
  accumulateElementForces<N>(elements, f, [&](int e, NodeMatrix<N>& fe) {
    const double V = volumeGradient<N>(gatherNodes<N>(x, elements[e]), fe);
    double phi, dphi, ddphi;
    volumePotential(V, restVolume[e], phi, dphi, ddphi);
    fe *= -tension_ * dphi;
    return 0.0;
  });
}

double ActiveTensionModel::addForce(const Eigen::VectorXd& x, const Eigen::VectorXd&,
                                    Eigen::VectorXd& f) const {
  if (tension_ == 0.0) return 0.0;
  if (form_ == ActiveForm::kIsotropic) {
    addVolumeForces<4>(tets_, tetVolume0_, x, f);
    addVolumeForces<8>(hexes_, hexVolume0_, x, f);
  } else
    axes_->addForces(x, f, [&](const Eigen::Matrix3d& zeta, const auto& r, double&) {
      return fibreForce(zeta, r);
    });
  return 0.0;
}

double ActiveTensionModel::potential(const Eigen::VectorXd& x) const {
  if (anisotropicTension() || tension_ == 0.0) return 0.0;
  if (form_ == ActiveForm::kAnisotropic)
    return axes_->energy(x, [&](const Eigen::Matrix3d& zeta, const auto& r) {
      return tension_ * r.volume / r.length0[0] * zeta.col(0).norm();
    });
  auto volumeEnergy = [&](const auto& elements, const std::vector<double>& restVolume, int e,
                          auto nodes) {
    constexpr int N = decltype(nodes)::value;
    NodeMatrix<N> grad;
    double phi, dphi, ddphi;
    volumePotential(volumeGradient<N>(gatherNodes<N>(x, elements[e]), grad), restVolume[e], phi,
                    dphi, ddphi);
    return tension_ * phi;
  };
  return sumOverTets(static_cast<int>(tets_.size()),
                     [&](int e) {
                       return volumeEnergy(tets_, tetVolume0_, e, std::integral_constant<int, 4>());
                     }) +
         sumOverTets(static_cast<int>(hexes_.size()), [&](int e) {
           return volumeEnergy(hexes_, hexVolume0_, e, std::integral_constant<int, 8>());
         });
}

void ActiveTensionModel::addStiffness(const Eigen::VectorXd& x, double scale,
                                      const SparsePattern& pattern, SparseMatrix& K) const {
  if (tension_ == 0.0) return;
  if (form_ == ActiveForm::kAnisotropic) {
    axes_->addStiffness(x, scale, pattern, K, [&](const Eigen::Matrix3d& zeta, const auto& r) {
      return fibreForceJacobian(zeta, r);
    });
    return;
  }
  addElementStiffness(
      pattern, K, scale, static_cast<int>(tets_.size()),
      [&](int e) { return volumeStiffness<4>(gatherNodes<4>(x, tets_[e]), tetVolume0_[e]); },
      hexes_,
      [&](int e) { return volumeStiffness<8>(gatherNodes<8>(x, hexes_[e]), hexVolume0_[e]); });
}

void ActiveTensionModel::addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                           double scale, Eigen::VectorXd& out) const {
  if (tension_ == 0.0) return;
  if (form_ == ActiveForm::kAnisotropic) {
    axes_->addStiffnessTimes(x, d, scale, out, [&](const Eigen::Matrix3d& zeta, const auto& r) {
      return fibreForceJacobian(zeta, r);
    });
    return;
  }
  addVolumeStiffnessTimes<4>(tets_, tetVolume0_, x, d, scale, out);
  addVolumeStiffnessTimes<8>(hexes_, hexVolume0_, x, d, scale, out);
}

// K_e = -t (phi' d2V + phi'' dV dV^T).
template <int N>
Eigen::Matrix<double, 3 * N, 3 * N> ActiveTensionModel::volumeStiffness(const NodeMatrix<N>& xe,
                                                                         double V0) const {
  NodeMatrix<N> grad;
  const double V = volumeGradient<N>(xe, grad);
  double phi, dphi, ddphi;
  volumePotential(V, V0, phi, dphi, ddphi);
  const Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>> g(grad.data());
  Eigen::Matrix<double, 3 * N, 3 * N> Ke = volumeHessian<N>(xe);
  Ke *= -tension_ * dphi;
  if (ddphi != 0.0) Ke.noalias() -= tension_ * ddphi * g * g.transpose();
  return Ke;
}

template <int N>
void ActiveTensionModel::addVolumeStiffnessTimes(const std::vector<std::array<int, N>>& elements,
                                                 const std::vector<double>& restVolume,
                                                 const Eigen::VectorXd& x, const Eigen::VectorXd& d,
                                                 double scale, Eigen::VectorXd& out) const {
  accumulateElementForces<N>(elements, out, [&](int e, NodeMatrix<N>& fe) {
    const NodeMatrix<N> de = gatherNodes<N>(d, elements[e]);
    Eigen::Map<Eigen::Matrix<double, 3 * N, 1>>(fe.data()).noalias() =
        scale * volumeStiffness<N>(gatherNodes<N>(x, elements[e]), restVolume[e]) *
        Eigen::Map<const Eigen::Matrix<double, 3 * N, 1>>(de.data());
    return 0.0;
  });
}

}  // namespace adamss
}  // namespace tt
