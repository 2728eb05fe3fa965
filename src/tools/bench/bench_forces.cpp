// Force-evaluation throughput of the tet models (edge_length, stvk_displacement, tensor_mass and
// the generic hyperelastic) on box grids (6 tets per cell), on
// one and two threads (tt::setThreadCount): million tets per second per core (median of
// repeats), each path's time relative to the edge_length fast path, and beside it the maximum
// relative difference of its forces against the fast path on one thread (the two-thread
// forces are compared too); the force expressions of Eq 30 and Eq 31 alone, one against the
// other; plus the stiffness assembly of the fast path. Then the muscle law's
// two PSD projections (psd_method eigen and diagonal_blocks) per tet tangent on random
// gradients, half of them inverted, and in the stiffness assembly of a compressed grid. Last,
// the stiffness assembly of a hex mesh (hyperelastic neo_hookean, no tet split): the blocks
// added with a search per row on one thread against through the pattern's precomputed offsets
// on one and two threads, with the largest relative difference of K beside each.
//   bench_forces [--quick] [--repeats N=7] [--psd-only]
// (--quick: the smaller grid and one repeat; --psd-only: only the PSD projections)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "common/command_line.h"
#include "tissue_trainer/core/material/law_point.h"
#include "tissue_trainer/core/material/teran_muscle.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/model/tensor_mass.h"
#include "tissue_trainer/core/model/tet_loops.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/registry/model_context.h"
#include "tissue_trainer/core/registry/registry.h"

namespace {

using namespace tt;
using Clock = std::chrono::steady_clock;

// cells^3 hexes of 1 cm, each split into 6 tets around its main diagonal, fibres along x.
Mesh boxGrid6(int cx, int cy, int cz, double h) {
  Mesh m;
  auto id = [&](int i, int j, int k) { return i + (cx + 1) * (j + (cy + 1) * k); };
  m.rest.resize(3, (cx + 1) * (cy + 1) * (cz + 1));
  for (int k = 0; k <= cz; ++k)
    for (int j = 0; j <= cy; ++j)
      for (int i = 0; i <= cx; ++i) m.rest.col(id(i, j, k)) = h * Eigen::Vector3d(i, j, k);
  const int paths[6][2] = {{1, 3}, {1, 5}, {2, 3}, {2, 6}, {4, 5}, {4, 6}};
  for (int k = 0; k < cz; ++k)
    for (int j = 0; j < cy; ++j)
      for (int i = 0; i < cx; ++i) {
        auto corner = [&](int b) { return id(i + (b & 1), j + ((b >> 1) & 1), k + ((b >> 2) & 1)); };
        for (const auto& p : paths) {
          Tet t = {corner(0), corner(p[0]), corner(p[1]), corner(7)};
          if (tetVolume(m.rest, t) < 0) std::swap(t[1], t[2]);
          m.tets.push_back(t);
        }
      }
  m.fillDefaults();
  return m;
}

volatile double benchSinkForces = 0.0;

double maxRelDiff(const Eigen::VectorXd& a, const Eigen::VectorXd& ref) {
  return (a - ref).lpNorm<Eigen::Infinity>() / ref.lpNorm<Eigen::Infinity>();
}

// Every repeat's seconds per call, sorted; each repeat runs enough calls to last ~0.1 s.
std::vector<double> sortedSeconds(const std::function<void()>& run, int repeats) {
  auto t0 = Clock::now();
  run();
  const double once = std::chrono::duration<double>(Clock::now() - t0).count();
  const int calls = std::max(1, static_cast<int>(0.1 / std::max(once, 1e-9)));
  std::vector<double> times;
  for (int r = 0; r < repeats; ++r) {
    t0 = Clock::now();
    for (int c = 0; c < calls; ++c) run();
    times.push_back(std::chrono::duration<double>(Clock::now() - t0).count() / calls);
  }
  std::sort(times.begin(), times.end());
  return times;
}

double medianSeconds(const std::function<void()>& run, int repeats) {
  return sortedSeconds(run, repeats)[repeats / 2];
}

// Jeffrey's claim (Sec. 2, after Eq 31): the single sum of Eq 31 evaluates about 35 % faster
// than the two sums of Eq 30. The force expressions alone, one thread, over every tet of the
// grid (the energy, which both model paths also return, left out), interleaved repeats.
void benchEq30AgainstEq31(const Mesh& mesh, const std::vector<Material>& mats,
                          const Eigen::VectorXd& x, int repeats) {
  std::vector<EdgeLengthLiteralTet> tets;
  for (int e = 0; e < mesh.numTets(); ++e)
    tets.push_back(makeEdgeLengthLiteralTet(mesh.rest, mesh.tets[e],
                                            mesh.fibreFrame[e].col(0).normalized(),
                                            mats.at(mesh.material.at(e))));
  Matrix34d sum31 = Matrix34d::Zero(), sum30 = Matrix34d::Zero();
  double worst = 0.0;  // largest |Eq 30 - Eq 31| of a tet relative to its largest Eq 31 entry
  for (int e = 0; e < mesh.numTets(); ++e) {
    const Matrix34d xe = gatherTet(x, mesh.tets[e]);
    const Matrix34d g31 = edgeLengthLiteralGradient(xe, tets[e]);
    worst = std::max(worst, (edgeLengthEq30Gradient(xe, tets[e]) - g31).cwiseAbs().maxCoeff() /
                                g31.cwiseAbs().maxCoeff());
  }
  auto run = [&](Matrix34d (*gradient)(const Matrix34d&, const EdgeLengthLiteralTet&),
                 Matrix34d& sum) {
    return [&, gradient] {
      for (int e = 0; e < mesh.numTets(); ++e)
        sum.noalias() += gradient(gatherTet(x, mesh.tets[e]), tets[e]);
    };
  };
  std::vector<double> t31, t30;
  for (int r = 0; r < repeats; ++r) {  // alternate, so that load changes hit both alike
    t31.push_back(sortedSeconds(run(&edgeLengthLiteralGradient, sum31), 1)[0]);
    t30.push_back(sortedSeconds(run(&edgeLengthEq30Gradient, sum30), 1)[0]);
  }
  std::sort(t31.begin(), t31.end());
  std::sort(t30.begin(), t30.end());
  benchSinkForces = sum31.sum() + sum30.sum();
  const int mid = repeats / 2;
  std::printf("  force expression alone, 1 thread, %d tets, median [min, max] of %d repeats:\n"
              "    Eq 31 (one sum)  %8.3f ms [%.3f, %.3f]\n"
              "    Eq 30 (two sums) %8.3f ms [%.3f, %.3f]\n"
              "    Eq 30 / Eq 31 = %.2f (Eq 31 %.0f %% less time); max rel diff per tet %.1e\n",
              mesh.numTets(), repeats, 1e3 * t31[mid], 1e3 * t31.front(), 1e3 * t31.back(),
              1e3 * t30[mid], 1e3 * t30.front(), 1e3 * t30.back(), t30[mid] / t31[mid],
              100.0 * (1.0 - t31[mid] / t30[mid]), worst);
}

void benchGrid(int cells, int repeats) {
  const double h = 0.01;
  Mesh mesh = boxGrid6(cells, cells, cells, h);
  const std::vector<Material> mats = {Material::transverselyIsotropic(3e4, 0.3, 1.2e5, 0.35, 1060)};
  // A 5% stretch along the fibre, a 15 degree turn and a 1% random jitter.
  std::mt19937 rng(1);
  std::normal_distribution<double> noise(0.0, 0.01 * h);
  const Eigen::Matrix3d F = Eigen::AngleAxisd(0.26, Eigen::Vector3d(1, 1, 0).normalized()) *
                            Eigen::Vector3d(1.05, 1.0, 1.0).asDiagonal();
  Eigen::VectorXd x(3 * mesh.numNodes());
  for (int i = 0; i < mesh.numNodes(); ++i)
    x.segment<3>(3 * i) = F * mesh.rest.col(i) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const Eigen::VectorXd v = Eigen::VectorXd::Zero(x.size());

  struct Entry {
    std::string label;
    std::unique_ptr<ForceModel> model;
  };
  std::vector<Entry> entries;
  entries.push_back({"edge_length fast", std::make_unique<EdgeLengthModel>(mesh, mats, EdgeLengthPath::kFast)});
  entries.push_back({"edge_length literal (Eq 31)", std::make_unique<EdgeLengthModel>(mesh, mats, EdgeLengthPath::kLiteral)});
  entries.push_back({"edge_length eq30 (Eq 30)", std::make_unique<EdgeLengthModel>(mesh, mats, EdgeLengthPath::kEq30)});
  entries.push_back({"stvk_displacement correct", std::make_unique<StvkDisplacementModel>(mesh, mats, AlphaSign::kCorrect)});
  entries.push_back({"stvk_displacement paper_literal", std::make_unique<StvkDisplacementModel>(mesh, mats, AlphaSign::kPaperLiteral)});
  entries.push_back({"tensor_mass (linear)", std::make_unique<TensorMassModel>(mesh, mats)});
  entries.push_back({"hyperelastic stvk", makeElasticModel("hyperelastic_stvk", mesh, mats)});
  entries.push_back({"hyperelastic neo_hookean (other law)",
                     makeElasticModel("hyperelastic_neo_hookean", mesh, mats)});
  const YAML::Node inverting = YAML::Load("{type: hyperelastic, law: stvk, inversion_threshold: 0.2}");
  const std::string origin = "bench_forces";
  entries.push_back({"hyperelastic stvk, inversion 0.2",
                     registry().makeForceModel(YamlEntry(inverting, "", &origin),
                                               ModelContext{mesh, mats, {}})});

  const double mtets = mesh.numTets() * 1e-6;
  std::printf("\n%d tets, %d nodes (box %d^3 cells, 6 tets/cell), stretch+rotation+jitter\n",
              mesh.numTets(), mesh.numNodes(), cells);
  std::printf("  %-38s %9s %9s %9s %9s %8s %8s %10s\n", "model / path", "1T ms", "1T Mt/s",
              "2T ms", "2T Mt/s/c", "speedup", "t/fast", "rel diff");
  Eigen::VectorXd reference = Eigen::VectorXd::Zero(x.size());
  entries[0].model->addForce(x, v, reference);
  Eigen::VectorXd f(x.size());
  double fastSeconds = 0.0;
  for (const Entry& e : entries) {
    double s[2], diff = 0.0;
    for (int threads : {1, 2}) {
      setThreadCount(threads);
      s[threads - 1] = medianSeconds([&] { f.setZero(); e.model->addForce(x, v, f); }, repeats);
      diff = std::max(diff, maxRelDiff(f, reference));
    }
    setThreadCount(1);
    if (&e == &entries[0]) fastSeconds = s[0];
    std::printf("  %-38s %9.3f %9.2f %9.3f %9.2f %8.2f %8.2f %10.2e\n", e.label.c_str(),
                1e3 * s[0], mtets / s[0], 1e3 * s[1], mtets / s[1] / 2, s[0] / s[1],
                s[0] / fastSeconds, diff);
  }
  benchEq30AgainstEq31(mesh, mats, x, repeats);
  SparsePattern pattern(mesh.numNodes(), mesh.tets);
  SparseMatrix K = pattern.zeroMatrix();
  double s[2];
  Eigen::VectorXd k1;
  double diff = 0.0;
  for (int threads : {1, 2}) {
    setThreadCount(threads);
    s[threads - 1] = medianSeconds([&] {
      K.coeffs().setZero();
      entries[0].model->addStiffness(x, 1.0, pattern, K);
    }, repeats);
    if (threads == 1) k1 = K.coeffs();
    else diff = maxRelDiff(K.coeffs(), k1);
  }
  setThreadCount(1);
  std::printf("  %-38s %9.3f %9.2f %9.3f %9.2f %8.2f %8s %10.2e\n", "stiffness assembly (fast)",
              1e3 * s[0], mtets / s[0], 1e3 * s[1], mtets / s[1] / 2, s[0] / s[1], "-", diff);
  const RowOwnership& bands = pattern.rowOwnership(2);
  std::printf("  (threaded assembly: tets visited by the two row bands %zu + %zu of %d; rel diff "
              "of K: 2 vs 1 thread)\n", bands.tets[0].size(), bands.tets[1].size(),
              pattern.numTets());
}

Eigen::Matrix3d frameOfFibre(const Eigen::Vector3d& fibre) {
  Eigen::Matrix3d R;
  R.col(0) = fibre.normalized();
  R.col(1) = R.col(0).unitOrthogonal();
  R.col(2) = R.col(0).cross(R.col(1));
  return R;
}

Eigen::Matrix3d randomRotation(std::mt19937& rng) {
  std::normal_distribution<double> n(0.0, 1.0);
  const Eigen::Quaterniond q(n(rng), n(rng), n(rng), n(rng));
  return q.normalized().toRotationMatrix();
}

volatile double benchSink = 0.0;

double smallestRelativeEigenvalue(const Matrix9d& A) {
  const Eigen::VectorXd l = Eigen::SelfAdjointEigenSolver<Matrix9d>(A).eigenvalues();
  return l.minCoeff() / l.cwiseAbs().maxCoeff();
}

// The muscle law's 9 x 9 projected tangent per quadrature point (one per tet) under each
// psd_method: n gradients Q diag(s) R with s in [0.3, 1.6], the third negated for half of
// them (inverted), activation 0.9, inversion threshold 0.25.
void benchMusclePsdPoints(bool deviatoric, int repeats) {
  constexpr int n = 4000;
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0.3, 1.6);
  std::vector<Eigen::Matrix3d> gradients;
  for (int i = 0; i < n; ++i) {
    Eigen::Vector3d s(u(rng), u(rng), u(rng));
    if (i % 2) s(2) = -s(2);
    gradients.push_back(randomRotation(rng) * s.asDiagonal() * randomRotation(rng));
  }
  TeranMuscleLaw::Constants k;
  k.activation = 0.9;
  k.deviatoricStretch = deviatoric;
  const auto p = TeranMuscleLaw::parameters(k, frameOfFibre(Eigen::Vector3d(1, 2, 2)));
  LawOptions plain, eigen, blocks;
  plain.inversionThreshold = eigen.inversionThreshold = blocks.inversionThreshold = 0.25;
  eigen.psdProjection = blocks.psdProjection = true;
  blocks.psdMethod = PsdMethod::kDiagonalBlocks;
  double sink = 0.0;
  const auto timePer = [&](const LawOptions& o) {
    return medianSeconds([&] {
      for (const Eigen::Matrix3d& F : gradients) {
        LawPoint point = lawPoint(F, o);
        sink += pointTangent<TeranMuscleLaw>(p, point, o)(0, 0);
      }
    }, repeats) / n;
  };
  const double tPlain = timePer(plain), tEigen = timePer(eigen), tBlocks = timePer(blocks);
  // Beside the times: how far apart the two projections are, and their smallest eigenvalues.
  std::vector<double> diff[2];
  double lowest[2] = {1.0, 1.0};
  for (int i = 0; i < n; ++i) {
    LawPoint a = lawPoint(gradients[i], eigen), b = lawPoint(gradients[i], blocks);
    const Matrix9d Ae = pointTangent<TeranMuscleLaw>(p, a, eigen);
    const Matrix9d Ab = pointTangent<TeranMuscleLaw>(p, b, blocks);
    diff[i % 2].push_back((Ab - Ae).norm() / Ae.norm());
    lowest[0] = std::min(lowest[0], smallestRelativeEigenvalue(Ae));
    lowest[1] = std::min(lowest[1], smallestRelativeEigenvalue(0.5 * (Ab + Ab.transpose())));
  }
  const auto median = [](std::vector<double> v) {
    std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
    return v[v.size() / 2];
  };
  const auto largest = [](const std::vector<double>& v) { return *std::max_element(v.begin(), v.end()); };
  std::printf("\nteran_muscle tangent per point, %s fibre stretch, activation 0.9, threshold 0.25 "
              "(%d gradients, half inverted; one thread, median of %d repeats)\n",
              deviatoric ? "deviatoric" : "non-deviatoric", n, repeats);
  std::printf("  %-28s %9.2f us\n", "unprojected tangent", 1e6 * tPlain);
  std::printf("  %-28s %9.2f us   smallest eigenvalue / largest |eigenvalue| %.1e\n",
              "psd_method: eigen", 1e6 * tEigen, lowest[0]);
  std::printf("  %-28s %9.2f us   smallest eigenvalue / largest |eigenvalue| %.1e\n",
              "psd_method: diagonal_blocks", 1e6 * tBlocks, lowest[1]);
  std::printf("  |A_blocks - A_eigen|_F / |A_eigen|_F: median %.3g, largest %.3g (not inverted); "
              "median %.3g, largest %.3g (inverted)\n", median(diff[0]), largest(diff[0]),
              median(diff[1]), largest(diff[1]));
  benchSink = sink;  // keeps the timed tangents from being optimised away
}

// The stiffness assembly of a 12^3-cell grid (10368 tets) compressed 30% across the fibre and
// stretched 20% along it, with jitter, under each psd_method (one thread).
void benchMusclePsdAssembly(int repeats) {
  const double h = 0.01;
  Mesh mesh = boxGrid6(12, 12, 12, h);
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.15 * h);
  const Eigen::Matrix3d F = Eigen::Vector3d(1.2, 0.7, 0.7).asDiagonal();
  Eigen::VectorXd x(3 * mesh.numNodes());
  for (int i = 0; i < mesh.numNodes(); ++i)
    x.segment<3>(3 * i) = F * mesh.rest.col(i) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  TeranMuscleLaw::Constants k;
  k.activation = 0.9;
  k.deviatoricStretch = false;
  SparsePattern pattern(mesh.numNodes(), mesh.tets);
  setThreadCount(1);
  std::printf("\nteran_muscle stiffness assembly, %d tets (non-deviatoric, activation 0.9, "
              "threshold 0.25, compressed 0.7 across, 1.2 along the fibre, jitter 0.15 h; one "
              "thread)\n", mesh.numTets());
  for (PsdMethod method : {PsdMethod::kEigen, PsdMethod::kDiagonalBlocks}) {
    LawOptions o;
    o.inversionThreshold = 0.25;
    o.psdProjection = true;
    o.psdMethod = method;
    const HyperelasticModel<TeranMuscleLaw> model(mesh, {k}, o);
    SparseMatrix K = pattern.zeroMatrix();
    const double t = medianSeconds([&] {
      K.coeffs().setZero();
      model.addStiffness(x, 1.0, pattern, K);
    }, repeats);
    std::printf("  %-28s %9.2f ms  %6.2f us per tet\n",
                method == PsdMethod::kEigen ? "psd_method: eigen" : "psd_method: diagonal_blocks",
                1e3 * t, 1e6 * t / mesh.numTets());
  }
}

// The hex stiffness assembly, searched (a pattern that knows the hexes' node pairs only) and
// through offsets (meshPattern).
void benchHexAssembly(int cells, int repeats) {
  Mesh mesh = boxGrid(cells + 1, cells + 1, cells + 1, Eigen::Vector3d::Constant(0.01 * cells),
                      TetSplit::kNone);
  mesh.fillDefaults();
  std::mt19937 rng(11);
  std::normal_distribution<double> noise(0.0, 1e-4);
  Eigen::VectorXd x(3 * mesh.numNodes());
  for (int i = 0; i < mesh.numNodes(); ++i)
    x.segment<3>(3 * i) = mesh.rest.col(i) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const auto model = makeElasticModel("hyperelastic_neo_hookean", mesh,
                                      {Material::isotropic(3e3, 0.45, 1000.0)});
  std::vector<std::array<int, 2>> pairs;
  for (const Hex& hex : mesh.hexes)
    for (int a = 0; a < 8; ++a)
      for (int b = a + 1; b < 8; ++b) pairs.push_back({hex[a], hex[b]});
  const SparsePattern searched(mesh.numNodes(), mesh.tets, pairs);
  const SparsePattern offsets = meshPattern(mesh);
  std::printf("\nhex stiffness assembly, hyperelastic neo_hookean, %d hexes (median of %d)\n",
              mesh.numHexes(), repeats);
  Eigen::VectorXd reference;
  double searchedSeconds = 0.0;
  auto row = [&](const char* label, const SparsePattern& pattern, int threads) {
    setThreadCount(threads);
    SparseMatrix K = pattern.zeroMatrix();
    const double t = medianSeconds([&] {
      K.coeffs().setZero();
      model->addStiffness(x, 1.0, pattern, K);
    }, repeats);
    setThreadCount(1);
    if (reference.size() == 0) {
      reference = K.coeffs();
      searchedSeconds = t;
    }
    std::printf("  %-34s %9.3f ms %8.2f us/hex  speed-up %5.2f  max rel diff of K %9.2e\n",
                label, 1e3 * t, 1e6 * t / mesh.numHexes(), searchedSeconds / t,
                maxRelDiff(K.coeffs(), reference));
  };
  row("searched per row, 1 thread", searched, 1);
  row("offsets, 1 thread", offsets, 1);
  row("offsets, 2 threads (row bands)", offsets, 2);
}

}  // namespace

int main(int argc, char** argv) {
  tools::CommandLine options(argc, argv, "bench_forces [--quick] [--repeats N] [--psd-only]");
  const bool quick = options.flag("--quick");
  const bool psdOnly = options.flag("--psd-only");
  const int repeats = options.positiveInteger("--repeats", quick ? 1 : 7);
  options.finish();
  std::printf("bench_forces: 1 and 2 threads, median of %d repeats; Mt/s/c = million tets per "
              "second per core\n", repeats);
  if (!psdOnly) {
    benchGrid(12, repeats);              // 10368 tets
    if (!quick) benchGrid(26, repeats);  // 105456 tets
  }
  benchMusclePsdPoints(false, repeats);
  benchMusclePsdPoints(true, repeats);
  benchMusclePsdAssembly(repeats);
  if (!psdOnly) benchHexAssembly(quick ? 6 : 16, repeats);
  return 0;
}
