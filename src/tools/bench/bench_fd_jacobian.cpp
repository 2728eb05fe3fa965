// Cost of backward Euler's Jacobians per step: the analytic stiffness and velocity Jacobian
// against forward differences of the total force (solve/finite_difference_jacobian.h),
// one DOF per force evaluation and coloured, on neo-Hookean box grids (6 tets per cell) of
// about 1e3 and 1e4 tets, strained 5 % in shear with a 1 % jitter, moving, with per-DOF
// damping. Per variant: the median wall time of df/dx and df/dv together (what one step
// builds) and of a whole backward-Euler step (h = 10 ms, Jacobi-PCG to 1e-6 from zero), the
// force evaluations per Jacobian pair, and the largest entry error of the finite-difference
// df/dx against the analytic one, relative to the largest entry. One thread.
//   bench_fd_jacobian [--quick] [--repeats N] [--sizes 1k,10k]   (--quick: 1k, one repeat)
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/material/neo_hookean.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/solve/finite_difference_jacobian.h"

namespace {

using namespace tt;

constexpr double kCell = 0.01;  // m

std::unique_ptr<System> boxSystem(int nx, int ny, int nz) {
  Mesh mesh = boxGrid(nx + 1, ny + 1, nz + 1, kCell * Eigen::Vector3d(nx, ny, nz), TetSplit::kSix);
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (mesh.rest(2, n) < 1e-9) mesh.nodeTags[n] = kFixedAll;
  auto s = std::make_unique<System>(
      mesh, std::vector<Material>{Material::isotropic(3e4, 0.4, 1060.0)});
  s->models.push_back(std::make_unique<HyperelasticModel<NeoHookeanLaw>>(
      s->mesh, std::vector<NeoHookeanLaw::Constants>{NeoHookeanLaw::constants(s->materials[0])},
      LawOptions{}));
  s->damping = 5.0 * s->mass;
  s->updateConstraints();
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01 * kCell);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 2) = 0.05;
  for (int n = 0; n < s->numNodes(); ++n) {
    if (mesh.nodeTags[n] & kFixedAll) continue;
    s->state.x.segment<3>(3 * n) =
        F * mesh.rest.col(n) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
    s->state.v.segment<3>(3 * n) = Eigen::Vector3d(noise(rng), noise(rng), noise(rng)) / kCell;
  }
  return s;
}

double medianSeconds(const std::function<void()>& call, int repeats) {
  std::vector<double> wall;
  for (int r = 0; r < repeats; ++r) {
    const double w0 = bench::wallSeconds();
    call();
    wall.push_back(bench::wallSeconds() - w0);
  }
  return bench::median(wall);
}

double relativeError(const SparseMatrix& a, const SparseMatrix& reference) {
  const SparseMatrix d = a - reference;
  const auto values = [](const SparseMatrix& m) {
    return Eigen::Map<const Eigen::VectorXd>(m.valuePtr(), m.nonZeros()).lpNorm<Eigen::Infinity>();
  };
  return values(d) / values(reference);
}

// One backward-Euler step from the prepared state, which is put back after each repeat.
double stepSeconds(System& s, BackwardEulerParams p, int repeats) {
  p.linearTolerance = 1e-6;
  p.linearMaxIterations = 5000;
  p.warmStart = false;  // every repeat solves from zero, not from the previous repeat's answer
  BackwardEulerIntegrator be(p);
  const State start = s.state;
  const double seconds = medianSeconds([&] {
    if (!be.advance(s, 0.01).ok) std::fprintf(stderr, "bench_fd_jacobian: a step failed\n");
    s.state = start;
  }, repeats);
  return seconds;
}

void measure(int nx, int ny, int nz, int repeats) {
  auto s = boxSystem(nx, ny, nz);
  const Eigen::VectorXd& x = s->state.x;
  const Eigen::VectorXd& v = s->state.v;
  Eigen::VectorXd f;
  s->computeForce(x, v, f);
  std::printf("%d tets, %d nodes, %d DOFs\n", s->mesh.numTets(), s->numNodes(), s->numDofs());
  std::printf("%-22s %8s %14s %14s %12s\n", "jacobian", "evals", "jacobians_ms", "step_ms",
              "rel_error");
  SparseMatrix K, C;
  const double analytic = medianSeconds([&] {
    s->assembleStiffness(x, K);
    s->assembleVelocityJacobian(x, v, C);
  }, repeats);
  BackwardEulerParams p = bench::jacobiBackwardEuler();
  std::printf("%-22s %8d %14.3f %14.3f %12s\n", "analytic", 0, 1e3 * analytic,
              1e3 * stepSeconds(*s, p, repeats), "-");
  for (bool coloring : {true, false}) {
    FiniteDifferenceSettings settings;
    settings.coloring = coloring;
    FiniteDifferenceJacobian fd(*s, settings);
    SparseMatrix Kfd, Cfd;
    // The plain variant at 1e4 tets takes seconds per Jacobian: fewer repeats.
    const int runs = coloring ? repeats : std::max(1, std::min(repeats, 3));
    const double seconds = medianSeconds([&] {
      s->computeForce(x, v, f);
      fd.positions(*s, x, v, f, 1.0, Kfd);
      fd.velocities(*s, x, v, f, 1.0, Cfd);
    }, runs);
    p.jacobian = BackwardEulerParams::Jacobian::kFiniteDifference;
    p.finiteDifference = settings;
    std::printf("%-22s %8d %14.3f %14.3f %12.2e\n",
                coloring ? "fd_coloured" : "fd_plain", 1 + 2 * fd.groups(), 1e3 * seconds,
                1e3 * stepSeconds(*s, p, runs), relativeError(Kfd, K));
    if (coloring) std::printf("  (%d colours)\n", fd.colours());
  }
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  tools::CommandLine options(argc, argv,
                            "bench_fd_jacobian [--quick] [--repeats N] [--sizes 1k,10k]");
  const bool quick = options.flag("--quick");
  const int repeats = options.positiveInteger("--repeats", quick ? 1 : 5);
  const std::vector<std::string> sizes = options.list(
      "--sizes", quick ? std::vector<std::string>{"1k"} : std::vector<std::string>{"1k", "10k"});
  options.finish();
  setThreadCount(1);
  for (const std::string& size : sizes) {
    if (size == "1k") {
      measure(5, 6, 6, repeats);  // 1080 tets
    } else if (size == "10k") {
      measure(12, 12, 12, repeats);  // 10368 tets
    } else {
      options.fail("--sizes takes 1k and 10k, got '" + size + "'");
    }
  }
  return 0;
}
