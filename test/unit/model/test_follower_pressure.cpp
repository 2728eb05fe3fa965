// The follower pressure (model/follower_pressure.h): its exact stiffness against central
// differences of its force, the symmetric part the solvers are given, the closed-surface case
// where the load is -p dV/dx (the enclosed volume of adamss/cavity.h, differentiated
// numerically) and its stiffness symmetric, and the load's size on a flat face.
#include <gtest/gtest.h>

#include <random>

#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/cavity.h"
#include "tissue_trainer/core/model/follower_pressure.h"
#include "tissue_trainer/core/solve/sparse_pattern.h"

namespace tt {
namespace {

// A 3 x 2 x 2-cell hex box (1 cm x 5 mm x 5 mm), its nodes moved randomly by up to 10 % of a
// cell: a deformed state.
struct FollowerBox {
  Mesh mesh = boxGrid(4, 3, 3, Eigen::Vector3d(0.01, 0.005, 0.005), TetSplit::kNone);
  Eigen::VectorXd x;
  FollowerBox() {
    std::mt19937 rng(5);
    std::uniform_real_distribution<double> u(-2.5e-4, 2.5e-4);
    x = Eigen::Map<const Eigen::VectorXd>(mesh.rest.data(), 3 * mesh.numNodes());
    for (int i = 0; i < x.size(); ++i) x[i] += u(rng);
  }
  std::vector<FollowerPressureModel::Face> faces(bool bottomOnly) const {
    std::vector<FollowerPressureModel::Face> out;
    for (const Triangle& t : mesh.surface) {
      const bool bottom = mesh.rest(2, t[0]) == 0.0 && mesh.rest(2, t[1]) == 0.0 &&
                          mesh.rest(2, t[2]) == 0.0;
      if (bottom || !bottomOnly) out.push_back({t[0], t[1], t[2]});
    }
    return out;
  }
};

Eigen::VectorXd followerForce(const FollowerPressureModel& m, const Eigen::VectorXd& x) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  m.addForce(x, Eigen::VectorXd::Zero(x.size()), f);
  return f;
}

Eigen::MatrixXd assembled(const FollowerBox& box, const FollowerPressureModel& m, bool exact) {
  const SparsePattern pattern = meshPattern(box.mesh);
  SparseMatrix K = pattern.zeroMatrix();
  if (exact)
    m.addExactStiffness(box.x, 1.0, pattern, K);
  else
    m.addStiffness(box.x, 1.0, pattern, K);
  return Eigen::MatrixXd(K);
}

TEST(FollowerPressure, ExactStiffnessIsTheForceDerivative) {
  const FollowerBox box;
  const FollowerPressureModel m(box.faces(true), 4.0);
  const Eigen::MatrixXd K = assembled(box, m, true);
  const double h = 1e-7;
  Eigen::MatrixXd fd(K.rows(), K.cols());
  for (int j = 0; j < box.x.size(); ++j) {
    Eigen::VectorXd xp = box.x, xm = box.x;
    xp[j] += h;
    xm[j] -= h;
    fd.col(j) = (followerForce(m, xp) - followerForce(m, xm)) / (2 * h);
  }
  ASSERT_GT(K.norm(), 0.0);
  EXPECT_LT((K - fd).lpNorm<Eigen::Infinity>(), 1e-7 * K.lpNorm<Eigen::Infinity>());
  // The bottom face's edges are free: the exact matrix is not symmetric there.
  EXPECT_GT((K - K.transpose()).lpNorm<Eigen::Infinity>(), 1e-3 * K.lpNorm<Eigen::Infinity>());
}

TEST(FollowerPressure, SolversGetTheSymmetricPartAndItsProduct) {
  const FollowerBox box;
  const FollowerPressureModel m(box.faces(true), 4.0);
  const Eigen::MatrixXd exact = assembled(box, m, true);
  const Eigen::MatrixXd K = assembled(box, m, false);
  EXPECT_LT((K - 0.5 * (exact + exact.transpose())).lpNorm<Eigen::Infinity>(),
            1e-14 * exact.lpNorm<Eigen::Infinity>());
  std::mt19937 rng(6);
  std::normal_distribution<double> n(0.0, 1.0);
  Eigen::VectorXd d(box.x.size());
  for (int i = 0; i < d.size(); ++i) d[i] = n(rng);
  Eigen::VectorXd Kd = Eigen::VectorXd::Zero(d.size());
  m.addStiffnessTimes(box.x, d, 2.0, Kd);
  EXPECT_LT((Kd - 2.0 * K * d).lpNorm<Eigen::Infinity>(), 1e-12 * (K * d).lpNorm<Eigen::Infinity>());
}

// On the closed surface of the box the load is -p dV/dx (V the enclosed volume), so the
// exact stiffness is -p d2V/dx2: symmetric.
TEST(FollowerPressure, OnAClosedSurfaceTheLoadIsMinusPTimesTheVolumeGradient) {
  const FollowerBox box;
  const double p = 3.0;
  const FollowerPressureModel m(box.faces(false), p);
  std::vector<adamss::CavityFacet> facets;
  for (const auto& f : m.faces()) facets.push_back({f[0], f[1], f[2]});
  const auto volume = [&](const Eigen::VectorXd& x) {
    return adamss::enclosedVolume(facets, Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, x.size() / 3));
  };
  EXPECT_NEAR(volume(Eigen::Map<const Eigen::VectorXd>(box.mesh.rest.data(), box.x.size())),
              0.01 * 0.005 * 0.005, 1e-18);
  const Eigen::VectorXd f = followerForce(m, box.x);
  const double h = 1e-7;
  for (int j = 0; j < box.x.size(); ++j) {
    Eigen::VectorXd xp = box.x, xm = box.x;
    xp[j] += h;
    xm[j] -= h;
    const double dV = (volume(xp) - volume(xm)) / (2 * h);
    EXPECT_NEAR(f[j], -p * dV, 1e-9 * p * 2.5e-5) << j;
  }
  const Eigen::MatrixXd K = assembled(box, m, true);
  EXPECT_LT((K - K.transpose()).lpNorm<Eigen::Infinity>(), 1e-12 * K.lpNorm<Eigen::Infinity>());
}

// At rest the bottom face (1 cm x 5 mm, outward normal -z) under p gets p A along +z in all.
TEST(FollowerPressure, FlatFaceAtRestCarriesPressureTimesArea) {
  const FollowerBox box;
  const FollowerPressureModel m(box.faces(true), 4.0);
  const Eigen::VectorXd rest = Eigen::Map<const Eigen::VectorXd>(box.mesh.rest.data(), box.x.size());
  const Eigen::VectorXd f = followerForce(m, rest);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (int n = 0; n < box.mesh.numNodes(); ++n) total += f.segment<3>(3 * n);
  EXPECT_NEAR(total.z(), 4.0 * 0.01 * 0.005, 1e-15);
  EXPECT_NEAR(total.x(), 0.0, 1e-18);
  EXPECT_NEAR(total.y(), 0.0, 1e-18);
}

}  // namespace
}  // namespace tt
