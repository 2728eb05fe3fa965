// The conformance suite of the element model `hyperelastic`: every law of LawTypes on a tet
// mesh and a hex mesh (jittered boxes) through the same checks: force against energy and
// stiffness against force by finite differences, K d against the assembled K, symmetry, no
// force at rest, rigid-motion invariance, a projected stiffness without negative
// eigenvalues, the patch test, and hexes against their tet splits under refinement.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <random>

#include "../model_test_util.h"
#include "tissue_trainer/core/material/guccione.h"
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/hunter_polynomial.h"
#include "tissue_trainer/core/material/neo_hookean.h"
#include "tissue_trainer/core/material/stvk.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

using namespace testutil;

template <class Law>
std::vector<typename Law::Constants> constantsFor(const std::vector<Material>& materials) {
  std::vector<typename Law::Constants> k;
  for (const Material& material : materials) {
    const ElasticConstants& m = material.elasticConstants();
    if constexpr (std::is_same_v<Law, VolumeLaw>) {
      k.push_back({0.5 * m.lambda, 1.0});
    } else if constexpr (std::is_same_v<Law, NeoHookeanLaw>) {
      k.push_back(NeoHookeanLaw::constants(Material::isotropic(2.0 * m.mu * 1.4, 0.4, 1000.0)));
    } else if constexpr (std::is_same_v<Law, HunterLaw>) {
      // Table 2.1's stiffnesses scaled to the material and its exponents, with the poles moved
      // past the large random strains of these checks (test_hunter.cpp has Table 2.1's poles).
      HunterConstants c = HunterConstants::table21();
      for (int t = 0; t < 6; ++t) c.k[t] *= m.mu / 1e3, c.a[t] += 10.0;
      k.push_back(c);
    } else if constexpr (std::is_same_v<Law, HunterPolynomialLaw>) {
      // Table 2.1 as it is: the random strains go past the switch strains and the poles.
      HunterPolynomialLaw::Constants c;
      for (double& stiffness : c.hunter.k) stiffness *= m.mu / 1e3;
      k.push_back(c);
    } else if constexpr (std::is_same_v<Law, GuccioneLaw>) {
      // The benchmark beam's weights, C and the bulk modulus scaled to the material.
      k.push_back({0.25 * m.mu, 8.0, 2.0, 4.0, m.lambda + m.mu});
    } else if constexpr (std::is_same_v<Law, TeranMuscleLaw>) {
      // Passive (no force at rest), scaled to the material; material 0 with the deviatoric
      // fibre stretch, material 1 with |F a0|.
      TeranMuscleLaw::Constants c;
      c.A = 0.3 * m.mu, c.B = 0.1 * m.mu, c.K = m.lambda + m.mu, c.sigmaMax = 2.0 * m.mu;
      c.deviatoricStretch = k.size() % 2 == 0;
      k.push_back(c);
    } else {
      k.push_back(Law::constants(material));
    }
  }
  return k;
}

// A box of hexes (no tets) with spacing h, interior nodes jittered, random fibre frames,
// materials alternating 0 / 1.
Mesh jitteredHexBox(int cells, double h, std::mt19937& rng, double jitter = 0.15) {
  Mesh m = boxGrid(cells + 1, cells + 1, cells + 1, Eigen::Vector3d::Constant(cells * h),
                   TetSplit::kNone);
  std::uniform_real_distribution<double> u(-jitter * h, jitter * h);
  for (int n = 0; n < m.numNodes(); ++n) {
    const Eigen::Vector3d X = m.rest.col(n);
    const bool interior = (X.array() > 1e-12).all() && (X.array() < cells * h - 1e-12).all();
    if (interior)
      for (int i = 0; i < 3; ++i) m.rest(i, n) += u(rng);
  }
  for (int e = 0; e < m.numHexes(); ++e) {
    m.hexFibreFrame[e] = frameFrom(randomUnit(rng));
    m.hexMaterial[e] = e % 2;
  }
  return m;
}

struct Case {
  const char* name;
  Mesh mesh;
};

std::vector<Case> meshes() {
  std::mt19937 rng(21);
  std::vector<Case> cases;
  cases.push_back({"tets", boxMesh(2, 2, 2, 0.01, rng)});
  cases.push_back({"hexes", jitteredHexBox(2, 0.01, rng)});
  return cases;
}

// The energy at rest: 0, except Eq. 10's constant V0 3 (A + B) per element of teran_muscle.
template <class Law>
double restEnergy(const Case& c) {
  if constexpr (std::is_same_v<Law, TeranMuscleLaw>) {
    const std::vector<TeranMuscleLaw::Constants> k = constantsFor<Law>(testMaterials());
    double e = 0.0;
    for (std::size_t t = 0; t < c.mesh.tets.size(); ++t)
      e += tetVolume(c.mesh.rest, c.mesh.tets[t]) * Law::restEnergy(k[c.mesh.material[t]]);
    for (std::size_t h = 0; h < c.mesh.hexes.size(); ++h) {
      double volume = 0.0;
      for (double w : Hex8::rest(c.mesh.rest, c.mesh.hexes[h]).weight) volume += w;
      e += volume * Law::restEnergy(k[c.mesh.hexMaterial[h]]);
    }
    return e;
  }
  return 0.0;
}

template <class Law>
class HyperelasticConformance : public ::testing::Test {
 protected:
  std::unique_ptr<ForceModel> model(const Mesh& mesh, LawOptions options = {}) const {
    return std::make_unique<HyperelasticModel<Law>>(mesh, constantsFor<Law>(testMaterials()),
                                                    options);
  }
};

using LawTypes = ::testing::Types<StvkLaw, NeoHookeanLaw, VolumeLaw, HunterLaw,
                                  HunterPolynomialLaw, GuccioneLaw, TeranMuscleLaw>;
TYPED_TEST_SUITE(HyperelasticConformance, LawTypes);

TYPED_TEST(HyperelasticConformance, ForceIsMinusTheEnergyGradient) {
  std::mt19937 rng(22);
  for (const Case& c : meshes()) {
    const auto m = this->model(c.mesh);
    const Eigen::VectorXd x = perturbed(c.mesh, 1e-3, rng);
    EXPECT_LT(relDiff(force(*m, x), Eigen::VectorXd(-fdGradient(*m, x, 1e-7))), 1e-6) << c.name;
  }
}

TYPED_TEST(HyperelasticConformance, StiffnessIsTheForceJacobianAndSymmetric) {
  std::mt19937 rng(23);
  for (const Case& c : meshes()) {
    const auto m = this->model(c.mesh);
    const Eigen::VectorXd x = perturbed(c.mesh, 1e-3, rng);
    const Eigen::MatrixXd K = denseStiffness(*m, c.mesh, x);
    EXPECT_LT(relDiff(K, fdForceJacobian(*m, x, 1e-7)), 1e-6) << c.name;
    EXPECT_LT(relDiff(Eigen::MatrixXd(K.transpose()), K), 1e-12) << c.name;
  }
}

TYPED_TEST(HyperelasticConformance, StiffnessProductMatchesTheAssembledStiffness) {
  std::mt19937 rng(24);
  for (bool projected : {false, true}) {
    for (const Case& c : meshes()) {
      LawOptions options;
      options.psdProjection = projected;
      const auto m = this->model(c.mesh, options);
      const Eigen::VectorXd x = perturbed(c.mesh, 1e-3, rng);
      const Eigen::VectorXd d = perturbed(c.mesh, 1.0, rng) - restVector(c.mesh);
      Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
      ASSERT_TRUE(m->hasStiffnessProduct());
      m->addStiffnessTimes(x, d, 1.0, Kd);
      const Eigen::VectorXd assembled = denseStiffness(*m, c.mesh, x) * d;
      EXPECT_LT(relDiff(Kd, assembled), 1e-12) << c.name << (projected ? " projected" : "");
    }
  }
}

TYPED_TEST(HyperelasticConformance, RestIsForceFreeAndMotionIsRigidInvariant) {
  std::mt19937 rng(25);
  for (const Case& c : meshes()) {
    const auto m = this->model(c.mesh);
    const Eigen::VectorXd rest = restVector(c.mesh);
    EXPECT_LT(force(*m, rest).template lpNorm<Eigen::Infinity>(), 1e-12) << c.name;
    const Eigen::VectorXd x = perturbed(c.mesh, 1e-3, rng);
    EXPECT_LT(std::abs(m->energy(rest) - restEnergy<TypeParam>(c)), 1e-12 * m->energy(x))
        << c.name;
    const Eigen::Matrix3d R = randomRotation(rng);
    const Eigen::Vector3d t(0.3, -1.2, 2.0);  // far from the origin: no digits lost
    const Eigen::VectorXd y = rigidMotion(x, R, t);
    EXPECT_NEAR(m->energy(y), m->energy(x), 1e-9 * m->energy(x)) << c.name;
    EXPECT_LT(relDiff(force(*m, y), rotateVectors(force(*m, x), R)), 1e-8) << c.name;
  }
}

TYPED_TEST(HyperelasticConformance, ProjectedStiffnessHasNoNegativeEigenvalue) {
  std::mt19937 rng(26);
  for (const Case& c : meshes()) {
    LawOptions options;
    options.inversionThreshold = 0.05;  // the compressed state may invert an element
    const auto plain = this->model(c.mesh, options);
    options.psdProjection = true;
    const auto projected = this->model(c.mesh, options);
    const Eigen::VectorXd x = perturbed(c.mesh, 3e-3, rng);  // large: elements compressed
    const auto minEigen = [&](const ForceModel& model) {
      const Eigen::MatrixXd H = -denseStiffness(model, c.mesh, x);
      const Eigen::VectorXd lambda = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(H).eigenvalues();
      return lambda.minCoeff() / lambda.cwiseAbs().maxCoeff();
    };
    EXPECT_LT(minEigen(*plain), -1e-6) << c.name << ": the state does not test the projection";
    EXPECT_GE(minEigen(*projected), -1e-9) << c.name;
  }
}

// Patch test: an affine deformation of a jittered mesh gives a constant stress, so the force
// on every interior node vanishes (the element integrals of grad N_p are exact).
TYPED_TEST(HyperelasticConformance, PatchTestOnTetsAndHexes) {
  std::mt19937 rng(27);
  for (Case& c : meshes()) {
    std::fill(c.mesh.material.begin(), c.mesh.material.end(), 0);  // one material: one stress
    std::fill(c.mesh.hexMaterial.begin(), c.mesh.hexMaterial.end(), 0);
    std::fill(c.mesh.fibreFrame.begin(), c.mesh.fibreFrame.end(), c.mesh.fibreFrame[0]);
    std::fill(c.mesh.hexFibreFrame.begin(), c.mesh.hexFibreFrame.end(), c.mesh.hexFibreFrame[0]);
    const auto m = this->model(c.mesh);
    Eigen::Matrix3d A = Eigen::Matrix3d::Identity();
    A << 1.08, 0.03, -0.02, 0.01, 0.95, 0.04, -0.03, 0.02, 1.05;
    Eigen::VectorXd x(3 * c.mesh.numNodes());
    for (int n = 0; n < c.mesh.numNodes(); ++n)
      x.segment<3>(3 * n) = A * c.mesh.rest.col(n) + Eigen::Vector3d(0.01, 0.02, -0.01);
    const Eigen::VectorXd f = force(*m, x);
    std::vector<bool> onSurface(c.mesh.numNodes(), false);
    for (const Triangle& t : extractSurface(c.mesh))
      for (int n : t) onSurface[n] = true;
    double interior = 0.0;
    int interiorNodes = 0;
    for (int n = 0; n < c.mesh.numNodes(); ++n) {
      if (onSurface[n]) continue;
      ++interiorNodes;
      interior = std::max(interior, f.segment<3>(3 * n).norm());
    }
    ASSERT_GT(interiorNodes, 0) << c.name;
    EXPECT_LT(interior, 1e-10 * f.template lpNorm<Eigen::Infinity>()) << c.name;
  }
}

// A smooth deformation of the unit-spaced box: the hex mesh and its six-tet split give
// energies that approach each other as the cells shrink.
TYPED_TEST(HyperelasticConformance, HexesAndTheirTetSplitsConvergeUnderRefinement) {
  using Law = TypeParam;
  const double size = 0.04;
  const auto deform = [&](const Eigen::Vector3d& X) {
    const double s = 3.14159265358979 / size;
    return Eigen::Vector3d(X.x() + 0.05 * size * std::sin(s * X.y()),
                           X.y() + 0.04 * size * std::sin(s * X.z()) * std::cos(s * X.x()),
                           0.97 * X.z() + 0.03 * size * std::sin(s * X.x()));
  };
  std::vector<double> gaps;
  double energy = 0.0;
  for (int cells : {2, 4, 8}) {
    double e[2];
    int i = 0;
    for (TetSplit split : {TetSplit::kNone, TetSplit::kSix}) {
      Mesh mesh = boxGrid(cells + 1, cells + 1, cells + 1, Eigen::Vector3d::Constant(size), split);
      Eigen::VectorXd x(3 * mesh.numNodes());
      for (int n = 0; n < mesh.numNodes(); ++n) x.segment<3>(3 * n) = deform(mesh.rest.col(n));
      const std::vector<Material> materials{Material::isotropic(1e4, 0.4, 1000.0)};
      e[i++] = HyperelasticModel<Law>(mesh, constantsFor<Law>(materials), {}).energy(x);
    }
    gaps.push_back(std::abs(e[0] - e[1]));
    energy = e[0];
  }
  std::printf("%s: |E_hex - E_tet| = %.3e, %.3e, %.3e J at 2, 4, 8 cells (E %.3e J)\n",
              Law::kName, gaps[0], gaps[1], gaps[2], energy);
  EXPECT_GT(gaps[0], 2.0 * gaps[1]);
  EXPECT_GT(gaps[1], 2.0 * gaps[2]);
  EXPECT_LT(gaps[2], 0.02 * energy);
}

// The generic model with the stvk law is the edge_length model's energy: the same forces.
TEST(Hyperelastic, StvkLawOnTetsGivesTheEdgeLengthForces) {
  std::mt19937 rng(28);
  const Mesh mesh = boxMesh(3, 2, 2, 0.01, rng);
  const std::vector<Material> materials = testMaterials();
  const auto generic = makeElasticModel("hyperelastic_stvk", mesh, materials);
  const auto edgeLength = makeElasticModel("edge_length", mesh, materials);
  const Eigen::VectorXd x = perturbed(mesh, 1e-3, rng);
  EXPECT_LT(relDiff(force(*generic, x), force(*edgeLength, x)), 1e-10);
  EXPECT_NEAR(generic->energy(x), edgeLength->energy(x), 1e-10 * edgeLength->energy(x));
}

// Inversion handling: a flattened-through tet keeps finite forces that undo the inversion;
// without it the Neo-Hookean energy is infinite and the model asks the stability guard to check.
TEST(Hyperelastic, InversionHandlingGivesFiniteRestoringForces) {
  std::mt19937 rng(29);
  const Mesh mesh = randomTet(rng);
  const std::vector<NeoHookeanLaw::Constants> k{
      NeoHookeanLaw::constants(Material::isotropic(5e3, 0.45, 1000.0))};
  LawOptions options;
  options.inversionThreshold = 0.1;
  const HyperelasticModel<NeoHookeanLaw> handled(mesh, k, options);
  const HyperelasticModel<NeoHookeanLaw> bare(mesh, k, {});
  EXPECT_TRUE(handled.toleratesInversion());
  EXPECT_FALSE(bare.toleratesInversion());
  Eigen::VectorXd x = restVector(mesh);
  const Eigen::Vector3d apex = x.segment<3>(9), base = x.segment<3>(0);
  const Eigen::Vector3d n = (x.segment<3>(3) - base).cross(x.segment<3>(6) - base).normalized();
  x.segment<3>(9) = apex - 1.5 * n.dot(apex - base) * n;  // node 3 pushed through its face
  ASSERT_LT(tetVolume(Eigen::Map<const Eigen::Matrix3Xd>(x.data(), 3, 4), mesh.tets[0]), 0.0);
  EXPECT_FALSE(std::isfinite(bare.energy(x)));
  const Eigen::VectorXd f = force(handled, x);
  ASSERT_TRUE(f.allFinite());
  EXPECT_TRUE(std::isfinite(handled.energy(x)));
  EXPECT_GT(f.segment<3>(9).dot(n), 0.0) << "node 3 is pushed back through its face";
}

}  // namespace
}  // namespace tt
