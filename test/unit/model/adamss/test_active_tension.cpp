// Active contraction of the Adamss mass-spring system (model/adamss/active_tension.h): the
// forces by hand on a cube and a tet; on tets the forces of the finite element with the active
// stress; internal forces (no net force or moment on any element); force against its potential and
// stiffness against force by finite differences; rigid-rotation covariance; a free box that
// contracts along its fibre alone, solved statically; and a run whose tension follows its
// time curve through beginStep.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "../../model_test_util.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/material/stvk.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/active_tension.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace adamss {
namespace {

using namespace testutil;

struct Variant {
  ActiveForm form;
  ActiveMode mode;
  const char* name;
};
const Variant kVariants[] = {{ActiveForm::kAnisotropic, ActiveMode::kTension, "anisotropic tension"},
                             {ActiveForm::kAnisotropic, ActiveMode::kForce, "anisotropic force"},
                             {ActiveForm::kIsotropic, ActiveMode::kTension, "isotropic tension"},
                             {ActiveForm::kIsotropic, ActiveMode::kForce, "isotropic force"}};

ActiveTensionModel constantTension(const Mesh& mesh, const Variant& v, double t) {
  return ActiveTensionModel(mesh, v.form, v.mode, TimeCurve::constant(t));
}

Mesh unitCube(double h) {
  Mesh m = boxGrid(2, 2, 2, Eigen::Vector3d(h, h, h), TetSplit::kNone);
  m.hexFibreFrame.assign(1, Eigen::Matrix3d::Identity());
  return m;
}

Mesh unitTet(double h) {
  Mesh m;
  m.rest.resize(3, 4);
  m.rest << 0, h, 0, 0, 0, 0, h, 0, 0, 0, 0, h;
  m.tets = {{0, 1, 2, 3}};
  m.fibreFrame = {Eigen::Matrix3d::Identity()};
  m.material = {0};
  m.fillDefaults();
  return m;
}

// One hex of random shape (non-planar, non-parallelogram faces) and fibre.
Mesh warpedHex(std::mt19937& rng) {
  Mesh m = boxGrid(2, 2, 2, Eigen::Vector3d(0.01, 0.012, 0.009), TetSplit::kNone);
  std::uniform_real_distribution<double> u(-1.5e-3, 1.5e-3);
  for (int n = 0; n < m.numNodes(); ++n)
    for (int i = 0; i < 3; ++i) m.rest(i, n) += u(rng);
  m.hexFibreFrame = {randomRotation(rng)};
  return m;
}

Mesh jitteredHexes(std::mt19937& rng) {
  Mesh m = boxGrid(3, 3, 2, Eigen::Vector3d(0.01, 0.01, 0.006), TetSplit::kNone);
  std::uniform_real_distribution<double> u(-5e-4, 5e-4);
  for (int n = 0; n < m.numNodes(); ++n)
    for (int i = 0; i < 3; ++i) m.rest(i, n) += u(rng);
  for (auto& B : m.hexFibreFrame) B = randomRotation(rng);
  return m;
}

Eigen::Vector3d netForce(const Eigen::VectorXd& f) {
  return f.reshaped(3, f.size() / 3).rowwise().sum();
}

Eigen::Vector3d netMoment(const Eigen::VectorXd& x, const Eigen::VectorXd& f) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (int n = 0; n < x.size() / 3; ++n) m += x.segment<3>(3 * n).cross(f.segment<3>(3 * n));
  return m;
}

// Eq. 2.112 with the face area, as printed otherwise: each face's -t S_j n_j (the vector area
// of a quad: half the cross product of its diagonals) in equal shares on its nodes.
Eigen::VectorXd equalShareFaceForces(const Mesh& m, const Eigen::VectorXd& x, double t) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  auto at = [&](int node) { return Eigen::Vector3d(x.segment<3>(3 * node)); };
  for (const Hex& hex : m.hexes)
    for (const auto& face : Hex8::faces) {
      const Eigen::Vector3d area =
          0.5 * (at(hex[face[2]]) - at(hex[face[0]])).cross(at(hex[face[3]]) - at(hex[face[1]]));
      for (int k = 0; k < 4; ++k) f.segment<3>(3 * hex[face[k]]) -= t * area / 4.0;
    }
  return f;
}

TEST(AdamssActiveTension, ZeroTensionGivesNoForceOrStiffness) {
  std::mt19937 rng(3);
  const Mesh tets = boxMesh(2, 1, 1, 0.01, rng);
  const Mesh hexes = jitteredHexes(rng);
  for (const Mesh* mesh : {&tets, &hexes})
    for (const Variant& v : kVariants) {
      SCOPED_TRACE(v.name);
      const ActiveTensionModel model = constantTension(*mesh, v, 0.0);
      const Eigen::VectorXd x = perturbed(*mesh, 1e-3, rng);
      EXPECT_EQ(force(model, x).lpNorm<Eigen::Infinity>(), 0.0);
      EXPECT_EQ(model.potential(x), 0.0);
      EXPECT_EQ(denseStiffness(model, *mesh, x).lpNorm<Eigen::Infinity>(), 0.0);
    }
}

// A cube of side h with the fibre along x, stretched by a along x and b along y. Anisotropic:
// the fibre points q_0 (face x = h) and q_1 (face x = 0) carry -+c e_x, a quarter per node,
// with c = t (b h) h (tension: the current face across the fibre) or t h^2 (force).
// Isotropic: node (+, +, +) gets -t/4 times the outward vector areas of its three faces,
// (b h^2, a h^2, a b h^2); the force mode scales this by (V0 / V)^(2/3) = (a b)^(-2/3).
TEST(AdamssActiveTension, StretchedCubeHandComputed) {
  const double h = 0.01, t = 2e3, a = 1.2, b = 1.1;
  const Mesh cube = unitCube(h);
  Eigen::VectorXd x = restVector(cube);
  for (int n = 0; n < cube.numNodes(); ++n) x[3 * n] *= a, x[3 * n + 1] *= b;
  int corner = -1;  // the node at (h, h, h)
  for (int n = 0; n < cube.numNodes(); ++n)
    if (cube.rest.col(n).minCoeff() > 0.5 * h) corner = n;
  ASSERT_GE(corner, 0);
  const double tol = 1e-12 * t * h * h;
  for (const Variant& v : kVariants) {
    SCOPED_TRACE(v.name);
    const Eigen::VectorXd f = force(constantTension(cube, v, t), x);
    if (v.form == ActiveForm::kAnisotropic) {
      const double c = v.mode == ActiveMode::kTension ? t * b * h * h : t * h * h;
      for (int n = 0; n < cube.numNodes(); ++n) {
        const double sign = cube.rest(0, n) > 0.5 * h ? -1.0 : 1.0;
        EXPECT_NEAR(f[3 * n], sign * c / 4, tol) << n;
        EXPECT_NEAR(f.segment<2>(3 * n + 1).norm(), 0.0, tol) << n;
      }
    } else {
      const double scale = v.mode == ActiveMode::kTension ? 1.0 : std::pow(a * b, -2.0 / 3.0);
      const Eigen::Vector3d expected = -scale * t / 4 * h * h * Eigen::Vector3d(b, a, a * b);
      EXPECT_LT((f.segment<3>(3 * corner) - expected).norm(), tol);
    }
  }
}

// The tet with nodes 0, h e_x, h e_y, h e_z and the fibre along x: the ray from the
// barycentre leaves through the slanted face at (h/2, h/4, h/4) (weights 1/2, 1/4, 1/4 on
// nodes 1, 2, 3) and through x = 0 at (0, h/4, h/4) (1/2, 1/4, 1/4 on nodes 0, 2, 3). With
// c = t V0 / |zeta_0| = t (h^3 / 6) / (h / 2) = t h^2 / 3 the nodes get
// -c/2 e_x (node 1), +c/2 e_x (node 0) and nothing on nodes 2, 3.
// Isotropic (Eq. 2.112 with the area): node 0 lies on the three faces of area h^2/2 with
// normals -e_x, -e_y, -e_z and gets t h^2 / 6 (1, 1, 1); node 1 lies on the faces with normals
// -e_y, -e_z and on the slanted face (vector area h^2/2 (1, 1, 1)) and gets -t h^2 / 6 e_x.
TEST(AdamssActiveTension, UnitTetHandComputed) {
  const double h = 0.01, t = 3e3;
  const Mesh tet = unitTet(h);
  const Eigen::VectorXd x = restVector(tet);
  const double tol = 1e-12 * t * h * h;
  const Eigen::VectorXd fa = force(constantTension(tet, kVariants[0], t), x);
  Eigen::VectorXd expected = Eigen::VectorXd::Zero(12);
  expected[0] = t * h * h / 6;
  expected[3] = -t * h * h / 6;
  EXPECT_LT((fa - expected).lpNorm<Eigen::Infinity>(), tol) << fa.transpose();
  EXPECT_LT((force(constantTension(tet, kVariants[1], t), x) - expected).lpNorm<Eigen::Infinity>(),
            tol);
  const Eigen::VectorXd fi = force(constantTension(tet, kVariants[2], t), x);
  EXPECT_LT((fi.segment<3>(0) - t * h * h / 6 * Eigen::Vector3d::Ones()).norm(), tol);
  EXPECT_LT((fi.segment<3>(3) + t * h * h / 6 * Eigen::Vector3d::UnitX()).norm(), tol);
}

// On a linear tet the forces are those of the finite element with a uniform active stress:
// f_p = -v sigma grad_x N_p with sigma = t u u^T (anisotropic tension, u the current fibre
// F a_0 / |F a_0|) or t I (isotropic tension), and f_p = -V0 P grad_X N_p with P = t u a_0^T
// (anisotropic force). The isotropic force mode is the tension mode times (V0 / v)^(2/3).
TEST(AdamssActiveTension, TetForcesAreThoseOfTheActiveStressElement) {
  std::mt19937 rng(8);
  const double t = 5e3;
  for (int trial = 0; trial < 20; ++trial) {
    const Mesh tet = randomTet(rng);
    const Eigen::VectorXd x = perturbed(tet, 1.5e-3, rng);
    Eigen::Matrix3d Dm, Ds;
    for (int k = 0; k < 3; ++k) {
      Dm.col(k) = tet.rest.col(k + 1) - tet.rest.col(0);
      Ds.col(k) = x.segment<3>(3 * (k + 1)) - x.segment<3>(0);
    }
    const Eigen::Matrix3d F = Ds * Dm.inverse();
    const Eigen::Vector3d a0 = tet.fibreFrame[0].col(0);
    const Eigen::Vector3d u = (F * a0).normalized();
    const double V0 = Dm.determinant() / 6, v = Ds.determinant() / 6;
    auto gradients = [](const Eigen::Matrix3d& D) {  // column p: grad N_p
      Eigen::Matrix<double, 3, 4> G;
      G.rightCols<3>() = D.inverse().transpose();
      G.col(0) = -G.rightCols<3>().rowwise().sum();
      return G;
    };
    const Eigen::Matrix<double, 3, 4> gx = gradients(Ds), gX = gradients(Dm);
    Eigen::VectorXd fTension(12), fForce(12), fIso(12);
    for (int p = 0; p < 4; ++p) {
      fTension.segment<3>(3 * p) = -v * t * u * u.dot(gx.col(p));
      fForce.segment<3>(3 * p) = -V0 * t * u * a0.dot(gX.col(p));
      fIso.segment<3>(3 * p) = -v * t * gx.col(p);
    }
    const Eigen::VectorXd fIsoForce = std::pow(V0 / v, 2.0 / 3.0) * fIso;
    const Eigen::VectorXd* expected[] = {&fTension, &fForce, &fIso, &fIsoForce};
    for (int k = 0; k < 4; ++k)
      EXPECT_LT(relDiff(force(constantTension(tet, kVariants[k], t), x), *expected[k]), 1e-10)
          << kVariants[k].name;
  }
}

// On every element the resultant and the moment vanish, for any shape and deformation.
// The printed equal shares of Eq. 2.112 leave a moment on a warped hex; on a hex with
// parallelogram faces (an affine image of the cube) they equal the model's isotropic force.
TEST(AdamssActiveTension, InternalForcesHaveNoNetForceOrMoment) {
  std::mt19937 rng(13);
  const double t = 1e4;
  for (int trial = 0; trial < 10; ++trial) {
    const Mesh tet = randomTet(rng);
    const Mesh hex = warpedHex(rng);
    for (const Mesh* mesh : {&tet, &hex}) {
      const Eigen::VectorXd x = perturbed(*mesh, 1e-3, rng);
      for (const Variant& v : kVariants) {
        SCOPED_TRACE(v.name);
        const Eigen::VectorXd f = force(constantTension(*mesh, v, t), x);
        const double scale = f.norm() * x.lpNorm<Eigen::Infinity>();
        EXPECT_GT(f.norm(), 1e-3 * t * 1e-4);
        EXPECT_LT(netForce(f).norm(), 1e-12 * f.norm());
        EXPECT_LT(netMoment(x, f).norm(), 1e-12 * scale);
      }
    }
    const Eigen::VectorXd x = perturbed(hex, 1e-3, rng);
    const Eigen::VectorXd printed = equalShareFaceForces(hex, x, t);
    EXPECT_LT(netForce(printed).norm(), 1e-12 * printed.norm());
    EXPECT_GT(netMoment(x, printed).norm(), 1e-4 * printed.norm() * x.lpNorm<Eigen::Infinity>());
  }
  const Mesh cube = unitCube(0.01);
  Eigen::Matrix3d A = Eigen::Matrix3d::Identity() + 0.2 * Eigen::Matrix3d::Random();
  if (A.determinant() < 0) A.col(0) *= -1.0;
  const Eigen::VectorXd x = rigidMotion(restVector(cube), A, Eigen::Vector3d(0.1, -0.2, 0.3));
  EXPECT_LT(relDiff(force(constantTension(cube, kVariants[2], t), x),
                    equalShareFaceForces(cube, x, t)),
            1e-12);
}

Eigen::VectorXd fdPotentialGradient(const ActiveTensionModel& model, const Eigen::VectorXd& x,
                                    double h) {
  Eigen::VectorXd g(x.size()), xp = x;
  for (int i = 0; i < x.size(); ++i) {
    xp[i] = x[i] + h;
    const double ep = model.potential(xp);
    xp[i] = x[i] - h;
    g[i] = (ep - model.potential(xp)) / (2 * h);
    xp[i] = x[i];
  }
  return g;
}

TEST(AdamssActiveTension, ForceIsThePotentialGradientAndStiffnessItsDerivative) {
  std::mt19937 rng(21);
  const Mesh tets = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const Mesh hexes = jitteredHexes(rng);
  const double t = 8e3;
  for (const Mesh* mesh : {&tets, &hexes})
    for (const Variant& v : kVariants) {
      SCOPED_TRACE(std::string(mesh->hexes.empty() ? "tets, " : "hexes, ") + v.name);
      const ActiveTensionModel model = constantTension(*mesh, v, t);
      const Eigen::VectorXd x = perturbed(*mesh, 8e-4, rng);
      const Eigen::VectorXd f = force(model, x);
      const Eigen::MatrixXd K = denseStiffness(model, *mesh, x);
      EXPECT_LT(relDiff(K, fdForceJacobian(model, x, 1e-8)), 1e-6);
      const Eigen::VectorXd d = perturbed(*mesh, 1.0, rng) - restVector(*mesh);
      Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
      ASSERT_TRUE(model.hasStiffnessProduct());
      model.addStiffnessTimes(x, d, 1.0, Kd);
      EXPECT_LT(relDiff(Kd, Eigen::VectorXd(K * d)), 1e-12);
      const bool conservative = !(v.form == ActiveForm::kAnisotropic && v.mode == ActiveMode::kTension);
      EXPECT_EQ(model.hasPotential(), conservative);
      EXPECT_FALSE(model.hasEnergy());  // the potential changes with time: see the header
      if (conservative) {
        EXPECT_LT(relDiff(f, Eigen::VectorXd(-fdPotentialGradient(model, x, 1e-8))), 1e-6);
        EXPECT_LT(relDiff(Eigen::MatrixXd(K.transpose()), K), 1e-12);
      } else {
        EXPECT_EQ(model.potential(x), 0.0);
        EXPECT_GT(relDiff(Eigen::MatrixXd(K.transpose()), K), 1e-3);  // no potential
      }
    }
}

// Moving the mesh, its fibres and the state by the same rotation (and a translation) rotates
// the forces.
TEST(AdamssActiveTension, RotatingTheConfigurationAndFibreRotatesTheForce) {
  std::mt19937 rng(34);
  const Mesh tets = boxMesh(2, 1, 1, 0.01, rng, 0.15);
  const Mesh hexes = jitteredHexes(rng);
  for (const Mesh* mesh : {&tets, &hexes}) {
    const Eigen::Matrix3d R = randomRotation(rng);
    const Eigen::Vector3d shift(0.02, -0.01, 0.03);
    Mesh turned = *mesh;
    for (int n = 0; n < turned.numNodes(); ++n) turned.rest.col(n) = R * mesh->rest.col(n) + shift;
    for (auto& B : turned.fibreFrame) B = R * B;
    for (auto& B : turned.hexFibreFrame) B = R * B;
    const Eigen::VectorXd x = perturbed(*mesh, 1e-3, rng);
    for (const Variant& v : kVariants) {
      SCOPED_TRACE(v.name);
      const Eigen::VectorXd f = force(constantTension(*mesh, v, 4e3), x);
      const Eigen::VectorXd fTurned =
          force(constantTension(turned, v, 4e3), rigidMotion(x, R, shift));
      EXPECT_LT(relDiff(fTurned, rotateVectors(f, R)), 1e-12);
    }
  }
}

// The static stretch of a free box of St Venant-Kirchhoff material without lateral coupling
// (lambda = 0) under the fibre tension t along x: F = diag(s, 1, 1) with
// P_11 = mu s (s^2 - 1) = -t in both modes (tension: the Cauchy stress t across the current
// face, whose area does not change; force: t per rest area). The lateral sizes stay.
double fibreStretch(double tOverMu) {
  double s = 1.0;
  for (int i = 0; i < 50; ++i) s -= (s * s * s - s + tOverMu) / (3 * s * s - 1);
  return s;
}

TEST(AdamssActiveTension, FibreTensionShortensAFreeBoxAlongTheFibreOnly) {
  const double mu = 1e4, t = 1e3;
  const Mesh box = boxGrid(4, 3, 3, Eigen::Vector3d(0.02, 0.01, 0.01), TetSplit::kSixMirrored);
  const HyperelasticModel<StvkLaw> elastic(box, {StvkLaw::Constants{0.0, mu, 0.0}}, {});
  const Eigen::VectorXd X = restVector(box);
  const double s = fibreStretch(t / mu);
  EXPECT_NEAR(s, 0.9457, 1e-3);
  // The 3-2-1 supports remove the rigid motions and nothing else.
  const std::vector<int> fixed = {0, 1, 2, 3 * 3 + 1, 3 * 3 + 2, 3 * 4 + 2};
  for (const ActiveMode mode : {ActiveMode::kTension, ActiveMode::kForce}) {
    const ActiveTensionModel active(box, ActiveForm::kAnisotropic, mode, TimeCurve::constant(t));
    Eigen::VectorXd x = X;
    for (int iteration = 0; iteration < 30; ++iteration) {
      Eigen::VectorXd f = force(elastic, x) + force(active, x);
      Eigen::MatrixXd K = denseStiffness(elastic, box, x) + denseStiffness(active, box, x);
      for (int d : fixed) {
        K.row(d).setZero();
        K.col(d).setZero();
        K(d, d) = 1.0;
        f[d] = 0.0;
      }
      x -= K.partialPivLu().solve(f);
    }
    for (int n = 0; n < box.numNodes(); ++n) {
      EXPECT_NEAR(x[3 * n], s * X[3 * n], 1e-10) << n;
      EXPECT_NEAR(x[3 * n + 1], X[3 * n + 1], 1e-10) << n;
      EXPECT_NEAR(x[3 * n + 2], X[3 * n + 2], 1e-10) << n;
    }
  }
}

// A run with the frame loop: the tension ramps up, holds, and ramps down. After every frame
// the model's tension is the curve at the start of the frame's last step; the damped box
// settles at the static stretch while the tension holds and returns to rest after.
TEST(AdamssActiveTension, TheTimeCurveIsFollowedThroughBeginStep) {
  const double mu = 1e4, tPeak = 1e3, frame = 1e-3;
  const Mesh box = boxGrid(3, 2, 2, Eigen::Vector3d(0.02, 0.01, 0.01), TetSplit::kSixMirrored);
  const TimeCurve curve =
      TimeCurve::piecewiseLinear({0.0, 0.05, 0.25, 0.3}, {0.0, tPeak, tPeak, 0.0});
  System system(box, {Material::isotropic(3e4, 0.0, 1000.0)});
  system.models.push_back(
      std::make_unique<HyperelasticModel<StvkLaw>>(box, std::vector<StvkLaw::Constants>{{0.0, mu, 0.0}},
                                                   LawOptions{}));
  system.models.push_back(std::make_unique<ActiveTensionModel>(box, ActiveForm::kAnisotropic,
                                                               ActiveMode::kTension, curve));
  const auto& active = static_cast<const ActiveTensionModel&>(*system.models.back());
  system.damping = 500.0 * system.mass;
  const Eigen::VectorXd X = restVector(box);
  auto lengthRatio = [&] {  // current over rest extent along x, and the largest lateral change
    const Eigen::Map<const Eigen::Matrix3Xd> x(system.state.x.data(), 3, box.numNodes());
    const double ratio = (x.row(0).maxCoeff() - x.row(0).minCoeff()) / 0.02;
    const double lateral = std::max(std::abs(x.row(1).maxCoeff() - x.row(1).minCoeff() - 0.01),
                                    std::abs(x.row(2).maxCoeff() - x.row(2).minCoeff() - 0.01));
    return std::make_pair(ratio, lateral);
  };
  BackwardEulerIntegrator integrator;
  for (int k = 0; k < 600; ++k) {
    const double start = system.state.t;
    ASSERT_TRUE(integrator.advance(system, frame).ok);
    ASSERT_DOUBLE_EQ(active.tension(), curve.value(start)) << start;
    if (k == 249) {  // t = 0.25: held at the peak for 0.2 s
      const auto [ratio, lateral] = lengthRatio();
      EXPECT_NEAR(ratio, fibreStretch(tPeak / mu), 1e-6);
      EXPECT_LT(lateral, 1e-9);
    }
  }
  const auto [ratio, lateral] = lengthRatio();
  EXPECT_NEAR(ratio, 1.0, 1e-6);
  EXPECT_LT(lateral, 1e-9);
  EXPECT_LT((system.state.x - X).lpNorm<Eigen::Infinity>(), 1e-8);

  // Explicit Euler in substeps: the tension after a frame is that of its last substep's start.
  ExplicitEulerParams params;
  params.substep = 1e-5;
  params.symplectic = true;
  ExplicitEulerIntegrator euler(params);
  system.state.t = 0.0;
  for (int k = 0; k < 20; ++k) {
    ASSERT_TRUE(euler.advance(system, frame).ok);
    EXPECT_NEAR(active.tension(), curve.value(system.state.t - params.substep), 1e-6 * tPeak);
  }
}

}  // namespace
}  // namespace adamss
}  // namespace tt
