#pragma once
// Small meshes, random deformations and finite-difference helpers for the force-model tests.
#include <Eigen/Geometry>
#include <functional>
#include <random>

#include "tissue_trainer/core/mesh/mesh.h"
#include "tissue_trainer/core/model/force_model.h"
#include "tissue_trainer/core/model/material.h"
#include "tissue_trainer/core/solve/sparse_pattern.h"
#include "random_draws.h"

namespace tt {
namespace testutil {

inline Eigen::Vector3d randomUnit(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  return drawVector(n, rng).normalized();
}

inline Eigen::Matrix3d frameFrom(const Eigen::Vector3d& a0) {
  Eigen::Matrix3d R;
  R.col(0) = a0.normalized();
  R.col(1) = R.col(0).unitOrthogonal();
  R.col(2) = R.col(0).cross(R.col(1));
  return R;
}

// One well-shaped, positively oriented tet with edge length about `size`, random fibre.
inline Mesh randomTet(std::mt19937& rng, double size = 0.01) {
  std::uniform_real_distribution<double> u(-0.25, 0.25);
  Mesh m;
  m.rest.resize(3, 4);
  m.rest << 0, 1, 0, 0, 0, 0, 1, 0, 0, 0, 0, 1;
  for (int p = 0; p < 4; ++p)
    for (int i = 0; i < 3; ++i) m.rest(i, p) = size * (m.rest(i, p) + u(rng));
  m.tets = {{0, 1, 2, 3}};
  m.fibreFrame = {frameFrom(randomUnit(rng))};
  m.material = {0};
  m.fillDefaults();
  return m;
}

// A box of cells with spacing h, each cell split into 6 tets around its main diagonal,
// nodes jittered by `jitter` * h, a random fibre per tet.
inline Mesh boxMesh(int cx, int cy, int cz, double h, std::mt19937& rng, double jitter = 0.1) {
  Mesh m;
  auto id = [&](int i, int j, int k) { return i + (cx + 1) * (j + (cy + 1) * k); };
  m.rest.resize(3, (cx + 1) * (cy + 1) * (cz + 1));
  std::uniform_real_distribution<double> u(-jitter, jitter);
  for (int k = 0; k <= cz; ++k)
    for (int j = 0; j <= cy; ++j)
      for (int i = 0; i <= cx; ++i)
        m.rest.col(id(i, j, k)) = h * (Eigen::Vector3d(i, j, k) + drawVector(u, rng));
  // Corners as bits (x, y, z); paths from corner 0 to corner 7 give the 6 tets.
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (int k = 0; k < cz; ++k)
    for (int j = 0; j < cy; ++j)
      for (int i = 0; i < cx; ++i) {
        auto corner = [&](int b) { return id(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1)); };
        for (const auto& p : paths) {
          Tet t = {corner(0), corner(p[0]), corner(p[1]), corner(7)};
          if (tetVolume(m.rest, t) < 0) std::swap(t[1], t[2]);
          m.tets.push_back(t);
        }
      }
  for (size_t e = 0; e < m.tets.size(); ++e) {
    m.fibreFrame.push_back(frameFrom(randomUnit(rng)));
    m.material.push_back(static_cast<int>(e % 2));
  }
  m.fillDefaults();
  return m;
}

// Muscle-like transversely isotropic material (E_L > E_T) and a second, softer one.
inline std::vector<Material> testMaterials() {
  return {Material::transverselyIsotropic(3e4, 0.3, 1.2e5, 0.35, 1060.0),
          Material::transverselyIsotropic(1e4, 0.45, 2e4, 0.4, 1000.0)};
}

inline Eigen::VectorXd restVector(const Mesh& m) {
  return Eigen::Map<const Eigen::VectorXd>(m.rest.data(), 3 * m.numNodes());
}

// rest + amplitude * size * N(0,1) per coordinate.
inline Eigen::VectorXd perturbed(const Mesh& m, double amplitude, std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::VectorXd x = restVector(m);
  for (int i = 0; i < x.size(); ++i) x[i] += amplitude * n(rng);
  return x;
}

inline Eigen::VectorXd force(const ForceModel& model, const Eigen::VectorXd& x) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  model.addForce(x, Eigen::VectorXd::Zero(x.size()), f);
  return f;
}

inline double relDiff(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(b.lpNorm<Eigen::Infinity>(), 1e-300);
}

// Central-difference gradient of the model energy.
inline Eigen::VectorXd fdGradient(const ForceModel& model, const Eigen::VectorXd& x, double h) {
  Eigen::VectorXd g(x.size()), xp = x;
  for (int i = 0; i < x.size(); ++i) {
    xp[i] = x[i] + h;
    const double ep = model.energy(xp);
    xp[i] = x[i] - h;
    const double em = model.energy(xp);
    xp[i] = x[i];
    g[i] = (ep - em) / (2 * h);
  }
  return g;
}

inline Eigen::MatrixXd denseStiffness(const ForceModel& model, const Mesh& m,
                                      const Eigen::VectorXd& x) {
  const SparsePattern pattern = meshPattern(m);
  SparseMatrix K = pattern.zeroMatrix();
  model.addStiffness(x, 1.0, pattern, K);
  return Eigen::MatrixXd(K);
}

// Central-difference Jacobian of the force.
inline Eigen::MatrixXd fdForceJacobian(const ForceModel& model, const Eigen::VectorXd& x,
                                       double h) {
  Eigen::MatrixXd J(x.size(), x.size());
  Eigen::VectorXd xp = x;
  for (int i = 0; i < x.size(); ++i) {
    xp[i] = x[i] + h;
    const Eigen::VectorXd fp = force(model, xp);
    xp[i] = x[i] - h;
    const Eigen::VectorXd fm = force(model, xp);
    xp[i] = x[i];
    J.col(i) = (fp - fm) / (2 * h);
  }
  return J;
}

inline double relDiff(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / std::max(b.lpNorm<Eigen::Infinity>(), 1e-300);
}

// x -> R x + t applied node by node.
inline Eigen::VectorXd rigidMotion(const Eigen::VectorXd& x, const Eigen::Matrix3d& R,
                                   const Eigen::Vector3d& t) {
  Eigen::VectorXd y(x.size());
  for (int i = 0; i < x.size() / 3; ++i) y.segment<3>(3 * i) = R * x.segment<3>(3 * i) + t;
  return y;
}

inline Eigen::VectorXd rotateVectors(const Eigen::VectorXd& f, const Eigen::Matrix3d& R) {
  return rigidMotion(f, R, Eigen::Vector3d::Zero());
}

inline Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::uniform_real_distribution<double> u(0.3, 2.5);
  const Eigen::Vector3d axis = randomUnit(rng);  // drawn first, as g++ did (random_draws.h)
  const double angle = u(rng);
  return Eigen::AngleAxisd(angle, axis).toRotationMatrix();
}

}  // namespace testutil
}  // namespace tt
