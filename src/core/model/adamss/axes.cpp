#include "tissue_trainer/core/model/adamss/axes.h"

#include <Eigen/Geometry>
#include <Eigen/LU>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tt {
namespace adamss {
namespace {

// Unit axis directions, or false for a zero or non-finite column.
bool unitAxes(const Eigen::Matrix3d& axes, Eigen::Matrix3d& unit) {
  for (int l = 0; l < kAxes; ++l) {
    const double n = axes.col(l).norm();
    if (!(n > 0.0) || !std::isfinite(n)) return false;
    unit.col(l) = axes.col(l) / n;
  }
  return true;
}

// The rest lengths |x_2l - x_2l+1| of the points of C (Eq. 2.30).
template <int N>
Eigen::Vector3d restLengths(const NodeMatrix<N>& Xe, const PointCoefficients<N>& C) {
  const Eigen::Matrix3d zeta = axisVectors(intersectionPoints<N>(Xe, C));
  return zeta.colwise().norm().transpose();
}

// The point where the ray x(t) = xb + t w (t > 0) crosses the bilinear patch of the face
// (a, b, c, d) (Eq. 2.7 with N_1..N_4 at a..d), by Newton's method from the face centre.
// Returns false when Newton does not converge or the solution is outside the face or behind
// the barycentre.
bool rayPatch(const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& c,
              const Eigen::Vector3d& d, const Eigen::Vector3d& xb, const Eigen::Vector3d& w,
              double size, double& xi, double& eta, double& t) {
  const auto patch = [&](double u, double v) -> Eigen::Vector3d {
    return (1 - u) * (1 - v) * a + u * (1 - v) * b + u * v * c + (1 - u) * v * d;
  };
  xi = 0.5;
  eta = 0.5;
  t = (0.25 * (a + b + c + d) - xb).dot(w);
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Eigen::Vector3d r = patch(xi, eta) - xb - t * w;
    if (r.norm() <= 1e-15 * size) break;
    Eigen::Matrix3d J;
    J.col(0) = (1 - eta) * (b - a) + eta * (c - d);
    J.col(1) = (1 - xi) * (d - a) + xi * (c - b);
    J.col(2) = -w;
    // A ray (nearly) parallel to the face, or a degenerate face: no crossing here.
    if (!(std::abs(J.determinant()) > 1e-12 * size * size)) return false;
    const Eigen::Vector3d step = J.inverse() * r;
    xi -= step[0];
    eta -= step[1];
    t -= step[2];
    if (!std::isfinite(xi) || !std::isfinite(eta) || !std::isfinite(t)) return false;
    if (std::abs(step[0]) + std::abs(step[1]) < 1e-14 && std::abs(step[2]) < 1e-14 * size) break;
  }
  if ((patch(xi, eta) - xb - t * w).norm() > 1e-12 * size) return false;
  const double tol = 1e-10;
  return t > 0.0 && xi >= -tol && xi <= 1 + tol && eta >= -tol && eta <= 1 + tol;
}

}  // namespace

bool tetAxisRest(const NodeMatrix<Tet4::kNodes>& Xe, const Eigen::Matrix3d& axes,
                 AxisRest<Tet4>& out) {
  if (!unitAxes(axes, out.axes0)) return false;
  Eigen::Matrix3d Dm;
  Dm << Xe.col(1) - Xe.col(0), Xe.col(2) - Xe.col(0), Xe.col(3) - Xe.col(0);
  const double det = Dm.determinant();
  const double scale = (Dm.colwise().norm()).prod();
  if (!(std::abs(det) > 1e-12 * scale) || !std::isfinite(det)) return false;
  // Rows of grad: the gradients of the barycentric coordinates lambda_0..lambda_3.
  const Eigen::Matrix3d inv = Dm.inverse();
  Eigen::Matrix<double, 4, 3> grad;
  grad.row(0) = -inv.colwise().sum();
  grad.bottomRows<3>() = inv;
  out.C.setZero();
  for (int l = 0; l < kAxes; ++l) {
    for (int side = 0; side < 2; ++side) {
      const int j = 2 * l + side;
      const Eigen::Vector3d w = side == 0 ? out.axes0.col(l) : Eigen::Vector3d(-out.axes0.col(l));
      // d lambda / d t along the ray; the coordinates sum to 1, so the rates sum to 0 and one
      // is negative. The ray leaves where the fastest-falling coordinate reaches 0.
      const Eigen::Vector4d rate = grad * w;
      int exit = 0;
      for (int i = 1; i < 4; ++i)
        if (rate[i] < rate[exit]) exit = i;
      if (!(rate[exit] < 0.0)) return false;
      const double t = -0.25 / rate[exit];
      Eigen::Vector4d lambda = (Eigen::Vector4d::Constant(0.25) + t * rate).cwiseMax(0.0);
      lambda[exit] = 0.0;
      lambda /= lambda.sum();
      out.C.col(j) = lambda;
      out.face[j] = exit;  // Tet4::faces[k] is the face opposite node k
    }
  }
  out.length0 = restLengths<Tet4::kNodes>(Xe, out.C);
  return true;
}

bool hexAxisRest(const NodeMatrix<Hex8::kNodes>& Xe, const Eigen::Matrix3d& axes,
                 AxisRest<Hex8>& out) {
  if (!unitAxes(axes, out.axes0)) return false;
  if (!Xe.allFinite()) return false;
  const Eigen::Vector3d xb = Xe.rowwise().mean();  // Eq. 2.8
  const double size = (Xe.colwise() - xb).colwise().norm().maxCoeff();
  if (!(size > 0.0)) return false;
  out.C.setZero();
  for (int l = 0; l < kAxes; ++l) {
    for (int side = 0; side < 2; ++side) {
      const int j = 2 * l + side;
      const Eigen::Vector3d w = side == 0 ? out.axes0.col(l) : Eigen::Vector3d(-out.axes0.col(l));
      int best = -1;
      double bestT = std::numeric_limits<double>::infinity(), bestXi = 0.0, bestEta = 0.0;
      for (int f = 0; f < Hex8::kFaces; ++f) {
        const int* n = Hex8::faces[f];
        double xi, eta, t;
        if (!rayPatch(Xe.col(n[0]), Xe.col(n[1]), Xe.col(n[2]), Xe.col(n[3]), xb, w, size, xi,
                      eta, t))
          continue;
        if (t < bestT) {
          best = f;
          bestT = t;
          bestXi = std::clamp(xi, 0.0, 1.0);
          bestEta = std::clamp(eta, 0.0, 1.0);
        }
      }
      if (best < 0) return false;
      const int* n = Hex8::faces[best];
      out.C(n[0], j) = (1 - bestXi) * (1 - bestEta);
      out.C(n[1], j) = bestXi * (1 - bestEta);
      out.C(n[2], j) = bestXi * bestEta;
      out.C(n[3], j) = (1 - bestXi) * bestEta;
      out.face[j] = best;
    }
  }
  out.length0 = restLengths<Hex8::kNodes>(Xe, out.C);
  return true;
}

namespace {

Eigen::Vector3d faceVectorArea(const NodeMatrix<Tet4::kNodes>& xe, int face) {
  const int* f = Tet4::faces[face];
  return 0.5 * (xe.col(f[1]) - xe.col(f[0])).cross(xe.col(f[2]) - xe.col(f[0]));
}

Eigen::Vector3d faceVectorArea(const NodeMatrix<Hex8::kNodes>& xe, int face) {
  const int* f = Hex8::faces[face];
  return 0.5 * (xe.col(f[2]) - xe.col(f[0])).cross(xe.col(f[3]) - xe.col(f[1]));
}

template <class Element>
Eigen::Vector3d meanProjectedAreas(const NodeMatrix<Element::kNodes>& xe,
                                   const AxisRest<Element>& rest) {
  Eigen::Vector3d area;
  for (int l = 0; l < kAxes; ++l)
    area[l] = 0.5 * (std::abs(faceVectorArea(xe, rest.face[2 * l]).dot(rest.axes0.col(l))) +
                     std::abs(faceVectorArea(xe, rest.face[2 * l + 1]).dot(rest.axes0.col(l))));
  return area;
}

}  // namespace

Eigen::Vector3d projectedFaceAreas(const NodeMatrix<Tet4::kNodes>& xe, const AxisRest<Tet4>& rest) {
  return meanProjectedAreas<Tet4>(xe, rest);
}

Eigen::Vector3d projectedFaceAreas(const NodeMatrix<Hex8::kNodes>& xe, const AxisRest<Hex8>& rest) {
  return meanProjectedAreas<Hex8>(xe, rest);
}

AxisMesh buildAxes(const Mesh& mesh) {
  AxisMesh axes;
  axes.tets = mesh.tets;
  axes.hexes = mesh.hexes;
  axes.tetRest.resize(mesh.tets.size());
  axes.hexRest.resize(mesh.hexes.size());
  for (std::size_t e = 0; e < mesh.tets.size(); ++e)
    if (!tetAxisRest(gatherNodes<Tet4::kNodes>(mesh.rest, mesh.tets[e]), mesh.fibreFrame.at(e),
                     axes.tetRest[e]))
      throw std::invalid_argument("adamss axes: tet " + std::to_string(e) +
                                  ": an axis ray meets no face (flat element or zero axis)");
  for (std::size_t e = 0; e < mesh.hexes.size(); ++e)
    if (!hexAxisRest(gatherNodes<Hex8::kNodes>(mesh.rest, mesh.hexes[e]),
                     mesh.hexFibreFrame.at(e), axes.hexRest[e]))
      throw std::invalid_argument("adamss axes: hex " + std::to_string(e) +
                                  ": an axis ray meets no face (flat or folded element, or "
                                  "zero axis)");
  return axes;
}

}  // namespace adamss
}  // namespace tt
