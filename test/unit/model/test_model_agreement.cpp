// Small strain: the linear tensor-mass model, the displacement StVK and the edge-length StVK
// (both paths) agree to first order in the displacement.
#include <gtest/gtest.h>

#include <cstdio>

#include "../model_test_util.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/model/tensor_mass.h"

namespace tt {
namespace {

using namespace testutil;

TEST(ModelAgreement, AllTetModelsAgreeAtSmallStrain) {
  std::mt19937 rng(41);
  Mesh m = boxMesh(3, 2, 2, 0.01, rng);
  const auto mats = testMaterials();
  EdgeLengthModel fast(m, mats, EdgeLengthPath::kFast);
  EdgeLengthModel literal(m, mats, EdgeLengthPath::kLiteral);
  StvkDisplacementModel displacement(m, mats);
  TensorMassModel linear(m, mats);
  const Eigen::VectorXd x = perturbed(m, 1e-6 * 0.01, rng);  // 1e-6 element lengths
  const Eigen::VectorXd reference = force(fast, x);
  const double dLiteral = relDiff(force(literal, x), reference);
  const double dDisplacement = relDiff(force(displacement, x), reference);
  const double dLinear = relDiff(force(linear, x), reference);
  std::printf("  rel. force difference vs edge_length fast: literal %.2e, displacement %.2e, "
              "tensor_mass %.2e\n", dLiteral, dDisplacement, dLinear);
  EXPECT_LT(dLiteral, 1e-9);
  EXPECT_LT(dDisplacement, 1e-9);
  EXPECT_LT(dLinear, 1e-5);  // first order in the strain: the dropped terms are O(strain)
  EXPECT_GT(dLinear, 1e-8);  // ... and they are not zero
  // Halving the displacement halves the linearisation error (it is first order).
  const Eigen::VectorXd rest = restVector(m);
  const Eigen::VectorXd half = rest + 0.5 * (x - rest);
  const double dHalf = relDiff(force(linear, half), force(fast, half));
  EXPECT_NEAR(dHalf / dLinear, 0.5, 0.05);
}

}  // namespace
}  // namespace tt
