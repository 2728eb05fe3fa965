// The algebraic multigrid preconditioner of solve/amg_preconditioner.h (hypre BoomerAMG) on the
// implicit-step matrix M - h^2 K of a clamped, jittered box of anisotropic StVK tets: CG with
// one V-cycle per iteration reaches the direct solution in a fraction of Jacobi's iterations;
// the V-cycle is a fixed symmetric positive definite linear map (what CG needs); a new set-up
// takes the new matrix; a hypre error is a refused set-up with hypre's message, not an abort.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <memory>
#include <random>

#include "../model_test_util.h"
#include "solve_test_util.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/solve/amg_preconditioner.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

// M - h^2 K at rest of a box of cells^3 cells (1 cm each, nodes jittered, two materials in
// alternate tets), its bottom face clamped (identity rows and columns).
SparseMatrix boxStepMatrix(int cells, double h) {
  std::mt19937 rng(11);
  Mesh mesh = testutil::boxMesh(cells, cells, cells, 0.01, rng);
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (mesh.rest(2, n) < 0.002) mesh.nodeTags[n] = kFixedAll;
  System system(mesh, testutil::testMaterials());
  system.models.push_back(std::make_unique<EdgeLengthModel>(system.mesh, system.materials));
  SparseMatrix A;
  system.assembleStiffness(system.state.x, A, -h * h);
  for (int dof = 0; dof < system.numDofs(); ++dof) A.coeffRef(dof, dof) += system.mass[dof];
  system.constrainMatrix(A);
  return A;
}

struct Solved {
  Eigen::VectorXd x;
  int iterations;
};

Solved pcg(const SparseMatrix& A, const Eigen::VectorXd& b, const Preconditioner& M) {
  Eigen::VectorXd x = Eigen::VectorXd::Zero(A.rows());
  KrylovWorkspace work;
  const SolveReport r = conjugateGradients(MatrixOperator(A), b, x, M, {1e-10, 5000, 30}, work);
  EXPECT_TRUE(r.converged()) << outcomeName(r.outcome);
  return {x, r.iterations};
}

TEST(AmgPreconditioner, PcgReachesTheDirectSolutionInAFractionOfJacobisIterations) {
  const SparseMatrix A = boxStepMatrix(10, 0.05);
  const Eigen::VectorXd b = randomVector(A.rows(), 3);
  const Eigen::SparseMatrix<double> colA = A;
  const Eigen::VectorXd direct = Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>>(colA).solve(b);
  ASSERT_LT((A * direct - b).norm(), 1e-10 * b.norm());

  AmgPreconditioner amg;
  ASSERT_TRUE(amg.setup(A)) << amg.lastRefusal();
  EXPECT_TRUE(amg.ready());
  EXPECT_EQ(amg.builds(), 1);
  JacobiPreconditioner jacobi;
  ASSERT_TRUE(jacobi.setFromMatrix(A));
  const Solved withAmg = pcg(A, b, amg), withJacobi = pcg(A, b, jacobi);
  EXPECT_LT((withAmg.x - direct).norm(), 1e-8 * direct.norm());
  EXPECT_LT((withJacobi.x - direct).norm(), 1e-8 * direct.norm());
  EXPECT_GT(withJacobi.iterations, 200);  // the matrix is hard for Jacobi
  EXPECT_LT(3 * withAmg.iterations, withJacobi.iterations)
      << "amg " << withAmg.iterations << ", jacobi " << withJacobi.iterations;
}

TEST(AmgPreconditioner, TheVCycleIsAFixedSymmetricPositiveDefiniteMap) {
  const SparseMatrix A = boxStepMatrix(6, 0.05);
  AmgPreconditioner amg;
  ASSERT_TRUE(amg.setup(A)) << amg.lastRefusal();
  const Eigen::VectorXd u = randomVector(A.rows(), 1), v = randomVector(A.rows(), 2);
  Eigen::VectorXd Mu, Mv, Mw;
  amg.apply(u, Mu);
  amg.apply(v, Mv);
  EXPECT_NEAR(v.dot(Mu), u.dot(Mv), 1e-10 * std::abs(u.dot(Mv)));
  EXPECT_GT(u.dot(Mu), 0.0);
  EXPECT_GT(v.dot(Mv), 0.0);
  amg.apply(2.0 * u + v, Mw);  // linear: each cycle starts from zero
  EXPECT_LT((Mw - 2.0 * Mu - Mv).norm(), 1e-10 * Mw.norm());
  EXPECT_GT((Mu - u).norm(), 0.1 * u.norm());  // not the identity
}

TEST(AmgPreconditioner, ANewSetupTakesTheNewMatrix) {
  const SparseMatrix A = boxStepMatrix(6, 0.05);
  AmgPreconditioner amg;
  ASSERT_TRUE(amg.setup(A));
  const Eigen::VectorXd r = randomVector(A.rows(), 4);
  Eigen::VectorXd z1, z2;
  amg.apply(r, z1);
  // Every step of the set-up and the cycle is invariant to a scale of A but the result: the
  // hierarchy of 2 A gives half the correction.
  ASSERT_TRUE(amg.setup(2.0 * A));
  EXPECT_EQ(amg.builds(), 2);
  amg.apply(r, z2);
  EXPECT_LT((2.0 * z2 - z1).norm(), 1e-10 * z1.norm());
}

TEST(AmgPreconditioner, AHypreErrorIsARefusedSetupWithHypresMessage) {
  const SparseMatrix A = boxStepMatrix(3, 0.05);
  AmgSettings bad;
  bad.numFunctions = 0;  // hypre rejects the argument
  AmgPreconditioner broken(bad);
  EXPECT_FALSE(broken.setup(A));
  EXPECT_FALSE(broken.ready());
  EXPECT_EQ(broken.refusals(), 1);
  EXPECT_EQ(broken.builds(), 0);
  EXPECT_NE(broken.lastRefusal().find("hypre BoomerAMG configuration failed"), std::string::npos)
      << broken.lastRefusal();
  EXPECT_NE(broken.lastRefusal().find("argument"), std::string::npos) << broken.lastRefusal();
  const Eigen::VectorXd r = randomVector(A.rows(), 5);
  Eigen::VectorXd z;
  broken.apply(r, z);  // no hierarchy: the identity
  EXPECT_EQ(z, r);

  EXPECT_FALSE(broken.setup(SparseMatrix(6, 3)));
  EXPECT_NE(broken.lastRefusal().find("square"), std::string::npos) << broken.lastRefusal();

  // hypre's error flag is global: cleared, so another preconditioner works.
  AmgPreconditioner good;
  EXPECT_TRUE(good.setup(A)) << good.lastRefusal();
  good.apply(r, z);
  EXPECT_TRUE(z.allFinite());
  EXPECT_GT(r.dot(z), 0.0);
}

}  // namespace
}  // namespace tt
