// A muscle block flattened through itself recovers its rest shape ("Derivation of
// Quasistatics and Landmark Optimization for Muscles", Sec. 4: the inversion handling of the
// Teran muscle; rotation-only SVD with threshold 0.25, PSD-projected stiffness): every free
// node of a block clamped at its base is mirrored through the base plane, so every tet is
// inverted; damped backward Euler brings it back to the equilibrium the quasistatic solver
// finds from the rest shape. (The quasistatic solver itself does not get out of the fully
// inverted state: its line search on the energy finds no decrease where the force, evaluated
// at the clamped F, is not the energy's gradient.)
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/equilibrium.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace {

// A 2 x 2 x 1 cm muscle block at rest activation 0.2, its base z = 0 clamped, every other node
// mirrored through the base (z -> -z): each tet has the negative of its rest volume.
std::unique_ptr<System> flattenedBlock() {
  Mesh mesh = boxGrid(4, 4, 3, Eigen::Vector3d(0.02, 0.02, 0.01), TetSplit::kSixMirrored);
  auto s = std::make_unique<System>(mesh, std::vector<Material>{Material::isotropic(3e4, 0.45, 1060.0)});
  TeranMuscleLaw::Constants k;
  k.activation = 0.2;
  LawOptions options;
  options.inversionThreshold = 0.25;
  options.psdProjection = true;
  s->models.push_back(std::make_unique<HyperelasticModel<TeranMuscleLaw>>(
      s->mesh, std::vector<TeranMuscleLaw::Constants>{k}, options));
  for (int n = 0; n < s->numNodes(); ++n)
    if (s->mesh.rest(2, n) == 0.0) s->mesh.nodeTags[n] = kFixedAll;
  s->updateConstraints();
  for (int n = 0; n < s->numNodes(); ++n) s->state.x[3 * n + 2] = -s->mesh.rest(2, n);
  return s;
}

int invertedTets(const System& s) {
  int inverted = 0;
  for (const Tet& t : s.mesh.tets) {
    Eigen::Matrix3d D;
    for (int c = 0; c < 3; ++c)
      D.col(c) = s.state.x.segment<3>(3 * t[c + 1]) - s.state.x.segment<3>(3 * t[0]);
    inverted += D.determinant() <= 0.0;
  }
  return inverted;
}

// The equilibrium reached from the rest shape (the activation shortens the fibres a little).
Eigen::VectorXd restEquilibrium() {
  auto s = flattenedBlock();
  s->state.x = Eigen::Map<const Eigen::VectorXd>(s->mesh.rest.data(), s->numDofs());
  EXPECT_TRUE(solveEquilibrium(*s).converged());
  return s->state.x;
}

TEST(MuscleInversion, DampedBackwardEulerUnflattensTheBlock) {
  auto s = flattenedBlock();
  ASSERT_EQ(invertedTets(*s), s->mesh.numTets());
  s->damping = 50.0 * s->mass;  // 1/s: the motion dies out within the run
  BackwardEulerIntegrator integrator;
  for (int frame = 0; frame < 200; ++frame)
    ASSERT_TRUE(integrator.advance(*s, 0.01).ok) << "frame " << frame;
  const double error = (s->state.x - restEquilibrium()).lpNorm<Eigen::Infinity>();
  std::printf("[ measured ] backward Euler, 2 s from fully inverted: largest distance from the "
              "rest equilibrium %.3g m\n", error);
  EXPECT_EQ(invertedTets(*s), 0);
  EXPECT_LT(error, 1e-5);
}

}  // namespace
}  // namespace tt
