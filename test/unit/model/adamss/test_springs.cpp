// The axial and torsion springs of the Adamss mass-spring system (model/adamss/axial_springs.h,
// torsion_springs.h): a hand-computed stretched cube; force against energy and stiffness
// against force by finite differences for every form that has an energy; the printed torsion
// forces' moment about the element against its closed form; no net force; invariance under
// rigid motion.
#include <gtest/gtest.h>

#include <Eigen/Dense>
#include <random>

#include "../../model_test_util.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/axial_springs.h"
#include "tissue_trainer/core/model/adamss/axis_friction.h"
#include "tissue_trainer/core/model/adamss/torsion_springs.h"
#include "tissue_trainer/core/model/adamss/volume_springs.h"

namespace tt {
namespace adamss {
namespace {

using namespace testutil;

Mesh springJitteredHexes(std::mt19937& rng) {
  Mesh m = boxGrid(3, 3, 2, Eigen::Vector3d(0.01, 0.01, 0.006), TetSplit::kNone);
  std::uniform_real_distribution<double> u(-5e-4, 5e-4);
  for (int n = 0; n < m.numNodes(); ++n)
    for (int i = 0; i < 3; ++i) m.rest(i, n) += u(rng);
  for (auto& B : m.hexFibreFrame) B = randomRotation(rng);
  return m;
}

AxialSpringParameters cubicAxial(bool area) {
  AxialSpringParameters p;
  p.areaForm = area;
  const double scale = area ? 1e3 : 10.0;
  p.k = {{{6.4 * scale, 50.0 * scale, 768 * scale},
          {1.0 * scale, 0.0, 288.5 * scale},
          {0.3 * scale, 2.0 * scale, 5.7 * scale}}};
  return p;
}

TorsionSpringParameters cubicTorsion(bool cosine, bool gradient, bool area) {
  TorsionSpringParameters p;
  p.cosine = cosine;
  p.gradient = gradient;
  p.areaForm = area;
  const double scale = area ? 1e3 : 1e-2;
  p.k = {{{3.4 * scale, 0.0, 97.4 * scale},
          {97.4 * scale, 1.0 * scale, 3.4 * scale},
          {45.9 * scale, 0.0, 2.3 * scale}}};
  return p;
}

Eigen::Vector3d springNetForce(const Eigen::VectorXd& f) {
  return f.reshaped(3, f.size() / 3).rowwise().sum();
}

Eigen::Vector3d springNetMoment(const Eigen::VectorXd& x, const Eigen::VectorXd& f) {
  Eigen::Vector3d m = Eigen::Vector3d::Zero();
  for (int n = 0; n < x.size() / 3; ++n) m += x.segment<3>(3 * n).cross(f.segment<3>(3 * n));
  return m;
}

// A cube of side h, axes along its edges, stretched by d along x: each axis-x point carries
// k d (length form), spread equally on its face's four nodes.
TEST(AdamssSprings, StretchedCubeHandComputed) {
  const double h = 0.01, d = 1e-3, k = 200.0;
  Mesh cube = boxGrid(2, 2, 2, Eigen::Vector3d(h, h, h), TetSplit::kNone);
  AxialSpringParameters p;
  p.k[0] = {k, 0.0, 0.0};
  const AxialSpringModel model(cube, p);
  Eigen::VectorXd x = restVector(cube);
  for (int n = 0; n < cube.numNodes(); ++n)
    if (cube.rest(0, n) > 0.5 * h) x[3 * n] += d;
  const Eigen::VectorXd f = force(model, x);
  for (int n = 0; n < cube.numNodes(); ++n) {
    const double expected = (cube.rest(0, n) > 0.5 * h ? -1.0 : 1.0) * k * d / 4;
    EXPECT_NEAR(f[3 * n], expected, 1e-12 * k * d) << n;
    EXPECT_NEAR(f.segment<2>(3 * n + 1).norm(), 0.0, 1e-12 * k * d);
  }
  EXPECT_NEAR(model.energy(x), 0.5 * k * d * d, 1e-12 * k * d * d);
  // The area form with E in Pa on the same stretch: E h^2 (d / h) per point.
  p.areaForm = true;
  p.k[0] = {3e4, 0.0, 0.0};
  const Eigen::VectorXd fa = force(AxialSpringModel(cube, p), x);
  EXPECT_NEAR(fa[3 * 7], -3e4 * h * h * (d / h) / 4, 1e-9);
}

TEST(AdamssSprings, AxialForceIsTheEnergyGradientAndStiffnessItsDerivative) {
  std::mt19937 rng(21);
  const Mesh tets = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const Mesh hexes = springJitteredHexes(rng);
  for (const Mesh* mesh : {&tets, &hexes})
    for (bool area : {false, true}) {
      SCOPED_TRACE(std::string(mesh->hexes.empty() ? "tets" : "hexes") + (area ? ", area" : ""));
      const AxialSpringModel model(*mesh, cubicAxial(area));
      const Eigen::VectorXd x = perturbed(*mesh, 8e-4, rng);
      const Eigen::VectorXd f = force(model, x);
      EXPECT_LT(relDiff(f, Eigen::VectorXd(-fdGradient(model, x, 1e-8))), 1e-6);
      const Eigen::MatrixXd K = denseStiffness(model, *mesh, x);
      EXPECT_LT(relDiff(K, fdForceJacobian(model, x, 1e-8)), 1e-6);
      EXPECT_LT(relDiff(Eigen::MatrixXd(K.transpose()), K), 1e-12);
      const Eigen::VectorXd d = perturbed(*mesh, 1.0, rng) - restVector(*mesh);
      Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
      model.addStiffnessTimes(x, d, 1.0, Kd);
      EXPECT_LT(relDiff(Kd, Eigen::VectorXd(K * d)), 1e-12);
      EXPECT_LT(springNetForce(f).norm(), 1e-12 * f.norm());
      EXPECT_LT(springNetMoment(x, f).norm(), 1e-12 * f.norm());
    }
}

TEST(AdamssSprings, GradientTorsionForceIsTheEnergyGradientWithNoNetForceOrMoment) {
  std::mt19937 rng(22);
  const Mesh tets = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const Mesh hexes = springJitteredHexes(rng);
  for (const Mesh* mesh : {&tets, &hexes})
    for (bool cosine : {false, true})
      for (bool area : {false, true}) {
        SCOPED_TRACE(std::string(mesh->hexes.empty() ? "tets" : "hexes") +
                     (cosine ? ", cosine" : ", angle") + (area ? ", area" : ""));
        const TorsionSpringModel model(*mesh, cubicTorsion(cosine, true, area));
        EXPECT_TRUE(model.hasEnergy());
        const Eigen::VectorXd x = perturbed(*mesh, 8e-4, rng);
        const Eigen::VectorXd f = force(model, x);
        EXPECT_LT(relDiff(f, Eigen::VectorXd(-fdGradient(model, x, 1e-8))), 1e-6);
        EXPECT_LT(springNetForce(f).norm(), 1e-12 * f.norm());
        EXPECT_LT(springNetMoment(x, f).norm(), 1e-12 * f.norm() * 0.01);
      }
}

// The gradient form's analytic stiffness (the Hessian of the energy in the axes, Eq. 2.29 to
// the nodes) against the finite-difference Jacobian of the force, K d against K, symmetry; the
// printed form has none.
TEST(AdamssSprings, GradientTorsionStiffnessIsTheForceDerivative) {
  std::mt19937 rng(24);
  const Mesh tets = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const Mesh hexes = springJitteredHexes(rng);
  for (const Mesh* mesh : {&tets, &hexes})
    for (bool cosine : {false, true})
      for (bool area : {false, true}) {
        SCOPED_TRACE(std::string(mesh->hexes.empty() ? "tets" : "hexes") +
                     (cosine ? ", cosine" : ", angle") + (area ? ", area" : ""));
        const TorsionSpringModel model(*mesh, cubicTorsion(cosine, true, area));
        ASSERT_TRUE(model.hasStiffness());
        const Eigen::VectorXd x = perturbed(*mesh, 8e-4, rng);
        const Eigen::MatrixXd K = denseStiffness(model, *mesh, x);
        EXPECT_LT(relDiff(K, fdForceJacobian(model, x, 1e-8)), 1e-6);
        EXPECT_LT(relDiff(Eigen::MatrixXd(K.transpose()), K), 1e-12);
        const Eigen::VectorXd d = perturbed(*mesh, 1.0, rng) - restVector(*mesh);
        Eigen::VectorXd Kd = Eigen::VectorXd::Zero(x.size());
        model.addStiffnessTimes(x, d, 1.0, Kd);
        EXPECT_LT(relDiff(Kd, Eigen::VectorXd(K * d)), 1e-12);
        // At rest the forces vanish: K is psi' grad theta grad theta^T, positive semi-definite.
        const Eigen::MatrixXd K0 = denseStiffness(model, *mesh, restVector(*mesh));
        EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(-K0).eigenvalues().minCoeff(),
                  -1e-9 * K0.norm());
      }
  EXPECT_FALSE(TorsionSpringModel(tets, cubicTorsion(false, false, false)).hasStiffness());
}

// The printed torsion forces of one pair put -psi (|zeta_l| - |zeta_m|) zeta_hat_l x zeta_hat_m
// of moment on the element (the moment of the point forces: the distribution keeps it).
TEST(AdamssSprings, PrintedTorsionForcesHaveTheClosedFormMoment) {
  std::mt19937 rng(23);
  for (bool cosine : {false, true}) {
    const Mesh tet = randomTet(rng);
    TorsionSpringParameters p;
    p.cosine = cosine;
    p.k[0] = {0.7, 0.0, 0.0};  // the pair (fibre, sheet) only
    const TorsionSpringModel model(tet, p);
    EXPECT_FALSE(model.hasEnergy());
    const Eigen::VectorXd x = perturbed(tet, 1e-3, rng);
    const Eigen::VectorXd f = force(model, x);
    const AxisMesh axes = buildAxes(tet);
    const Eigen::Matrix3d zeta =
        axisVectors(intersectionPoints<4>(gatherNodes<4>(x, tet.tets[0]), axes.tetRest[0].C));
    const Eigen::Vector3d ul = zeta.col(0).normalized(), um = zeta.col(1).normalized();
    const Eigen::Matrix3d& B = tet.fibreFrame[0];
    const double rest = B.col(0).dot(B.col(1));
    const double theta = cosine ? ul.dot(um) - rest : std::acos(ul.dot(um)) - std::acos(rest);
    const Eigen::Vector3d expected =
        -0.7 * theta * (zeta.col(0).norm() - zeta.col(1).norm()) * ul.cross(um);
    EXPECT_LT(springNetForce(f).norm(), 1e-12 * f.norm());
    EXPECT_LT((springNetMoment(x, f) - expected).norm(), 1e-10 * expected.norm());
    EXPECT_GT(expected.norm(), 1e-3 * f.norm() * 1e-2);  // the moment is there
  }
}

TEST(AdamssSprings, NoForceAtRestAndInvariantUnderRigidMotion) {
  std::mt19937 rng(24);
  const Mesh mesh = boxMesh(2, 1, 1, 0.01, rng, 0.15);
  const AxialSpringModel axial(mesh, cubicAxial(true));
  const TorsionSpringModel printed(mesh, cubicTorsion(false, false, true));
  const TorsionSpringModel gradient(mesh, cubicTorsion(true, true, false));
  for (const ForceModel* model : std::initializer_list<const ForceModel*>{&axial, &printed, &gradient}) {
    SCOPED_TRACE(model->name());
    const Eigen::VectorXd x = perturbed(mesh, 8e-4, rng);
    const Eigen::VectorXd f = force(*model, x);
    EXPECT_LT(force(*model, restVector(mesh)).lpNorm<Eigen::Infinity>(),
              1e-10 * f.lpNorm<Eigen::Infinity>());
    const Eigen::Matrix3d R = randomRotation(rng);
    const Eigen::VectorXd y = rigidMotion(x, R, Eigen::Vector3d(0.2, 0.1, -0.3));
    EXPECT_LT(relDiff(force(*model, y), rotateVectors(f, R)), 1e-10);
  }
}

Eigen::VectorXd frictionForce(const ForceModel& model, const Eigen::VectorXd& x,
                              const Eigen::VectorXd& v) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  model.addForce(x, v, f);
  return f;
}

// Friction: its velocity Jacobian against finite differences in v, dissipation f . v <= 0, no
// force for a rigid motion's velocities, and the three forms' coefficients in the ratios their
// definitions give on a cube (A_l = h^2, V0 / |zeta_l^0| = h^2: area = virtual_hexahedron).
TEST(AdamssSprings, FrictionVelocityJacobianDissipationAndRigidMotion) {
  std::mt19937 rng(25);
  const Mesh tets = boxMesh(2, 2, 1, 0.01, rng, 0.15);
  const Mesh hexes = springJitteredHexes(rng);
  using Form = AxisFrictionForm;
  for (const Mesh* mesh : {&tets, &hexes})
    for (Form form : {Form::kBourguignon, Form::kArea, Form::kVirtualHexahedron}) {
      const AxisFrictionModel model(*mesh, 3.0, form);
      const Eigen::VectorXd x = perturbed(*mesh, 8e-4, rng);
      const Eigen::VectorXd v = perturbed(*mesh, 0.05, rng) - restVector(*mesh);
      const Eigen::VectorXd f = frictionForce(model, x, v);
      EXPECT_LT(f.dot(v), 0.0);
      // Linear in v: the Jacobian is exact, and C v = f.
      const SparsePattern pattern = meshPattern(*mesh);
      SparseMatrix C = pattern.zeroMatrix();
      model.addVelocityJacobian(x, v, 1.0, pattern, C);
      EXPECT_LT(relDiff(Eigen::VectorXd(C * v), f), 1e-12);
      const Eigen::VectorXd dv = perturbed(*mesh, 0.05, rng) - restVector(*mesh);
      EXPECT_LT(relDiff(Eigen::VectorXd(frictionForce(model, x, v + dv) - f),
                        Eigen::VectorXd(C * dv)), 1e-12);
      const Eigen::MatrixXd dense(C);
      EXPECT_LT(relDiff(Eigen::MatrixXd(dense.transpose()), dense), 1e-12);
      EXPECT_LT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(dense).eigenvalues().maxCoeff(),
                1e-12 * dense.norm());
      // A rigid motion's velocities, w x x + c, change no axis length.
      const Eigen::Vector3d w(0.3, -1.2, 0.7), c(0.1, 0.2, -0.05);
      Eigen::VectorXd rigid(x.size());
      for (int n = 0; n < x.size() / 3; ++n) rigid.segment<3>(3 * n) = w.cross(x.segment<3>(3 * n)) + c;
      EXPECT_LT(frictionForce(model, x, rigid).norm(), 1e-12 * f.norm());
    }
  const double h = 0.01;
  const Mesh cube = boxGrid(2, 2, 2, Eigen::Vector3d(h, h, h), TetSplit::kNone);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(3 * cube.numNodes());
  for (int n = 0; n < cube.numNodes(); ++n)
    if (cube.rest(0, n) > 0.5 * h) v[3 * n] = 0.1;
  const Eigen::VectorXd x = restVector(cube);
  const Eigen::VectorXd plain = frictionForce(AxisFrictionModel(cube, 3.0, Form::kBourguignon), x, v);
  EXPECT_NEAR(plain[3 * 7], -3.0 * 0.1 / 4, 1e-12);
  EXPECT_LT(relDiff(frictionForce(AxisFrictionModel(cube, 3.0, Form::kArea), x, v), Eigen::VectorXd(h * h * plain)), 1e-12);
  EXPECT_LT(relDiff(frictionForce(AxisFrictionModel(cube, 3.0, Form::kVirtualHexahedron), x, v),
                    Eigen::VectorXd(h * h * plain)), 1e-12);
}

// Bourguignon's volume springs with the restoring sign: an element grown about its barycentre
// is pulled back (sum f_i . xi_i < 0), a shrunk one pushed out; the gradient form is the
// gradient of its energy with no net force; the printed form has a net force on an irregular
// element; the hex damping opposes a radial velocity and ignores a translation.
TEST(AdamssSprings, VolumeSpringsRestoreTheVolume) {
  std::mt19937 rng(26);
  const Mesh tets = boxMesh(2, 1, 1, 0.01, rng, 0.15);
  const Mesh hexes = springJitteredHexes(rng);
  for (const Mesh* mesh : {&tets, &hexes}) {
    SCOPED_TRACE(mesh->hexes.empty() ? "tets" : "hexes");
    for (bool gradient : {false, true}) {
      const VolumeSpringModel model(*mesh, {50.0, 0.0, gradient});
      const Eigen::Vector3d centre = mesh->rest.rowwise().mean();
      for (double scale : {1.1, 0.9}) {
        Eigen::VectorXd x = restVector(*mesh);
        for (int n = 0; n < mesh->numNodes(); ++n)
          x.segment<3>(3 * n) = centre + scale * (mesh->rest.col(n) - centre);
        const Eigen::VectorXd f = force(model, x);
        double work = 0.0;  // f . (x - centre) over the nodes: < 0 pulls in, > 0 pushes out
        for (int n = 0; n < mesh->numNodes(); ++n) work += f.segment<3>(3 * n).dot(x.segment<3>(3 * n) - centre);
        EXPECT_LT(scale > 1 ? work : -work, 0.0) << "scale " << scale;
      }
      const Eigen::VectorXd x = perturbed(*mesh, 8e-4, rng);
      const Eigen::VectorXd f = force(model, x);
      if (gradient) {
        EXPECT_LT(relDiff(f, Eigen::VectorXd(-fdGradient(model, x, 1e-8))), 1e-6);
        EXPECT_LT(springNetForce(f).norm(), 1e-12 * f.norm());
        EXPECT_LT(springNetMoment(x, f).norm(), 1e-12 * f.norm() * 0.01);
      } else {
        EXPECT_GT(springNetForce(f).norm(), 1e-3 * f.norm());
      }
    }
  }
  const VolumeSpringModel damped(hexes, {50.0, 2.0, true});
  const Eigen::VectorXd x = restVector(hexes);
  Eigen::VectorXd v = Eigen::VectorXd::Zero(x.size());
  for (int n = 0; n < hexes.numNodes(); ++n) v.segment<3>(3 * n) = Eigen::Vector3d(0.3, -0.1, 0.2);
  Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
  damped.addForce(x, v, f);
  EXPECT_LT(f.norm(), 1e-12);
  v = x;  // a uniform expansion rate about the origin
  f.setZero();
  damped.addForce(x, v, f);
  EXPECT_LT(f.dot(v), 0.0);
}

}  // namespace
}  // namespace adamss
}  // namespace tt
