#include "tissue_trainer/core/integrate/specimen_loading.h"

#include <Eigen/Geometry>
#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace tt {

namespace {

const char* axisName(int axis) { return axis == 0 ? "x" : axis == 1 ? "y" : "z"; }

// Rest area of the boundary triangles with every node in `onFace`.
double faceArea(const Mesh& mesh, const std::vector<std::uint8_t>& onFace) {
  double area = 0.0;
  for (const Triangle& t : mesh.surface)
    if (onFace[t[0]] && onFace[t[1]] && onFace[t[2]])
      area += 0.5 * (mesh.rest.col(t[1]) - mesh.rest.col(t[0]))
                        .cross(mesh.rest.col(t[2]) - mesh.rest.col(t[0]))
                        .norm();
  return area;
}

// The force of the models that are not body loads at x (v = 0).
void internalForce(const System& system, const Eigen::VectorXd& x, Eigen::VectorXd& f) {
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(x.size());
  f.setZero(x.size());
  for (const auto& model : system.models)
    if (!model->isBodyLoad()) model->addForce(x, v, f);
}

double internalEnergy(const System& system, const Eigen::VectorXd& x) {
  double energy = 0.0;
  for (const auto& model : system.models)
    if (!model->isBodyLoad()) energy += model->energy(x);
  return energy;
}

std::string formatted(const char* what, double value) {
  char text[64];
  std::snprintf(text, sizeof text, "%s %.6g", what, value);
  return text;
}

// The lower face fixed, the upper face controlled: its offset is set per step. Moves the
// upper face along `along` in `steps` equal steps up to maxDisplacement, each to equilibrium;
// afterStep(i) reads the state of step i = 0..steps.
SpecimenRun moveUpperFace(System& system, const SpecimenFaces& faces, int normal, int along,
                          double maxDisplacement, int steps, const EquilibriumParams& params,
                          const char* measure, double maxMeasure,
                          const std::function<void(int)>& afterStep) {
  std::fill(system.mesh.nodeTags.begin(), system.mesh.nodeTags.end(), 0);
  for (int n : faces.lower) system.mesh.nodeTags[n] = kFixedAll;
  system.controlled.assign(1, ControlledSet{faces.upper, {}});
  PrescribedPath& path = system.controlled[0].path;
  path.times = {0.0};
  path.offsets = {Eigen::Vector3d::Zero()};
  system.updateConstraints();

  State& s = system.state;
  s.x = Eigen::Map<const Eigen::VectorXd>(system.mesh.rest.data(), system.numDofs());
  s.v.setZero(system.numDofs());
  const double lowest = system.mesh.rest.row(normal).minCoeff();
  EquilibriumSolver solver(params);
  SpecimenRun run;
  double previous = 0.0;
  for (int i = 0; i <= steps; ++i) {
    const double displacement = maxDisplacement * i / steps;
    path.offsets[0] = Eigen::Vector3d::Zero();
    path.offsets[0][along] = displacement;
    for (int n = 0; n < system.numNodes(); ++n)
      s.x[3 * n + along] += (displacement - previous) *
                            (system.mesh.rest(normal, n) - lowest) / faces.height;
    previous = displacement;
    system.prescribe(0.0, s.x, s.v);
    run.last = solver.solve(system, s.x);
    if (!run.last.converged()) {
      run.ok = false;
      run.failure = "equilibrium failed at " + formatted(measure, maxMeasure * i / steps) +
                    " (step " + std::to_string(i) + " of " + std::to_string(steps) + "): " +
                    run.last.reason;
      return run;
    }
    afterStep(i);
  }
  return run;
}

void checkAxis(int axis) {
  if (axis < 0 || axis > 2) throw std::invalid_argument("specimen: the axis must be 0, 1 or 2");
}

}  // namespace

SpecimenFaces specimenFaces(const Mesh& mesh, int axis) {
  checkAxis(axis);
  SpecimenFaces faces;
  const double low = mesh.rest.row(axis).minCoeff(), high = mesh.rest.row(axis).maxCoeff();
  faces.height = high - low;
  if (!(faces.height > 0.0))
    throw std::invalid_argument(std::string("the mesh has no extent along ") + axisName(axis));
  const double tolerance = 1e-6 * faces.height;
  std::vector<std::uint8_t> onLower(mesh.numNodes(), 0), onUpper(mesh.numNodes(), 0);
  for (int n = 0; n < mesh.numNodes(); ++n) {
    if (mesh.rest(axis, n) <= low + tolerance) {
      faces.lower.push_back(n);
      onLower[n] = 1;
    } else if (mesh.rest(axis, n) >= high - tolerance) {
      faces.upper.push_back(n);
      onUpper[n] = 1;
    }
  }
  faces.lowerArea = faceArea(mesh, onLower);
  faces.upperArea = faceArea(mesh, onUpper);
  for (const auto& [area, end] : {std::make_pair(faces.lowerArea, "lower"),
                                  std::make_pair(faces.upperArea, "upper")})
    if (!(area > 0.0))
      throw std::invalid_argument(std::string("the mesh does not end in a flat face normal to ") +
                                  axisName(axis) + " at its " + end + " end");
  return faces;
}

SpecimenRun stretchSpecimen(System& system, int axis, double maxStrain, int steps,
                            const EquilibriumParams& params,
                            const std::function<void(const StretchRow&)>& row) {
  if (steps < 1 || !(maxStrain > -1.0))
    throw std::invalid_argument("stretch: steps >= 1 and a strain above -1 are needed");
  const SpecimenFaces faces = specimenFaces(system.mesh, axis);
  Eigen::VectorXd f;
  return moveUpperFace(system, faces, axis, axis, maxStrain * faces.height, steps, params,
                       "strain", maxStrain, [&](int i) {
                         internalForce(system, system.state.x, f);
                         StretchRow r;
                         r.strain = maxStrain * i / steps;
                         r.stretch = 1.0 + r.strain;
                         for (int n : faces.upper) r.force -= f[3 * n + axis];
                         r.stress = r.force / faces.upperArea;
                         row(r);
                       });
}

SpecimenRun shearSpecimen(System& system, int normal, int direction, double maxShear, int steps,
                          const EquilibriumParams& params,
                          const std::function<void(const ShearRow&)>& row) {
  checkAxis(direction);
  if (steps < 1 || !std::isfinite(maxShear) || direction == normal)
    throw std::invalid_argument("shear: steps >= 1, a finite shear and a direction other than "
                                "the plane normal are needed");
  const SpecimenFaces faces = specimenFaces(system.mesh, normal);
  Eigen::VectorXd f, previousF, previousX;
  double work = 0.0;
  return moveUpperFace(system, faces, normal, direction, maxShear * faces.height, steps, params,
                       "shear", maxShear, [&](int i) {
                         const Eigen::VectorXd& x = system.state.x;
                         internalForce(system, x, f);
                         // Eq. 2.151 with the force on the controlled nodes from outside, the
                         // reaction -f: the work done on the specimen.
                         if (i > 0)
                           for (int n : faces.upper)
                             work -= (x.segment<3>(3 * n) - previousX.segment<3>(3 * n))
                                         .dot(f.segment<3>(3 * n) + previousF.segment<3>(3 * n)) /
                                     2.0;
                         previousX = x;
                         previousF = f;
                         ShearRow r;
                         r.shear = maxShear * i / steps;
                         r.work = work;
                         r.energy = internalEnergy(system, x);
                         row(r);
                       });
}

}  // namespace tt
