// Time per implicit step of backward_euler (linearised, Jacobi-PCG) with the anisotropic
// edge_length model (fast path): stiffness assembly alone, then whole steps (force +
// assembly + PCG), on one and two threads, at two PCG tolerances. Beside each time: the PCG
// iterations and achieved relative residual of the step, and the step's error against the
// same step solved tightly (PCG to 1e-13), max |x - x_ref| / max |x_ref - x_start|.
//
// Meshes: a ~10k-tet box grid and a ~50k-tet liver meshed with TetGen from
// config/meshes/liver-smooth.obj (converted to .smesh in a temporary folder) when `tetgen` is
// on the PATH, else a ~50k-tet box grid (the table says which). Liver: clamped on its lowest
// 15% in z, pulled by gravity; grid: clamped at x = 0. Step h = 10 ms (100 Hz: real time
// needs step ms <= 10).
//   bench_implicit_step [steps=9]
#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/mesh/mesh_io.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/parallel.h"

namespace {

using namespace tt;
using Clock = std::chrono::steady_clock;

// The repository root: $TT_SOURCE_DIR, else where this file was compiled from.
std::string sourceDir() {
  if (const char* env = std::getenv("TT_SOURCE_DIR")) return env;
  const std::string file = __FILE__;
  return file.substr(0, file.rfind("/src/tools/"));
}

double seconds(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

// OBJ (coordinates times `toMetres`) -> TetGen .smesh (m) -> tetgen -pq1.4a<vol> -> Mesh,
// aiming at `targetTets`.
bool tetgenLiver(const std::string& obj, double toMetres, int targetTets, Mesh& mesh,
                 std::string& note) {
  if (std::system("command -v tetgen > /dev/null 2>&1") != 0) {
    note = "tetgen not found";
    return false;
  }
  const SurfaceMesh surface = readObj(sourceDir() + "/config/meshes/" + obj);
  const std::string dir = "/tmp/tt_bench_liver";
  if (std::system(("mkdir -p " + dir).c_str()) != 0) return false;
  {
    std::ofstream out(dir + "/liver.smesh");
    out.precision(17);
    out << surface.vertices.cols() << " 3 0 0\n";
    for (Eigen::Index i = 0; i < surface.vertices.cols(); ++i)
      out << i << ' ' << toMetres * surface.vertices(0, i) << ' ' << toMetres * surface.vertices(1, i)
          << ' ' << toMetres * surface.vertices(2, i) << '\n';
    out << surface.triangles.size() << " 0\n";
    for (const Triangle& t : surface.triangles) out << "3 " << t[0] << ' ' << t[1] << ' ' << t[2] << '\n';
    out << "0\n0\n";
  }
  // Enclosed volume of the closed surface (divergence theorem), for the volume constraint.
  double volume = 0.0;
  for (const Triangle& t : surface.triangles)
    volume += toMetres * toMetres * toMetres * surface.vertices.col(t[0]).dot(
        surface.vertices.col(t[1]).cross(surface.vertices.col(t[2]))) / 6.0;
  volume = std::abs(volume);
  double maxVolume = 1.25 * volume / targetTets;  // quality refinement adds tets
  for (int attempt = 0; attempt < 3; ++attempt) {
    char cmd[512];
    std::snprintf(cmd, sizeof cmd, "cd %s && tetgen -pq1.4a%.6eQ liver.smesh > tetgen.log 2>&1",
                  dir.c_str(), maxVolume);
    if (std::system(cmd) != 0) {
      note = "tetgen failed on " + obj + " (see " + dir + "/tetgen.log)";
      return false;
    }
    mesh = readMesh(dir + "/liver.1.ele");
    const double ratio = static_cast<double>(mesh.numTets()) / targetTets;
    if (ratio > 0.9 && ratio < 1.1) break;
    maxVolume *= ratio;
  }
  char buf[160];
  std::snprintf(buf, sizeof buf, "TetGen -pq1.4a%.2e from %s (%.0f cm^3)", maxVolume,
                obj.c_str(), volume * 1e6);
  note = buf;
  return true;
}

struct Scenario {
  std::string name, note;
  Mesh mesh;
};

// Nodes with coordinate `axis` below min + fraction * extent are clamped.
void clampLow(Mesh& mesh, int axis, double fraction) {
  mesh.fillDefaults();
  const double lo = mesh.rest.row(axis).minCoeff(), hi = mesh.rest.row(axis).maxCoeff();
  for (int a = 0; a < mesh.numNodes(); ++a)
    if (mesh.rest(axis, a) <= lo + fraction * (hi - lo)) mesh.nodeTags[a] = kFixedAll;
}

std::unique_ptr<System> buildSystem(const Mesh& mesh) {
  // Liver-like transversely isotropic tissue, fibres along each tet's frame column 0.
  auto system = std::make_unique<System>(
      mesh, std::vector<Material>{Material::transverselyIsotropic(5e3, 0.4, 1.5e4, 0.4, 1060.0)});
  system->models.push_back(std::make_unique<EdgeLengthModel>(system->mesh, system->materials));
  system->models.push_back(std::make_unique<GravityModel>(system->mass, Eigen::Vector3d(0, 0, -9.81)));
  system->damping = 2.0 * system->mass;  // light mass-proportional damping, 1/s
  return system;
}

struct Row {
  double assemblyMs = 0, stepMs = 0, residual = 0, error = 0;
  int iterations = 0;
};

Row measure(const Mesh& mesh, int threads, double tolerance, int steps) {
  setThreadCount(threads);
  auto system = buildSystem(mesh);
  const double h = 0.01;
  Row row;
  {  // assembly alone
    SparseMatrix K;
    system->assembleStiffness(system->state.x, K);
    std::vector<double> times;
    for (int r = 0; r < 5; ++r) {
      const auto t0 = Clock::now();
      system->assembleStiffness(system->state.x, K);
      times.push_back(seconds(t0));
    }
    row.assemblyMs = 1e3 * median(times);
  }
  BackwardEulerParams params;
  params.linearTolerance = tolerance;
  params.linearMaxIterations = 2000;
  BackwardEulerIntegrator integrator(params);
  BackwardEulerParams tight = params;
  tight.linearTolerance = 1e-13;
  tight.linearMaxIterations = 20000;
  tight.warmStart = false;
  // Two steps to get the tissue moving (and warm the PCG start), then the timed steps.
  for (int s = 0; s < 2; ++s) integrator.advance(*system, h);
  std::vector<double> times, errors, residuals, iterations;
  for (int s = 0; s < steps; ++s) {
    const State start = system->state;
    // The reference: the same step from the same state, solved tightly.
    BackwardEulerIntegrator reference(tight);
    reference.advance(*system, h);
    const Eigen::VectorXd xRef = system->state.x;
    system->state = start;
    const auto t0 = Clock::now();
    const StepReport report = integrator.advance(*system, h);
    times.push_back(seconds(t0));
    if (!report.ok) std::printf("  step failed: %s\n", report.failure.c_str());
    errors.push_back((system->state.x - xRef).lpNorm<Eigen::Infinity>() /
                     (xRef - start.x).lpNorm<Eigen::Infinity>());
    residuals.push_back(integrator.diagnostics().lastRelativeResidual);
    iterations.push_back(report.linearIterations);
  }
  row.stepMs = 1e3 * median(times);
  row.error = median(errors);
  row.residual = median(residuals);
  row.iterations = static_cast<int>(median(iterations));
  setThreadCount(1);
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const int steps = argc > 1 ? std::max(1, std::atoi(argv[1])) : 9;
  std::vector<Scenario> scenarios;
  {
    Scenario grid{"box grid 13^3 nodes", "6 tets/hex, 10 cm cube, clamped at x = 0",
                  boxGrid(13, 13, 13, Eigen::Vector3d(0.1, 0.1, 0.1), TetSplit::kSixMirrored)};
    clampLow(grid.mesh, 0, 0.0);
    scenarios.push_back(std::move(grid));
  }
  {
    Scenario liver;
    // liver-smooth.obj (cm) is the liver of the scenes; TetGen rejects it when its surface
    // self-intersects (tetgen -d), then liver2.obj (units taken as dm: 21 cm across) is used.
    std::string firstNote;
    const bool meshed = tetgenLiver("liver-smooth.obj", 0.01, 50000, liver.mesh, firstNote) ||
                        tetgenLiver("liver2.obj", 0.1, 50000, liver.mesh, liver.note);
    if (meshed && liver.note.empty()) liver.note = firstNote;
    else if (meshed) liver.note = firstNote + "; " + liver.note;
    else liver.note = firstNote + "; " + liver.note;
    if (meshed) {
      liver.name = "liver (TetGen)";
      clampLow(liver.mesh, 2, 0.15);
    } else {
      liver.name = "box grid 21x21x22 nodes";
      liver.note = "FALLBACK, " + liver.note + ": box grid of the liver's size";
      liver.mesh = boxGrid(21, 21, 22, Eigen::Vector3d(0.2, 0.2, 0.21), TetSplit::kSixMirrored);
      clampLow(liver.mesh, 0, 0.0);
    }
    scenarios.push_back(std::move(liver));
  }
  std::printf("bench_implicit_step: backward_euler (1 linearised step, Jacobi-PCG), edge_length "
              "fast + gravity, h = 10 ms, median of %d steps\n", steps);
  for (const Scenario& s : scenarios) {
    std::printf("\n%s: %d tets, %d nodes, %ld constrained DOFs; %s\n", s.name.c_str(),
                s.mesh.numTets(), s.mesh.numNodes(), 3L * std::count(s.mesh.nodeTags.begin(), s.mesh.nodeTags.end(), kFixedAll),
                s.note.c_str());
    std::printf("  %7s %9s %11s %9s %10s %10s %12s\n", "threads", "PCG tol", "assembly ms",
                "PCG its", "residual", "step ms", "error/ref");
    for (double tol : {1e-4, 1e-8})
      for (int threads : {1, 2}) {
        const Row r = measure(s.mesh, threads, tol, steps);
        std::printf("  %7d %9.0e %11.2f %9d %10.2e %10.2f %12.2e\n", threads, tol, r.assemblyMs,
                    r.iterations, r.residual, r.stepMs, r.error);
      }
  }
  return 0;
}
