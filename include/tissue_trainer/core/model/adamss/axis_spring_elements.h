#pragma once
// The element loops the Adamss spring models share ("Adamss: Advanced Anisotropic Mass-Spring
// System", Sec. 2.4.2.1): a spring model computes, per element, the forces g_l at the points
// q_2l from the current axes zeta (columns; the force at q_2l+1 is -g_l, Eq. 2.34), and these
// loops gather the axes from the nodes and carry the forces back (Eq. 2.29), on tets and hexes.
// With an energy E(zeta) the nodal stiffness follows from its 9 x 9 Hessian in zeta.
#include <Eigen/Core>
#include <vector>

#include "tissue_trainer/core/model/adamss/axes.h"
#include "tissue_trainer/core/model/tet_loops.h"
#include "tissue_trainer/core/solve/sparse_pattern.h"

namespace tt {
namespace adamss {

using Matrix9d = Eigen::Matrix<double, 9, 9>;

class AxisSpringElements {
 public:
  // Throws std::invalid_argument naming the element ("tet 4") whose axes cannot be built.
  explicit AxisSpringElements(const Mesh& mesh);

  int tetCount() const { return static_cast<int>(tets_.size()); }
  int hexCount() const { return static_cast<int>(hexes_.size()); }

  // pointForces(zeta, rest, energy&) -> Matrix3d, column l the force at q_2l. Returns the
  // energy summed over the elements.
  template <class PointForces>
  double addForces(const Eigen::VectorXd& x, Eigen::VectorXd& f,
                   const PointForces& pointForces) const {
    return addForcesOf<4>(tets_, tetRest_, x, f, pointForces) +
           addForcesOf<8>(hexes_, hexRest_, x, f, pointForces);
  }

  // The same for forces that depend on the axes' rates too: pointForces(zeta, zetaDot, rest)
  // -> Matrix3d (no energy).
  template <class PointForces>
  void addRateForces(const Eigen::VectorXd& x, const Eigen::VectorXd& v, Eigen::VectorXd& f,
                     const PointForces& pointForces) const {
    addRateForcesOf<4>(tets_, tetRest_, x, v, f, pointForces);
    addRateForcesOf<8>(hexes_, hexRest_, x, v, f, pointForces);
  }

  // energyOf(zeta, rest) -> double.
  template <class EnergyOf>
  double energy(const Eigen::VectorXd& x, const EnergyOf& energyOf) const {
    return energyOfSet<4>(tets_, tetRest_, x, energyOf) + energyOfSet<8>(hexes_, hexRest_, x, energyOf);
  }

  // hessianOf(zeta, rest) -> Matrix9d, d2E/dzeta2 (row 3 l + i: component i of axis l).
  template <class HessianOf>
  void addStiffness(const Eigen::VectorXd& x, double scale, const SparsePattern& pattern,
                    SparseMatrix& K, const HessianOf& hessianOf) const {
    addElementStiffness(
        pattern, K, scale, tetCount(),
        [&](int e) { return nodalStiffness<4>(x, tets_[e], tetRest_[e], hessianOf); }, hexes_,
        [&](int e) { return nodalStiffness<8>(x, hexes_[e], hexRest_[e], hessianOf); });
  }

  template <class HessianOf>
  void addStiffnessTimes(const Eigen::VectorXd& x, const Eigen::VectorXd& d, double scale,
                         Eigen::VectorXd& out, const HessianOf& hessianOf) const {
    productOf<4>(tets_, tetRest_, x, d, scale, out, hessianOf);
    productOf<8>(hexes_, hexRest_, x, d, scale, out, hessianOf);
  }

 private:
  template <int N>
  static Eigen::Matrix3d axesOf(const Eigen::VectorXd& x, const std::array<int, N>& nodes,
                                const AxisSpringRest<N>& r) {
    return gatherNodes<N>(x, nodes) * r.D;  // the columns of D sum to 0: no need to centre
  }

  template <int N, class PointForces>
  static double addForcesOf(const std::vector<std::array<int, N>>& elements,
                            const std::vector<AxisSpringRest<N>>& rest, const Eigen::VectorXd& x,
                            Eigen::VectorXd& f, const PointForces& pointForces) {
    return accumulateElementForces<N>(elements, f, [&](int e, NodeMatrix<N>& fe) {
      double energy = 0.0;
      fe.noalias() = pointForces(axesOf<N>(x, elements[e], rest[e]), rest[e], energy) *
                     rest[e].D.transpose();
      return energy;
    });
  }

  template <int N, class PointForces>
  static void addRateForcesOf(const std::vector<std::array<int, N>>& elements,
                              const std::vector<AxisSpringRest<N>>& rest, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& v, Eigen::VectorXd& f,
                              const PointForces& pointForces) {
    accumulateElementForces<N>(elements, f, [&](int e, NodeMatrix<N>& fe) {
      fe.noalias() = pointForces(axesOf<N>(x, elements[e], rest[e]),
                                 axesOf<N>(v, elements[e], rest[e]), rest[e]) *
                     rest[e].D.transpose();
      return 0.0;
    });
  }

  template <int N, class EnergyOf>
  static double energyOfSet(const std::vector<std::array<int, N>>& elements,
                            const std::vector<AxisSpringRest<N>>& rest, const Eigen::VectorXd& x,
                            const EnergyOf& energyOf) {
    return sumOverTets(static_cast<int>(elements.size()), [&](int e) {
      return energyOf(axesOf<N>(x, elements[e], rest[e]), rest[e]);
    });
  }

  // -D (x) H (x) D^T: row 3 p + i, column 3 q + j.
  template <int N, class HessianOf>
  static Eigen::Matrix<double, 3 * N, 3 * N> nodalStiffness(const Eigen::VectorXd& x,
                                                            const std::array<int, N>& nodes,
                                                            const AxisSpringRest<N>& r,
                                                            const HessianOf& hessianOf) {
    const Matrix9d H = hessianOf(axesOf<N>(x, nodes, r), r);
    Eigen::Matrix<double, 3 * N, 9> DH = Eigen::Matrix<double, 3 * N, 9>::Zero();
    for (int p = 0; p < N; ++p)
      for (int l = 0; l < kAxes; ++l) DH.template block<3, 9>(3 * p, 0) +=
          r.D(p, l) * H.template block<3, 9>(3 * l, 0);
    Eigen::Matrix<double, 3 * N, 3 * N> K;
    for (int q = 0; q < N; ++q) {
      Eigen::Matrix<double, 3 * N, 3> column = Eigen::Matrix<double, 3 * N, 3>::Zero();
      for (int m = 0; m < kAxes; ++m) column += r.D(q, m) * DH.template middleCols<3>(3 * m);
      K.template middleCols<3>(3 * q) = -column;
    }
    return K;
  }

  template <int N, class HessianOf>
  static void productOf(const std::vector<std::array<int, N>>& elements,
                        const std::vector<AxisSpringRest<N>>& rest, const Eigen::VectorXd& x,
                        const Eigen::VectorXd& d, double scale, Eigen::VectorXd& out,
                        const HessianOf& hessianOf) {
    accumulateElementForces<N>(elements, out, [&](int e, NodeMatrix<N>& fe) {
      const Matrix9d H = hessianOf(axesOf<N>(x, elements[e], rest[e]), rest[e]);
      Eigen::Matrix3d dZeta = axesOf<N>(d, elements[e], rest[e]);
      Eigen::Matrix3d dForce;
      Eigen::Map<Eigen::Matrix<double, 9, 1>>(dForce.data()) =
          -scale * H * Eigen::Map<const Eigen::Matrix<double, 9, 1>>(dZeta.data());
      fe.noalias() = dForce * rest[e].D.transpose();
      return 0.0;
    });
  }

  std::vector<Tet> tets_;
  std::vector<AxisSpringRest<4>> tetRest_;
  std::vector<Hex> hexes_;
  std::vector<AxisSpringRest<8>> hexRest_;
};

}  // namespace adamss
}  // namespace tt
