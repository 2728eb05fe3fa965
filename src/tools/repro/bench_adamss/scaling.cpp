// Computational complexity ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.8.3,
// Fig. 2.29): the time of 1000 implicit steps against the number of volume elements, on
// 6 x 6 x 12 cm cuboids of n x n x 2n hexahedra ("the same physical properties": the Hunter
// law of Table 2.1 plus the volume term with p = 1e3 kPa through the virtual hexahedron,
// hanging from the fixed top face under gravity), linearised backward Euler with a fixed step
// of 1 ms, PCG to 1e-8 with the Jacobi or the sparse Cholesky preconditioner. The chapter
// claims a linear relation (time ~ elements^1). The slope of log time against log elements is
// fitted per preconditioner and thread count (one thread unless --threads asks for more).
// Medians over repeats (each repeat a fresh system from rest); CPU time is the measure (the
// wall time of a shared machine is not). Beside the times, counts that do not depend on the
// machine: the nonzeros of the step's matrix A = M - h^2 K at rest, those of its sparse
// Cholesky factor (AMD ordering), and the work of a step in multiply-adds,
// PCG iterations x (nnz A + 2 nnz L) with the Cholesky preconditioner (two triangular solves
// an iteration; the factorisations, made only when a solve needs more than 15 iterations, left
// out) and PCG iterations x nnz A with Jacobi.
//   bench_adamss scaling [--quick] [--out DIR] [--no-plot] [--sizes 3,4,6] [--threads 1,2]
//                        [--preconditioners jacobi,cholesky] [--steps N] [--repeats N]
//   -> DIR/scaling.csv, DIR/scaling_fits.csv, scaling.png
#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <map>
#include <set>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "common/bench_support.h"
#include "experiment_support.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/parallel.h"

namespace tt {
namespace bench_adamss {
namespace {

constexpr double kStep = 1e-3;       // s
constexpr double kPressure = 1e6;    // Pa: p = 1e3 kPa
constexpr double kScalingDensity = 1060.0;  // kg/m^3
const Eigen::Vector3d kSize(0.06, 0.06, 0.12);

struct Sample {
  std::string preconditioner;
  int threads = 1, cellsAcross = 0, elements = 0, nodes = 0, steps = 0, repeats = 0;
  double wall = 0.0, cpu = 0.0;        // median seconds of `steps` steps
  double linearIterations = 0.0;       // per step, of the median run's kind (all runs equal)
  double wallSpread = 0.0;             // (max - min) / median of the repeats' wall times
  double matrixNonzeros = 0.0, factorNonzeros = 0.0;
  // Multiply-adds of the PCG iterations of a step (see the top of the file).
  double workPerStep() const {
    const double perIteration =
        matrixNonzeros + (preconditioner == "cholesky" ? 2.0 * factorNonzeros : 0.0);
    return linearIterations * perIteration;
  }
};

// The nonzeros of A = M - h^2 K at rest (constrained rows and columns identity, full symmetric
// storage) and of its AMD-ordered Cholesky factor L.
std::pair<double, double> stepMatrixNonzeros(const System& s) {
  SparseMatrix A;
  s.assembleStiffness(s.state.x, A, -kStep * kStep);
  for (int i = 0; i < A.rows(); ++i) A.coeffRef(i, i) += s.mass[i];
  s.constrainMatrix(A);
  const Eigen::SparseMatrix<double> columnMajor = A;
  Eigen::SimplicialLLT<Eigen::SparseMatrix<double>, Eigen::Lower, Eigen::AMDOrdering<int>> llt;
  llt.compute(columnMajor);
  if (llt.info() != Eigen::Success) return {static_cast<double>(A.nonZeros()), NAN};
  const Eigen::SparseMatrix<double> L = llt.matrixL();
  return {static_cast<double>(A.nonZeros()), static_cast<double>(L.nonZeros())};
}

std::unique_ptr<System> hangingCuboid(int n) {
  Mesh mesh = cuboid(Eigen::Vector3i(n, n, 2 * n), kSize, TetSplit::kNone);
  Eigen::Matrix3d frame;
  frame << Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY();
  setFibreFrame(mesh, frame);
  for (int node : nodesAt(mesh, 2, kSize.z())) mesh.nodeTags[node] = kFixedAll;
  auto s = std::make_unique<System>(mesh, std::vector<Material>{
                                              Material::isotropic(1.0, 0.0, kScalingDensity)});
  s->models.push_back(hunterModel(s->mesh));
  s->models.push_back(volumeModel(s->mesh, kPressure));
  s->models.push_back(std::make_unique<GravityModel>(s->mass, Eigen::Vector3d(0, 0, -9.81)));
  s->updateConstraints();
  return s;
}

BackwardEulerParams::Preconditioning preconditioning(const std::string& name) {
  return name == "cholesky" ? BackwardEulerParams::Preconditioning::kCholesky
                            : BackwardEulerParams::Preconditioning::kJacobi;
}

Sample measure(int n, const std::string& preconditioner, int threads, int steps, int repeats) {
  setThreadCount(threads);
  Sample sample{preconditioner, threads, n, 0, 0, steps, repeats};
  std::vector<double> wall, cpu;
  for (int r = 0; r < repeats; ++r) {
    auto s = hangingCuboid(n);
    sample.elements = s->mesh.numHexes();
    sample.nodes = s->numNodes();
    std::tie(sample.matrixNonzeros, sample.factorNonzeros) = stepMatrixNonzeros(*s);
    BackwardEulerParams params;
    params.linearTolerance = 1e-8;  // the defaults before docs/solvers.md's measured ones
    params.preconditioner = preconditioning(preconditioner);
    params.backgroundRefactor = false;
    params.linearMaxIterations = 5000;
    BackwardEulerIntegrator integrator(params);
    long iterations = 0;
    const double w0 = bench::wallSeconds(), c0 = bench::cpuSeconds();
    for (int k = 0; k < steps; ++k) iterations += integrator.advance(*s, kStep).linearIterations;
    wall.push_back(bench::wallSeconds() - w0);
    cpu.push_back(bench::cpuSeconds() - c0);
    sample.linearIterations = static_cast<double>(iterations) / steps;
    if (!s->state.x.allFinite()) std::fprintf(stderr, "scaling: n = %d diverged\n", n);
  }
  sample.wall = bench::median(wall);
  sample.cpu = bench::median(cpu);
  sample.wallSpread =
      (*std::max_element(wall.begin(), wall.end()) - *std::min_element(wall.begin(), wall.end())) /
      sample.wall;
  return sample;
}

std::vector<int> integerList(const std::string& option, const std::string& text,
                             const std::vector<int>& fallback) {
  if (text.empty()) return fallback;
  std::vector<int> values;
  for (const std::string& item : bench::splitList(text))
    values.push_back(bench::positiveInteger("bench_adamss scaling", option, item.c_str()));
  return values;
}

}  // namespace

int runScaling(const Args& args) {
  Options o;
  if (!parseOptions("scaling", args, {"sizes", "threads", "preconditioners", "steps", "repeats"},
                    o))
    return 2;
  const std::vector<int> sizes = integerList(
      "--sizes", o.values[0], o.quick ? std::vector<int>{2, 3, 4} : std::vector<int>{3, 4, 5, 6, 8});
  if (std::set<int>(sizes.begin(), sizes.end()).size() < 2) {
    std::fprintf(stderr, "bench_adamss scaling: --sizes needs at least two different sizes for a slope\n");
    return 2;
  }
  const std::vector<int> threads = integerList("--threads", o.values[1], {1});
  std::vector<std::string> preconditioners =
      o.values[2].empty() ? std::vector<std::string>{"jacobi", "cholesky"}
                          : bench::splitList(o.values[2]);
  bench::requireKnown("bench_adamss scaling", "preconditioner", preconditioners,
                      {"jacobi", "cholesky"});
  const char* tool = "bench_adamss scaling";
  const int steps = o.values[3].empty()
                        ? (o.quick ? 100 : 1000)
                        : bench::positiveInteger(tool, "--steps", o.values[3].c_str());
  const int repeats = o.values[4].empty()
                          ? (o.quick ? 1 : 3)
                          : bench::positiveInteger(tool, "--repeats", o.values[4].c_str());
  std::vector<Sample> samples;
  for (const std::string& pc : preconditioners)
    for (int t : threads)
      for (int n : sizes) {
        samples.push_back(measure(n, pc, t, steps, repeats));
        const Sample& s = samples.back();
        std::printf("progress scaling %s %d thread(s) %d hexes: %.3g s wall, %.3g s CPU per %d "
                    "steps (%.1f PCG its/step)\n",
                    pc.c_str(), t, s.elements, s.wall, s.cpu, steps, s.linearIterations);
        std::fflush(stdout);
      }
  setThreadCount(1);

  FILE* csv = openCsv(o, "scaling.csv");
  std::fprintf(csv, "preconditioner,threads,cells_across,elements,nodes,steps,repeats,"
                    "wall_seconds,cpu_seconds,wall_spread,linear_iterations_per_step,matrix_nonzeros,"
                    "factor_nonzeros,work_per_step\n");
  for (const Sample& s : samples)
    std::fprintf(csv, "%s,%d,%d,%d,%d,%d,%d,%.6g,%.6g,%.4g,%.2f,%.0f,%.0f,%.6g\n",
                 s.preconditioner.c_str(), s.threads, s.cellsAcross, s.elements, s.nodes, s.steps,
                 s.repeats, s.wall, s.cpu, s.wallSpread, s.linearIterations, s.matrixNonzeros,
                 s.factorNonzeros, s.workPerStep());
  std::fclose(csv);

  std::map<std::pair<std::string, int>, std::vector<const Sample*>> groups;
  for (const Sample& s : samples) groups[{s.preconditioner, s.threads}].push_back(&s);
  FILE* fits = openCsv(o, "scaling_fits.csv");
  std::fprintf(fits, "preconditioner,threads,slope_wall,slope_cpu,slope_iterations,"
                     "slope_matrix_nonzeros,slope_factor_nonzeros,slope_work\n");
  std::printf("\nTime of %d backward Euler steps (h = 1 ms) against hexahedra (Sec. 2.8.3; the "
              "chapter claims linear, slope 1)\n",
              steps);
  std::printf("%-9s %7s %14s %14s %18s %12s %12s %12s\n", "precond.", "threads", "slope (wall)",
              "slope (CPU)", "slope (PCG its)", "nnz A", "nnz L", "work");
  for (const auto& [key, group] : groups) {
    std::vector<double> elements, wall, cpu, iterations, matrix, factor, work;
    for (const Sample* s : group) {
      elements.push_back(s->elements);
      wall.push_back(s->wall);
      cpu.push_back(s->cpu);
      iterations.push_back(std::max(s->linearIterations, 1e-9));
      matrix.push_back(s->matrixNonzeros);
      factor.push_back(s->factorNonzeros);
      work.push_back(std::max(s->workPerStep(), 1e-9));
    }
    const double sw = logLogSlope(elements, wall), sc = logLogSlope(elements, cpu),
                 si = logLogSlope(elements, iterations), sm = logLogSlope(elements, matrix),
                 sf = logLogSlope(elements, factor), sk = logLogSlope(elements, work);
    std::fprintf(fits, "%s,%d,%.4f,%.4f,%.4f,%.4f,%.4f,%.4f\n", key.first.c_str(), key.second,
                 sw, sc, si, sm, sf, sk);
    std::printf("%-9s %7d %14.3f %14.3f %18.3f %12.3f %12.3f %12.3f\n", key.first.c_str(),
                key.second, sw, sc, si, sm, sf, sk);
  }
  std::fclose(fits);
  drawPlot("scaling", o);
  std::printf("wrote %s/scaling.csv and scaling_fits.csv\n", o.out.c_str());
  return 0;
}

}  // namespace bench_adamss
}  // namespace tt
