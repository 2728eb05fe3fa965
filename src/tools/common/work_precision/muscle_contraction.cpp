// The muscle problem of bench_work_precision (problem.h): a block of muscle_groups tissue (the
// teran_muscle law, M. Bao, "Derivation of Quasistatics and Landmark Optimization for
// Muscles", Sec. 4.3, Eq. 10) contracting to its equilibrium at activation 0.5, for the muscle
// tissue presets (teran_muscle, teran_muscle_inversion, teran_muscle_inversion_psd). A static
// problem: the quasistatic solver finds the equilibrium in one frame, the dynamic integrators
// run the damped motion to rest.
#include <Eigen/Core>
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>
#include <string>

#include "common/bench_support.h"
#include "common/work_precision/problem.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace work_precision {
namespace {

// 6. A 2 x 2 x 1 cm block (4 x 4 x 2 cells, 192 tets), fibres along x, the base clamped, E 30
// kPa / nu 0.45 through the law's constants (the presets' scaling), 1060 kg/m^3, the one
// muscle switched on at activation 0.5 at t = 0 and held; mass-proportional damping 2 omega_1
// (critical for the lowest mode at rest), run for 20 / omega_1. Error (and discrete error):
// the largest node distance of the end state from the equilibrium of the same model, relative
// to the largest node displacement of that equilibrium. The reference equilibrium: the bench's
// own Newton with a sparse Cholesky solve (no line search, not the solver under test), the
// activation raised to 0.5 in ten equal steps.
class MuscleContraction : public Problem {
 public:
  MuscleContraction() {
    name = "muscle_contraction";
    models = {"teran_muscle", "teran_muscle_inversion", "teran_muscle_inversion_psd"};
    isStatic = true;
    auto s = build("teran_muscle");
    const bench::RestModes modes = bench::restModes(*s);
    omega1_ = modes.omega.minCoeff();
    damping_ = 2.0 * omega1_;
    duration = 20.0 / omega1_;
    sampleInterval = duration / 8.0;
    bodySize = kSize;
    lengthScale = 1e-3;
    velocityScale = lengthScale * omega1_;
    for (double divisions : {2, 4, 8, 16, 32}) implicitSteps.push_back(duration / divisions);
    stableStep = 2.0 / modes.omega.maxCoeff();
    facts = {{"tets", static_cast<double>(s->mesh.numTets()), "", "4 x 4 x 2 cells of a 2 x 2 x 1 cm block"},
             {"activation", kActivation, "", "of the one muscle, from t = 0"},
             {"omega_1", omega1_, "rad/s", "lowest natural frequency at rest"},
             {"damping", damping_, "1/s", "mass-proportional, 2 omega_1"},
             {"duration", duration, "s", "20 / omega_1"},
             {"stable_step", stableStep, "s", "2 / omega_max of the mesh at rest"}};
  }
  std::unique_ptr<System> build(const std::string& model) const override {
    Mesh mesh = boxGrid(5, 5, 3, Eigen::Vector3d(2 * kSize, 2 * kSize, kSize), TetSplit::kSixMirrored);
    mesh.fillDefaults();
    for (int n = 0; n < mesh.numNodes(); ++n)
      if (mesh.rest(2, n) < 1e-12) mesh.nodeTags[n] = kFixedAll;
    auto s = std::make_unique<System>(
        mesh, std::vector<Material>{Material::isotropic(kYoung, kPoisson, kDensity)});
    bench::addPreset(*s, model);
    s->damping = damping_ * s->mass;
    s->updateConstraints();
    return s;
  }
  void prepare(const std::vector<std::string>& runModels) override {
    for (const std::string& model : runModels) {
      Eigen::VectorXd x;
      const int newton = reference(model, x);
      auto s = build(model);
      const double largest = nodeDistance(x, s->mesh.rest.reshaped());
      reference_[model] = x;
      scale_[model] = largest;
      Eigen::VectorXd f;
      s->computeForce(x, Eigen::VectorXd::Zero(x.size()), f);
      s->zeroConstrained(f);
      facts.push_back({"reference_displacement_" + model, largest, "m",
                       "largest node displacement of the equilibrium (Newton, sparse Cholesky, " +
                           std::to_string(newton) + " iterations)"});
      facts.push_back({"reference_residual_" + model, f.norm(), "N",
                       "|f| over the free DOFs at the reference equilibrium"});
    }
  }
  Errors evaluate(const std::string& model, const Trajectory& run) const override {
    const double e = nodeDistance(run.x.back(), reference_.at(model)) / scale_.at(model);
    return {e, e, ""};
  }

 private:
  static constexpr double kSize = 0.01, kYoung = 30e3, kPoisson = 0.45, kDensity = 1060.0;
  static constexpr double kActivation = 0.5;  // the presets' activation

  static double nodeDistance(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
    return (a - b).reshaped(3, a.size() / 3).colwise().norm().maxCoeff();
  }
  // The equilibrium at kActivation by continuation in the activation; returns the Newton
  // iterations in all.
  int reference(const std::string& model, Eigen::VectorXd& x) const {
    auto s = build(model);
    auto* muscle = dynamic_cast<ActivatedForceModel*>(s->models.front().get());
    x = s->mesh.rest.reshaped();
    int iterations = 0;
    for (int k = 1; k <= 10; ++k) {
      muscle->setActivation(0, kActivation * k / 10.0);
      const int taken = staticEquilibrium(*s, x, 1e-14);
      if (taken == kNoEquilibrium)
        throw std::runtime_error("muscle_contraction: no reference equilibrium for " + model +
                                 " at activation step " + std::to_string(k) + " of 10");
      iterations += taken;
    }
    return iterations;
  }

  double omega1_ = 0.0, damping_ = 0.0;
  std::map<std::string, Eigen::VectorXd> reference_;
  std::map<std::string, double> scale_;
};

}  // namespace

std::unique_ptr<Problem> makeMuscleContraction() { return std::make_unique<MuscleContraction>(); }

}  // namespace work_precision
}  // namespace tt
