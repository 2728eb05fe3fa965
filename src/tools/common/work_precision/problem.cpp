#include "common/work_precision/problem.h"

#include <Eigen/SparseCholesky>
#include <cmath>
#include <stdexcept>

#include "common/bench_support.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace work_precision {

const std::vector<std::string>& problemNames() {
  static const std::vector<std::string> names = {
      "cantilever_static", "cantilever_vibration", "beam_large_deflection", "spindle_pull",
      "patch",             "uniaxial_stretch",     "muscle_contraction"};
  return names;
}

std::unique_ptr<Problem> makeProblem(const std::string& name, bool quick) {
  const double looser = 1e-6;  // the references of a quick run
  if (name == "cantilever_static") return makeCantileverStatic();
  if (name == "cantilever_vibration") return makeCantileverVibration();
  if (name == "beam_large_deflection") return makeBeamLargeDeflection(quick ? looser : 1e-10);
  if (name == "spindle_pull") return makeSpindlePull(quick ? looser : 1e-10);
  if (name == "patch") return makePatchTest();
  if (name == "uniaxial_stretch") return makeUniaxialStretch(quick ? looser : 1e-9);
  if (name == "muscle_contraction") return makeMuscleContraction();
  throw std::invalid_argument("no work-precision problem named '" + name + "'");
}

RadauOptions radauOptions(const Problem& p, double tol) {
  RadauOptions o;
  o.absTol = tol * p.lengthScale;
  o.absTolVelocity = tol * p.velocityScale;
  o.relTol = tol;
  o.initialStep = std::min(1e-4, p.sampleInterval);
  return o;
}

std::string blowUp(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                   const Eigen::VectorXd& rest, double bodySize) {
  if (!x.allFinite() || !v.allFinite()) return "non-finite state";
  if ((x - rest).lpNorm<Eigen::Infinity>() > 10.0 * bodySize)
    return "blow-up: a node moved more than 10 body sizes";
  return "";
}

std::unique_ptr<System> beamSystem(const Beam& beam, const std::string& model,
                                   double gravity, double dampingRate) {
  Mesh mesh = cantileverBeam(beam.length, beam.width, 10 * beam.cellsAcross, beam.cellsAcross);
  const std::vector<Material> materials = {
      Material::isotropic(beam.young, beam.poisson, beam.density)};
  auto s = std::make_unique<System>(mesh, materials);
  s->models.push_back(makeElasticModel(model, s->mesh, s->materials));
  if (gravity > 0.0)
    s->models.push_back(std::make_unique<GravityModel>(s->mass, Eigen::Vector3d(0, 0, -gravity)));
  s->damping = dampingRate * s->mass;
  return s;
}

std::vector<int> tipNodes(const Mesh& mesh, double length) {
  std::vector<int> nodes;
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (std::abs(mesh.rest(0, n) - length) < 1e-12) nodes.push_back(n);
  return nodes;
}

Eigen::Vector3d meanOf(const Eigen::VectorXd& x, const Eigen::Matrix3Xd& rest,
                       const std::vector<int>& nodes) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (int n : nodes) sum += x.segment<3>(3 * n) - rest.col(n);
  return sum / static_cast<double>(nodes.size());
}

int staticEquilibrium(const System& s, Eigen::VectorXd& x, double tolerance) {
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(s.numDofs());
  Eigen::VectorXd f;
  for (int it = 1; it <= 50; ++it) {
    s.computeForce(x, v, f);
    s.zeroConstrained(f);
    Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(bench::negativeStiffness(s, x));
    if (solver.info() != Eigen::Success) return kNoEquilibrium;
    const Eigen::VectorXd dx = solver.solve(f);
    if (!dx.allFinite()) return kNoEquilibrium;
    x += dx;
    if (dx.lpNorm<Eigen::Infinity>() < tolerance) return it;
  }
  return kNoEquilibrium;
}

double relative(double value, double exact) { return std::abs(value - exact) / std::abs(exact); }

}  // namespace work_precision
}  // namespace tt
