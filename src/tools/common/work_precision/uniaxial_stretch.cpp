// The Adamss problem of bench_work_precision (problem.h): uniaxial stretch of a myocardium cube
// along its fibres ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.8.1), run
// dynamically by each integrator, for the two Adamss tissue presets (adamss_hunter,
// adamss_springs) at E = 10 kPa, where their stiffness is Table 2.1's and Table 2.2's, and
// nu = 0, where they have no volume term.
#include <Eigen/Core>
#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <map>

#include "common/bench_support.h"
#include "common/work_precision/problem.h"
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace work_precision {
namespace {

// 5. A 1 cm cube (2 x 2 x 2 cells, six tets each, mirrored), fibres along z, 1060 kg/m^3; the
// bottom face fixed, the top face moved 15 % up over 50 ms (lateral motion held) and held to
// 100 ms, mass-proportional damping 100 /s. Error: the nominal stress on the top face at the end
// (reaction force / rest area) against the Hunter law's uniaxial value lambda w_11'(E_11) at
// 15 % (the homogeneous state every mesh holds); discrete error: the largest difference of that
// stress from Radau IIA's at a tight tolerance on the same model over the samples, relative to
// the Hunter value. The explicit sweep's limit is 2 / omega_max at the 15 % stretch (the
// models stiffen: at rest it is several times longer).
class UniaxialStretch : public Problem {
 public:
  UniaxialStretch() {
    name = "uniaxial_stretch";
    models = {"adamss_hunter", "adamss_springs"};
    duration = 0.1;
    sampleInterval = 0.005;
    bodySize = lengthScale = kSize;
    velocityScale = kStrain * kSize / kRamp;
    implicitSteps = {0.01, 0.005, 0.0025, 0.00125, 0.000625};
    const double stretch = 1.0 + kStrain;
    stableStep = 1e9;
    for (const std::string& model : models) {
      auto s = build(model);
      Eigen::VectorXd x = s->mesh.rest.reshaped();
      for (int n = 0; n < s->numNodes(); ++n) x[3 * n + 2] *= stretch;
      stableStep = std::min(stableStep, 2.0 / omegaMaxAt(*s, x));
    }
    const HunterConstants k = HunterConstants::table21();
    exact_ = stretch * PoleZeroTerm{k.k[0], k.a[0], k.b[0]}.first(0.5 * (stretch * stretch - 1.0));
    facts = {{"stress_hunter", exact_, "Pa",
              "lambda w_11'((lambda^2 - 1) / 2) at 15 % (Eq. 2.153)"},
             {"damping", kDamping, "1/s", "mass-proportional"},
             {"duration", duration, "s", "50 ms ramp, then held"},
             {"stable_step", stableStep, "s", "2 / omega_max at 15 % stretch (both models)"}};
  }
  std::unique_ptr<System> build(const std::string& model) const override {
    Mesh mesh = boxGrid(3, 3, 3, Eigen::Vector3d::Constant(kSize), TetSplit::kSixMirrored);
    Eigen::Matrix3d frame;
    frame << Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY();
    mesh.fibreFrame.assign(mesh.numTets(), frame);
    for (int n = 0; n < mesh.numNodes(); ++n)
      if (mesh.rest(2, n) < 1e-12) mesh.nodeTags[n] = kFixedAll;
    auto s = std::make_unique<System>(mesh, std::vector<Material>{
                                                Material::isotropic(kYoung, 0.0, kDensity)});
    bench::addPreset(*s, model);
    s->damping = kDamping * s->mass;
    s->controlled.push_back(
        {topNodes(s->mesh),
         {{0.0, kRamp}, {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, kStrain * kSize)}}});
    s->updateConstraints();
    return s;
  }
  void prepare(const std::vector<std::string>& runModels) override {
    for (const std::string& model : runModels) {
      auto s = build(model);
      RadauIIA radau(radauOptions(*this, referenceTolerance));
      std::vector<double>& stress = reference_[model];
      stress.push_back(topStress(*s, s->state.x));
      const int frames = static_cast<int>(std::lround(duration / sampleInterval));
      for (int f = 0; f < frames; ++f) {
        radau.advance(*s, sampleInterval);
        stress.push_back(topStress(*s, s->state.x));
      }
      facts.push_back({"stress_reference_" + model, stress.back(), "Pa",
                       "end stress by Radau IIA at the reference tolerance"});
    }
  }
  Errors evaluate(const std::string& model, const Trajectory& run) const override {
    auto s = build(model);
    const std::vector<double>& reference = reference_.at(model);
    double discrete = 0.0;
    for (std::size_t k = 0; k < run.t.size(); ++k) {
      const std::size_t j = static_cast<std::size_t>(std::lround(run.t[k] / sampleInterval));
      if (j < reference.size())
        discrete = std::max(discrete, std::abs(topStress(*s, run.x[k]) - reference[j]));
    }
    return {relative(topStress(*s, run.x.back()), exact_), discrete / exact_, ""};
  }

  double referenceTolerance = 1e-9;

 private:
  static constexpr double kSize = 0.01, kStrain = 0.15, kRamp = 0.05;
  static constexpr double kDensity = 1060.0, kDamping = 100.0;
  static constexpr double kYoung = 10e3;  // the tissue presets' unscaled stiffness

  static std::vector<int> topNodes(const Mesh& mesh) {
    std::vector<int> nodes;
    for (int n = 0; n < mesh.numNodes(); ++n)
      if (mesh.rest(2, n) > kSize - 1e-12) nodes.push_back(n);
    return nodes;
  }
  // The force along z the clamps apply to the top face (minus the models' force there), over
  // the face's rest area.
  static double topStress(const System& s, const Eigen::VectorXd& x) {
    Eigen::VectorXd f = Eigen::VectorXd::Zero(x.size());
    const Eigen::VectorXd v = Eigen::VectorXd::Zero(x.size());
    for (const auto& m : s.models) m->addForce(x, v, f);
    double force = 0.0;
    for (int n : topNodes(s.mesh)) force -= f[3 * n + 2];
    return force / (kSize * kSize);
  }

  // Largest natural frequency at positions x (dense; free DOFs).
  static double omegaMaxAt(const System& s, const Eigen::VectorXd& x) {
    const Eigen::MatrixXd K = Eigen::MatrixXd(bench::negativeStiffness(s, x));
    Eigen::VectorXd scale = s.mass.cwiseSqrt().cwiseInverse();
    for (int d = 0; d < s.numDofs(); ++d)
      if (s.isConstrained[d]) scale[d] = 0.0;
    const Eigen::MatrixXd A = scale.asDiagonal() * K * scale.asDiagonal();
    const double largest =
        Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(A).eigenvalues().maxCoeff();
    return std::sqrt(std::max(0.0, largest));
  }

  double exact_ = 0.0;
  std::map<std::string, std::vector<double>> reference_;
};

}  // namespace

std::unique_ptr<Problem> makeUniaxialStretch(double referenceTolerance) {
  auto p = std::make_unique<UniaxialStretch>();
  p->referenceTolerance = referenceTolerance;
  return p;
}

}  // namespace work_precision
}  // namespace tt
