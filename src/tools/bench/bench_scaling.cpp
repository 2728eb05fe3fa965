// Scaling with the mesh size: time per force evaluation (every elastic model), per explicit
// step (Newtonian scheme) and per implicit step (linearised backward Euler, h = 10 ms, under
// gravity, bottom fixed; PCG to 1e-6 with each preconditioner: the model column says which)
// of the edge_length fast model, on box grids of 6 tets per cell from about 1e3 to 1e5 tets.
// One thread; medians of repeats; the fitted log-log slope of time against tets per quantity. Writes DIR/scaling.csv and DIR/scaling_fits.csv.
//   bench_scaling [--quick] [--repeats N] [--out DIR]
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/parallel.h"
#include "tissue_trainer/core/registry/registry.h"

namespace {

using namespace tt;

constexpr double kCell = 0.01;  // m

struct Timing {
  double wall = 0.0, cpu = 0.0;  // medians, s per call
  int repeats = 0;
  double iterations = 0.0;       // linear iterations per implicit step
};

struct Sample {
  std::string quantity, model;
  int tets = 0, nodes = 0;
  Timing timing;
};

// Median seconds per call; each repeat runs enough calls to last about 50 ms.
Timing timeCalls(const std::function<void()>& call, int repeats) {
  const double t0 = bench::wallSeconds();
  call();
  const double once = bench::wallSeconds() - t0;
  const int calls = std::max(1, static_cast<int>(0.05 / std::max(once, 1e-9)));
  std::vector<double> wall, cpu;
  for (int r = 0; r < repeats; ++r) {
    const double w0 = bench::wallSeconds(), c0 = bench::cpuSeconds();
    for (int c = 0; c < calls; ++c) call();
    wall.push_back((bench::wallSeconds() - w0) / calls);
    cpu.push_back((bench::cpuSeconds() - c0) / calls);
  }
  return {bench::median(wall), bench::median(cpu), repeats, 0.0};
}

std::unique_ptr<System> boxSystem(int cells, const std::string& model) {
  Mesh mesh = boxGrid(cells + 1, cells + 1, cells + 1, Eigen::Vector3d::Constant(cells * kCell),
                      TetSplit::kSix);
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (mesh.rest(2, n) < 1e-9) mesh.nodeTags[n] = kFixedAll;
  const std::vector<Material> materials = {
      Material::transverselyIsotropic(3e4, 0.3, 1.2e5, 0.35, 1060.0)};
  auto s = std::make_unique<System>(mesh, materials);
  s->models.push_back(makeElasticModel(model, s->mesh, s->materials));
  s->models.push_back(std::make_unique<GravityModel>(s->mass, Eigen::Vector3d(0, 0, -9.81)));
  s->damping = 5.0 * s->mass;
  return s;
}

// A 5 % shear with a 1 % jitter: every tet strained, no symmetry left.
Eigen::VectorXd strainedState(const Mesh& mesh) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.01 * kCell);
  Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
  F(0, 2) = 0.05;
  Eigen::VectorXd x(3 * mesh.numNodes());
  for (int n = 0; n < mesh.numNodes(); ++n)
    x.segment<3>(3 * n) =
        F * mesh.rest.col(n) + Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  return x;
}

Timing forceTiming(const System& s, int repeats) {
  const Eigen::VectorXd x = strainedState(s.mesh), v = Eigen::VectorXd::Zero(x.size());
  Eigen::VectorXd f(x.size());
  return timeCalls([&] {
    f.setZero();
    s.models.front()->addForce(x, v, f);
  }, repeats);
}

Timing explicitStepTiming(System& s, int repeats) {
  const double h = 1e-5;
  NewtonianIntegrator newtonian(NewtonianParams{h});
  return timeCalls([&] { newtonian.advance(s, h); }, repeats);
}

// Each repeat is one step of the system falling under gravity (not repeated within a repeat).
Timing implicitStepTiming(System& s, int repeats, BackwardEulerParams::Preconditioning pc) {
  BackwardEulerIntegrator be;
  be.params.preconditioner = pc;
  be.params.backgroundRefactor = false;  // every factorisation in the step that asks for it
  be.params.linearTolerance = 1e-6;
  be.params.linearMaxIterations = 5000;
  be.advance(s, 0.01);  // warm-up: allocations and the first solve
  std::vector<double> wall, cpu;
  double iterations = 0.0;
  for (int r = 0; r < repeats; ++r) {
    const double w0 = bench::wallSeconds(), c0 = bench::cpuSeconds();
    const StepReport report = be.advance(s, 0.01);
    wall.push_back(bench::wallSeconds() - w0);
    cpu.push_back(bench::cpuSeconds() - c0);
    iterations += report.linearIterations;
  }
  return {bench::median(wall), bench::median(cpu), repeats, iterations / repeats};
}

// Least-squares slope and intercept of log(seconds) against log(tets).
std::pair<double, double> logLogFit(const std::vector<Sample>& samples) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(samples.size());
  for (const Sample& s : samples) {
    const double x = std::log(s.tets), y = std::log(s.timing.wall);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  const double slope = (n * sxy - sx * sy) / (n * sxx - sx * sx);
  return {slope, (sy - slope * sx) / n};
}

void measureSize(int cells, int repeats, std::vector<Sample>& out) {
  for (const std::string& model : bench::elasticModelNames()) {
    auto s = boxSystem(cells, model);
    out.push_back({"force_evaluation", model, s->mesh.numTets(), s->numNodes(),
                   forceTiming(*s, repeats)});
    std::printf("progress %d tets: force evaluation %s %.3g ms\n", s->mesh.numTets(),
                model.c_str(), 1e3 * out.back().timing.wall);
  }
  auto s = boxSystem(cells, "edge_length");
  out.push_back({"explicit_step", "edge_length", s->mesh.numTets(), s->numNodes(),
                 explicitStepTiming(*s, repeats)});
  std::printf("progress %d tets: explicit step %.3g ms\n", s->mesh.numTets(),
              1e3 * out.back().timing.wall);
  using Pc = BackwardEulerParams::Preconditioning;
  const std::pair<const char*, Pc> preconditioners[] = {
      {"edge_length", Pc::kJacobi}, {"edge_length_cholesky", Pc::kCholesky}, {"edge_length_amg", Pc::kAmg}};
  for (const auto& [label, pc] : preconditioners) {
    auto fresh = boxSystem(cells, "edge_length");
    out.push_back({"implicit_step", label, fresh->mesh.numTets(), fresh->numNodes(),
                   implicitStepTiming(*fresh, std::max(3, repeats - 2), pc)});
    std::printf("progress %d tets: implicit step %s %.3g ms (%.1f PCG its)\n",
                fresh->mesh.numTets(), label, 1e3 * out.back().timing.wall,
                out.back().timing.iterations);
  }
}

void writeCsv(const std::string& dir, const std::vector<Sample>& samples) {
  FILE* f = std::fopen((dir + "/scaling.csv").c_str(), "w");
  std::fprintf(f, "quantity,model,tets,nodes,wall_seconds,cpu_seconds,repeats,linear_iterations\n");
  for (const Sample& s : samples)
    std::fprintf(f, "%s,%s,%d,%d,%.6g,%.6g,%d,%.1f\n", s.quantity.c_str(), s.model.c_str(),
                 s.tets, s.nodes, s.timing.wall, s.timing.cpu, s.timing.repeats,
                 s.timing.iterations);
  std::fclose(f);
}

void writeFits(const std::string& dir, const std::vector<Sample>& samples) {
  std::map<std::string, std::vector<Sample>> groups;
  for (const Sample& s : samples) groups[s.quantity + "," + s.model].push_back(s);
  FILE* f = std::fopen((dir + "/scaling_fits.csv").c_str(), "w");
  std::fprintf(f, "quantity,model,slope,log_intercept\n");
  for (const auto& [key, group] : groups) {
    const auto [slope, intercept] = logLogFit(group);
    std::fprintf(f, "%s,%.4f,%.6g\n", key.c_str(), slope, intercept);
    std::printf("slope %s: %.3f (time ~ tets^%.2f)\n", key.c_str(), slope, slope);
  }
  std::fclose(f);
}

}  // namespace

int main(int argc, char** argv) {
  std::setvbuf(stdout, nullptr, _IOLBF, 0);
  tools::CommandLine options(argc, argv, "bench_scaling [--quick] [--repeats N] [--out DIR]");
  const bool quick = options.flag("--quick");
  const int repeats = options.positiveInteger("--repeats", quick ? 3 : 7);
  const std::string out = options.text("--out", "docs/report");
  options.finish();
  setThreadCount(1);
  std::filesystem::create_directories(out);
  const std::vector<int> cells = quick ? std::vector<int>{5, 7} : std::vector<int>{6, 9, 13, 19, 26};
  std::vector<Sample> samples;
  for (int c : cells) measureSize(c, repeats, samples);
  writeCsv(out, samples);
  writeFits(out, samples);
  std::printf("wrote %s/scaling.csv and scaling_fits.csv\n", out.c_str());
  return 0;
}
