// The patch test of bench_work_precision (problem.h).
#include <Eigen/Core>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "common/bench_support.h"
#include "common/work_precision/problem.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace work_precision {
namespace {

// A 4 x 4 x 4-cell box (4 cm) with jittered interior nodes; the boundary nodes follow an
// affine map x = A X (ramped in over 0.05 s), the interior settles under damping and must
// land on the same map.
class PatchTest : public Problem {
 public:
  PatchTest() {
    name = "patch";
    mesh_ = jitteredBox();
    gradient_ << 0.08, 0.03, -0.02, 0.01, -0.05, 0.04, -0.03, 0.02, 0.06;
    auto s = build("edge_length");
    const bench::RestModes modes = bench::restModes(*s);
    damping_ = 2.0 * modes.omega.minCoeff();
    duration = std::ceil((kRamp + 25.0 / modes.omega.minCoeff()) / 0.01) * 0.01;
    sampleInterval = duration / 8.0;
    bodySize = lengthScale = kSize;
    velocityScale = kSize / kRamp;
    for (double divisions : {2, 4, 8, 16, 32}) implicitSteps.push_back(duration / divisions);
    stableStep = 2.0 / modes.omega.maxCoeff();
    facts = {{"tets", static_cast<double>(mesh_.numTets()), "", "jittered 4 x 4 x 4-cell box"},
             {"damping", damping_, "1/s", "mass-proportional, 2 omega_min"},
             {"duration", duration, "s", "ramp 0.05 s, then 25 / omega_min"},
             {"stable_step", stableStep, "s", "2 / omega_max of the mesh at rest"}};
  }
  std::unique_ptr<System> build(const std::string& model) const override {
    const std::vector<Material> materials = {
        Material::transverselyIsotropic(3e4, 0.3, 1.2e5, 0.35, 1060.0)};
    auto s = std::make_unique<System>(mesh_, materials);
    s->models.push_back(makeElasticModel(model, s->mesh, s->materials));
    s->damping = damping_ * s->mass;
    for (int n = 0; n < mesh_.numNodes(); ++n)
      if (onBoundary(mesh_.rest.col(n)))
        s->controlled.push_back(
            {{n}, {{0.0, kRamp}, {Eigen::Vector3d::Zero(), gradient_ * mesh_.rest.col(n)}}});
    s->updateConstraints();
    return s;
  }
  Errors evaluate(const std::string&, const Trajectory& run) const override {
    double error = 0.0, scale = 0.0;
    for (int n = 0; n < mesh_.numNodes(); ++n) {
      const Eigen::Vector3d affine = mesh_.rest.col(n) + gradient_ * mesh_.rest.col(n);
      error = std::max(error, (run.x.back().segment<3>(3 * n) - affine).norm());
      scale = std::max(scale, (gradient_ * mesh_.rest.col(n)).norm());
    }
    return {error / scale, error / scale, ""};
  }

 private:
  static constexpr double kSize = 0.04, kRamp = 0.05;
  static bool onBoundary(const Eigen::Vector3d& p) {
    return (p.array() < 1e-9).any() || (p.array() > kSize - 1e-9).any();
  }
  static Mesh jitteredBox() {
    Mesh m = boxGrid(5, 5, 5, Eigen::Vector3d(kSize, kSize, kSize), TetSplit::kSixMirrored);
    std::mt19937 rng(7);
    std::uniform_real_distribution<double> jitter(-0.2 * kSize / 4, 0.2 * kSize / 4);
    for (int n = 0; n < m.numNodes(); ++n)
      if (!onBoundary(m.rest.col(n)))
        for (int i = 0; i < 3; ++i) m.rest(i, n) += jitter(rng);
    const Eigen::Vector3d fibre = Eigen::Vector3d(1, 2, 0.5).normalized();
    const Eigen::Vector3d across = fibre.unitOrthogonal();
    Eigen::Matrix3d frame;
    frame << fibre, across, fibre.cross(across);
    m.fibreFrame.assign(m.numTets(), frame);
    return m;
  }
  Mesh mesh_;
  Eigen::Matrix3d gradient_;
  double damping_ = 0.0;
};

}  // namespace

std::unique_ptr<Problem> makePatchTest() { return std::make_unique<PatchTest>(); }

}  // namespace work_precision
}  // namespace tt
