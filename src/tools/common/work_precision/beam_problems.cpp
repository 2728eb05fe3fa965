// The beam problems of bench_work_precision (problem.h): the cantilever's static deflection and
// free vibration against Euler-Bernoulli, and the two large-deformation problems (the beam
// under full gravity, the spindle pulled) against a Radau IIA reference.
#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <map>

#include "common/bench_support.h"
#include "common/muscle_scene.h"
#include "common/work_precision/problem.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace work_precision {
namespace {

// 1. Small deflection under a body load, run to steady state with damping.
class CantileverStatic : public Problem {
 public:
  CantileverStatic() {
    name = "cantilever_static";
    isStatic = true;
    omegaBeam_ = beam_.firstOmega();
    damping_ = 2.0 * omegaBeam_;  // critical for the first mode
    duration = 2.0;               // 20 / omega_1: the damped transient is below 1e-8
    sampleInterval = 0.25;
    bodySize = lengthScale = beam_.length;
    velocityScale = beam_.length * omegaBeam_;
    implicitSteps = {1.0, 0.5, 0.25, 0.125, 0.0625};
    stableStep = 2.0 / bench::restModes(*build("edge_length")).omega.maxCoeff();
    exact_ = beam_.tipDeflection(kGravity);
    facts = {{"tip_deflection_euler_bernoulli", exact_, "m", "q L^4 / (8 E I)"},
             {"load", kGravity, "m/s^2", "body load (1 % of gravity)"},
             {"damping", damping_, "1/s", "mass-proportional, 2 omega_1 (critical for mode 1)"},
             {"duration", duration, "s", "simulated time to steady state"},
             {"stable_step", stableStep, "s", "2 / omega_max of the mesh at rest"}};
  }
  std::unique_ptr<System> build(const std::string& model) const override {
    return beamSystem(beam_, model, kGravity, damping_);
  }
  void prepare(const std::vector<std::string>& models) override {
    for (const std::string& model : models) {
      auto s = build(model);
      Eigen::VectorXd x = s->mesh.rest.reshaped();
      const bool solved = staticEquilibrium(*s, x, 1e-14) != kNoEquilibrium;
      // Without a static solution the model's runs get no discrete error (NaN), not one
      // against Newton's last iterate.
      meshDeflection_[model] = solved ? tipDeflection(*s, x) : std::nan("");
      facts.push_back({"tip_deflection_mesh_" + model, meshDeflection_[model], "m",
                       solved ? "static solution of the mesh (Newton, sparse Cholesky)"
                              : "none: Newton from rest found no solution (a singular "
                                "factorisation, or no convergence in 50 iterations)"});
    }
  }
  Errors evaluate(const std::string& model, const Trajectory& run) const override {
    auto s = build(model);
    const double tip = tipDeflection(*s, run.x.back());
    return {relative(tip, exact_), relative(tip, meshDeflection_.at(model)), ""};
  }

 private:
  static constexpr double kGravity = 0.0981;
  double tipDeflection(const System& s, const Eigen::VectorXd& x) const {
    return -meanOf(x, s.mesh.rest, tipNodes(s.mesh, beam_.length)).z();
  }
  Beam beam_;
  double omegaBeam_ = 0.0, damping_ = 0.0, exact_ = 0.0;
  std::map<std::string, double> meshDeflection_;
};

// 2. Free vibration in the first bending mode of the mesh (0.1 mm at the tip, undamped).
class CantileverVibration : public Problem {
 public:
  CantileverVibration() {
    name = "cantilever_vibration";
    auto s = beamSystem(beam_, "edge_length", 0.0, 0.0);
    const bench::RestModes modes = bench::restModes(*s);
    pickBendingMode(*s, modes);
    const double period = 2.0 * kPi / omegaMesh_;
    duration = 1.5 * period;  // zero crossings at T/4, 3T/4, 5T/4
    sampleInterval = period / 64.0;
    bodySize = beam_.length;
    lengthScale = kAmplitude;
    velocityScale = kAmplitude * omegaMesh_;
    for (double divisions : {8, 16, 32, 64, 128}) implicitSteps.push_back(period / divisions);
    stableStep = 2.0 / modes.omega.maxCoeff();
    facts = {{"frequency_euler_bernoulli", beam_.firstOmega() / (2 * kPi), "Hz",
              "1.8751^2 / (2 pi) sqrt(E I / (rho A L^4))"},
             {"frequency_mesh", omegaMesh_ / (2 * kPi), "Hz", "lowest bending mode of the mesh"},
             {"amplitude", kAmplitude, "m", "initial tip displacement along the mode"},
             {"duration", duration, "s", "1.5 periods"},
             {"stable_step", stableStep, "s", "2 / omega_max of the mesh at rest"}};
  }
  std::unique_ptr<System> build(const std::string& model) const override {
    auto s = beamSystem(beam_, model, 0.0, 0.0);
    s->state.x = s->mesh.rest.reshaped() + shape_;
    return s;
  }
  Errors evaluate(const std::string& model, const Trajectory& run) const override;

 private:
  static constexpr double kAmplitude = 1e-4;
  // The lowest mode whose tip moves mostly along z, scaled to kAmplitude at the tip.
  void pickBendingMode(const System& s, const bench::RestModes& modes) {
    const std::vector<int> tip = tipNodes(s.mesh, beam_.length);
    const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, s.numNodes());
    for (int m = 0; m < modes.omega.size(); ++m) {
      const Eigen::Vector3d d = meanOf(modes.shapes.col(m), zero, tip);
      if (std::abs(d.z()) < std::abs(d.y())) continue;
      omegaMesh_ = modes.omega[m];
      direction_ = d.normalized();
      shape_ = modes.shapes.col(m) * (kAmplitude / d.norm());
      return;
    }
  }
  double tipAlongMode(const Eigen::VectorXd& x, const Eigen::Matrix3Xd& rest,
                      const std::vector<int>& tip) const {
    return direction_.dot(meanOf(x, rest, tip));
  }
  Beam beam_;
  double omegaMesh_ = 0.0;
  Eigen::Vector3d direction_;
  Eigen::VectorXd shape_;
};

// The zero of the cubic Hermite interpolant of (u0, du0) at 0 and (u1, du1) at h, by bisection.
double hermiteZero(double u0, double du0, double u1, double du1, double h) {
  auto u = [&](double s) {  // s in [0, 1]
    const double s2 = s * s, s3 = s2 * s;
    return (2 * s3 - 3 * s2 + 1) * u0 + (s3 - 2 * s2 + s) * h * du0 + (-2 * s3 + 3 * s2) * u1 +
           (s3 - s2) * h * du1;
  };
  double a = 0.0, b = 1.0;
  for (int it = 0; it < 60; ++it) {
    const double m = 0.5 * (a + b);
    if ((u(a) <= 0.0) == (u(m) <= 0.0)) a = m; else b = m;
  }
  return 0.5 * (a + b) * h;
}

Errors CantileverVibration::evaluate(const std::string& model, const Trajectory& run) const {
  auto s = build(model);
  const std::vector<int> tip = tipNodes(s->mesh, beam_.length);
  const Eigen::Matrix3Xd zero = Eigen::Matrix3Xd::Zero(3, s->numNodes());
  std::vector<double> crossings;
  for (size_t k = 1; k < run.t.size(); ++k) {
    const double u0 = tipAlongMode(run.x[k - 1], s->mesh.rest, tip);
    const double u1 = tipAlongMode(run.x[k], s->mesh.rest, tip);
    if ((u0 > 0.0) == (u1 > 0.0)) continue;
    const double du0 = direction_.dot(meanOf(run.v[k - 1], zero, tip));
    const double du1 = direction_.dot(meanOf(run.v[k], zero, tip));
    const double h = run.t[k] - run.t[k - 1];
    crossings.push_back(run.t[k - 1] + hermiteZero(u0, du0, u1, du1, h));
  }
  if (crossings.size() < 3) return {kNaN, kNaN, "fewer than 3 zero crossings"};
  const double frequency = 1.0 / (crossings[2] - crossings[0]);
  return {relative(frequency, beam_.firstOmega() / (2 * kPi)),
          relative(frequency, omegaMesh_ / (2 * kPi)), ""};
}

// --- large deformation dynamics against a Radau IIA reference -------------------------------

// Shared by the two large-deformation problems: the reference is edge_length (exact StVK) by
// Radau IIA at referenceTolerance; the models that are not StVK also get a reference of their
// own (for the discrete error). The reference's own accuracy: the run at 10x the tolerance.
class AgainstReference : public Problem {
 public:
  void prepare(const std::vector<std::string>& models) override {
    const Trajectory physics = reference("edge_length", referenceTolerance);
    const Trajectory looser = reference("edge_length", 10.0 * referenceTolerance);
    references_["physics"] = physics;
    scale_ = largestDisplacement(physics);
    facts.push_back({"reference_tolerance", referenceTolerance, "",
                     "Radau IIA relative tolerance of the references"});
    facts.push_back({"reference_accuracy", distance(looser, physics) / scale_, "",
                     "edge_length reference at 10x the tolerance vs the reference (relative)"});
    facts.push_back({"reference_displacement", scale_, "m", "largest node displacement of the reference"});
    for (const std::string& model : models)
      if (!sameAsStvk(model)) references_[model] = reference(model, referenceTolerance);
  }
  Errors evaluate(const std::string& model, const Trajectory& run) const override {
    const Trajectory& own = references_.at(sameAsStvk(model) ? "physics" : model);
    return {distance(run, references_.at("physics")) / scale_, distance(run, own) / scale_, ""};
  }

  // The models that evaluate the StVK force polynomial itself (Eq 31 and, with the corrected
  // sign of alpha, Eq 13 of Jeffrey, "A non-linear anisotropic Finite Element Method for
  // surgical simulation") share the edge_length reference; the linear model and the printed
  // Eq 5 sign get references of their own.
  static bool sameAsStvk(const std::string& model) {
    return model == "edge_length" || model == "edge_length_literal" || model == "stvk_displacement";
  }

  double referenceTolerance = 1e-10;  // the references' Radau IIA relative tolerance

 private:
  Trajectory reference(const std::string& model, double tol) const {
    auto s = build(model);
    RadauIIA radau(radauOptions(*this, tol));
    Trajectory t;
    t.t.push_back(0.0);
    t.x.push_back(s->state.x);
    const int frames = static_cast<int>(std::lround(duration / sampleInterval));
    for (int f = 1; f <= frames; ++f) {
      radau.advance(*s, sampleInterval);
      t.t.push_back(s->state.t);
      t.x.push_back(s->state.x);
    }
    return t;
  }
  double largestDisplacement(const Trajectory& t) const {
    double d = 0.0;
    for (const Eigen::VectorXd& x : t.x) d = std::max(d, nodeDistance(x, t.x.front()));
    return d;
  }
  static double nodeDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a - b).reshaped(3, a.size() / 3).colwise().norm().maxCoeff();
  }
  // Largest node distance at the run's sample times (which are reference sample times).
  double distance(const Trajectory& run, const Trajectory& ref) const {
    double d = 0.0;
    for (size_t k = 0; k < run.t.size(); ++k) {
      const size_t j = static_cast<size_t>(std::lround(run.t[k] / sampleInterval));
      if (j < ref.x.size()) d = std::max(d, nodeDistance(run.x[k], ref.x[j]));
    }
    return d;
  }
  std::map<std::string, Trajectory> references_;
  double scale_ = 1.0;
};

// 3a. The soft beam falling under full gravity (tip deflection of the order of its length).
class BeamLargeDeflection : public AgainstReference {
 public:
  BeamLargeDeflection() {
    name = "beam_large_deflection";
    duration = 0.5;
    sampleInterval = 0.01;
    bodySize = lengthScale = beam_.length;
    velocityScale = 1.0;
    implicitSteps = {0.02, 0.01, 0.005, 0.0025, 0.00125};
    stableStep = 2.0 / bench::restModes(*build("edge_length")).omega.maxCoeff();
    facts = {{"load", kGravity, "m/s^2", "gravity"},
             {"tip_deflection_euler_bernoulli", beam_.tipDeflection(kGravity), "m",
              "linear theory, far outside its range"},
             {"damping", kDamping, "1/s", "mass-proportional"},
             {"duration", duration, "s", ""},
             {"stable_step", stableStep, "s", "2 / omega_max of the mesh at rest"}};
  }
  std::unique_ptr<System> build(const std::string& model) const override {
    return beamSystem(beam_, model, kGravity, kDamping);
  }

 private:
  static constexpr double kGravity = 9.81, kDamping = 5.0;
  Beam beam_;
};

// 3b. The spindle muscle (training-scene resolution) with a belly node pulled 1 cm and back.
class SpindlePull : public AgainstReference {
 public:
  SpindlePull() {
    name = "spindle_pull";
    duration = muscle_scene::kEnd;
    sampleInterval = 0.01;
    bodySize = 0.1;
    lengthScale = muscle_scene::kPull;
    velocityScale = 0.1;
    implicitSteps = {0.02, 0.01, 0.005, 0.0025, 0.00125};
    auto s = build("edge_length");
    stableStep = 2.0 / bench::restModes(*s).omega.maxCoeff();
    facts = {{"nodes", static_cast<double>(s->numNodes()), "", ""},
             {"tets", static_cast<double>(s->mesh.numTets()), "", ""},
             {"pull", muscle_scene::kPull, "m", "belly node, out over 0.1 s and back over 0.1 s"},
             {"duration", duration, "s", ""},
             {"stable_step", stableStep, "s", "2 / omega_max of the mesh at rest"}};
  }
  std::unique_ptr<System> build(const std::string& model) const override {
    SpindleShape shape;
    shape.segments = 10;
    shape.layers = 17;
    Mesh mesh = spindleMuscle(shape);
    const std::vector<Material> materials = {
        Material::transverselyIsotropic(20e3, 0.4, 150e3, 0.4, 1060.0)};
    const int belly = muscle_scene::bellyNode(mesh);
    auto s = std::make_unique<System>(mesh, materials);
    s->damping = muscle_scene::kDampingRate * s->mass;
    s->models.push_back(makeElasticModel(model, s->mesh, s->materials));
    s->controlled.push_back(
        {{belly},
         {{0.0, muscle_scene::kPeak, muscle_scene::kEnd},
          {Eigen::Vector3d::Zero(), Eigen::Vector3d(muscle_scene::kPull, 0, 0),
           Eigen::Vector3d::Zero()}}});
    s->updateConstraints();
    return s;
  }
};

}  // namespace

std::unique_ptr<Problem> makeCantileverStatic() { return std::make_unique<CantileverStatic>(); }

std::unique_ptr<Problem> makeCantileverVibration() {
  return std::make_unique<CantileverVibration>();
}

std::unique_ptr<Problem> makeBeamLargeDeflection(double referenceTolerance) {
  auto p = std::make_unique<BeamLargeDeflection>();
  p->referenceTolerance = referenceTolerance;
  return p;
}

std::unique_ptr<Problem> makeSpindlePull(double referenceTolerance) {
  auto p = std::make_unique<SpindlePull>();
  p->referenceTolerance = referenceTolerance;
  return p;
}

}  // namespace work_precision
}  // namespace tt
