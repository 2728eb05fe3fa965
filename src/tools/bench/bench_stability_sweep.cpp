// Numerical stability of every integrator x force model on stiff and extreme tissue.
//
//   bench_stability_sweep [--quick] [--out DIR] [--integrators a,b] [--models a,b]
//                         [--grid-only | --extremes-only [--cases a,b]]
// (--integrators and --models restrict the grid, not the explicit limit and the extreme cases
// below; --grid-only skips those two; --extremes-only runs the extreme cases alone, of the
// integrators, models and cases named.)
//
// 1. The grid: a 2 cm block (4 x 4 x 4 nodes, 162 tets) clamped at its base, released from a
//    10 % shear (u_x = 0.1 z), mass damping 1/s, no gravity; Young's modulus 1 kPa .. 1 GPa,
//    Poisson ratio 0.3 .. 0.4999, step 1e-5 .. 1e-1 s, one step per frame, for
//    max(50 steps, 5 ms). Each cell runs bare and, when that fails, under the StabilityGuard:
//      stable     the bare run stays finite, its energy never exceeds 10x the initial energy
//                 (the exact solution only loses energy), no node moves 10 block sizes and,
//                 for the models that cannot take inversion (the StVK forms), no tet falls
//                 to 1 % of its rest volume or below (the guard's own volume test);
//      recovered  the bare run fails, the guarded run passes (the guard's halvings counted);
//      failed     both fail (the guard ends the run with its message).
//    -> stability_sweep.csv
//    The adaptive steppers (abm3 and backward_euler_adaptive of the Adamss chapter,
//    rk4_adaptive of Jeffrey's Appendix A) run frames of h with h their first and longest step
//    (makeAdaptiveStepper); rk4_fixed is the same Runge-Kutta method at fixed steps of h.
// 2. The explicit limit: for each material the largest step at which symplectic Euler and the
//    Newtonian scheme stay stable (bisection in log h over 300-step runs), beside the
//    critical step h_c = L / c ("Adamss: Advanced Anisotropic Mass-Spring System", Eq. 2.150;
//    L the shortest edge, c the dilatational wave speed sqrt((lambda + 2 mu) / rho)) and
//    2 / omega_max of the assembled system.
//    -> critical_step.csv
// 3. Extreme cases at E = 10 kPa, nu = 0.45: 80 % compression, a forced inversion, a
//    180-degree twist, a 20 m/s impact, sliver elements (the block flattened 50:1).
//    -> extreme_cases.csv
// The grid and the extreme cases run the registry's presets, among them the tissue presets: the
// two Adamss tissues (adamss_hunter, adamss_springs), their stiffness scaled to Young's modulus
// and a volume term from the Poisson ratio (src/core/model/adamss/tissue_presets_registration.cpp),
// and the muscle tissue (muscle_groups with the teran_muscle law at activation 0.5:
// teran_muscle, teran_muscle_inversion with inversion threshold 0.25, and
// teran_muscle_inversion_psd with PSD-projected tangents, which only the integrators that use
// the stiffness run: for the others it is teran_muscle_inversion). The muscle tissue (the
// presets with an activated model) alone also runs the quasistatic solver (each frame the equilibrium at the frame's end; the step h is
// only the frame), in the grid and in every extreme case but the impact, which is all inertia.
// The energy of the tests is counted from the rest state's (the muscle law keeps
// psi(I) = 3 (A + B)).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "common/bench_support.h"
#include "common/command_line.h"
#include "tissue_trainer/core/integrate/abm3.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/integrate/rk4_adaptive.h"
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/activated_force_model.h"
#include "tissue_trainer/core/registry/registry.h"

namespace tt {
namespace {

constexpr double kBlock = 0.02;       // m
constexpr double kDensity = 1000.0;   // kg/m^3
constexpr double kDampingRate = 1.0;  // 1/s, mass damping
constexpr double kBlowUpGrowth = 10.0;

// ---- the block ------------------------------------------------------------------------------

Mesh blockMesh(double heightScale = 1.0) {
  Mesh mesh = boxGrid(4, 4, 4, Eigen::Vector3d(kBlock, kBlock, kBlock * heightScale),
                      TetSplit::kSixMirrored);
  mesh.fillDefaults();
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (mesh.rest(2, n) < 1e-12) mesh.nodeTags[n] = kFixedAll;
  return mesh;
}

std::unique_ptr<System> blockSystem(const std::string& model, double young, double poisson,
                                    const Mesh& mesh) {
  auto s = std::make_unique<System>(mesh, std::vector<Material>{
                                              Material::isotropic(young, poisson, kDensity)});
  bench::addPreset(*s, model);
  s->damping = kDampingRate * s->mass;
  s->updateConstraints();
  return s;
}

// The 10 % shear the grid runs start from (clamped base unmoved).
void shear(System& s, double amount) {
  for (int n = 0; n < s.numNodes(); ++n)
    s.state.x[3 * n] += amount * s.mesh.rest(2, n);
}

// Kinetic plus potential energy, the potential counted from the rest state's.
double totalEnergy(const System& s, double restPotential) {
  return s.kineticEnergy(s.state.v) + s.potentialEnergy(s.state.x) - restPotential;
}

struct TetCounts {
  int inverted = 0;  // signed volume <= 0
  int collapsed = 0; // at or below the guard's minVolumeRatio of the rest volume (inverted too)
};

TetCounts countBadTets(const System& s, const std::vector<double>& restVolume) {
  const Eigen::Map<const Eigen::Matrix3Xd> x(s.state.x.data(), 3, s.numNodes());
  const double minRatio = StabilityGuardParams{}.minVolumeRatio;
  TetCounts c;
  for (std::size_t e = 0; e < s.mesh.tets.size(); ++e) {
    const double v = tetVolume(x, s.mesh.tets[e]);
    c.inverted += v <= 0.0;
    c.collapsed += v <= minRatio * restVolume[e];
  }
  return c;
}

// Whether every model of the system tolerates inverted tets (else an inverted or flat tet is
// a failure, as for the guard: the StVK forms have an inverted rest state).
bool toleratesInversion(const System& s) {
  return std::all_of(s.models.begin(), s.models.end(),
                     [](const auto& m) { return m->toleratesInversion(); });
}

// ---- the adaptive steppers of "Adamss: Advanced Anisotropic Mass-Spring System" ------------
// Sec. 2.5.4 (abm3: halving/doubling on the predictor-corrector difference) and Sec. 2.5.5
// (backward_euler_adaptive: the iteration-count control, GMRES). For them h is the frame: the
// first step and the longest one (a step is cut to the frame's end); the controller may halve
// it six times, down to h / 64, as the stability guard does (abm3: a shorter proposal fails
// the frame; backward Euler keeps its steps at h / 64 whatever they need). rk4_adaptive
// ("A non-linear anisotropic Finite Element Method for surgical simulation", Appendix A: step
// doubling after Numerical Recipes, Sec. 16.2) likewise, with tolerances 1e-6 as abm3.

const std::vector<std::string> kAdaptiveIntegrators = {"backward_euler_adaptive", "abm3",
                                                       "rk4_adaptive"};

bool isAdaptiveStepper(const std::string& name) {
  return std::find(kAdaptiveIntegrators.begin(), kAdaptiveIntegrators.end(), name) !=
         kAdaptiveIntegrators.end();
}

std::unique_ptr<Integrator> makeAdaptiveStepper(const std::string& name, double h) {
  if (name == "abm3") {
    Abm3Params p;
    p.timeStep = h;
    p.minStep = h / 64.0;
    return std::make_unique<Abm3Integrator>(p);
  }
  if (name == "rk4_adaptive") {
    Rk4AdaptiveParams p;
    p.timeStep = h;
    p.minStep = h / 64.0;
    return std::make_unique<Rk4AdaptiveIntegrator>(p);
  }
  BackwardEulerParams p = bench::jacobiBackwardEuler();  // lower_iterations 10, upper_iterations 40: the defaults
  p.adaptive = true;
  p.linearSolver = BackwardEulerParams::LinearSolver::kGmres;
  p.initialStep = h;
  p.minStep = h / 64.0;
  return std::make_unique<BackwardEulerIntegrator>(p);
}

// ---- integrators by name, stepping h ---------------------------------------------------------

const std::vector<std::string> kIntegrators = {"explicit_euler", "symplectic_euler", "newtonian",
                                               "backward_euler", "radau_iia_fixed", "abm3_fixed",
                                               "rk4_fixed"};

// Whether the integrator solves with the stiffness (so that a PSD projection changes it).
bool usesStiffness(const std::string& integrator) {
  return integrator == "backward_euler" || integrator == "backward_euler_adaptive" ||
         integrator == "radau_iia_fixed" || integrator == "quasistatic";
}

// Whether the preset has an activated model (the muscle tissue): the one kind whose
// equilibrium the quasistatic solver is run to find.
bool isActivated(const std::string& model) {
  static std::map<std::string, bool> known;
  auto it = known.find(model);
  if (it == known.end()) {
    const auto s = blockSystem(model, 1e4, 0.45, blockMesh());
    const bool activated = std::any_of(s->models.begin(), s->models.end(), [](const auto& m) {
      return dynamic_cast<const ActivatedForceModel*>(m.get()) != nullptr;
    });
    it = known.emplace(model, activated).first;
  }
  return it->second;
}

// The pairs the sweep runs: the quasistatic solver on the muscle tissue only, and the
// PSD-projected muscle only where the projection changes anything.
bool runsPair(const std::string& integrator, const std::string& model) {
  if (integrator == "quasistatic") return isActivated(model);
  return model != "teran_muscle_inversion_psd" || usesStiffness(integrator);
}

std::unique_ptr<Integrator> makeStepper(const std::string& name, double h) {
  if (name == "explicit_euler" || name == "symplectic_euler") {
    ExplicitEulerParams p;
    p.substep = h;
    p.symplectic = name == "symplectic_euler";
    return std::make_unique<ExplicitEulerIntegrator>(p);
  }
  if (name == "newtonian") {
    NewtonianParams p;
    p.substep = h;
    return std::make_unique<NewtonianIntegrator>(p);
  }
  if (name == "backward_euler") return std::make_unique<BackwardEulerIntegrator>(bench::jacobiBackwardEuler());
  if (name == "abm3_fixed") {  // fixed steps of h, the third-order Runge-Kutta start
    Abm3Params p;
    p.adaptive = false;
    p.timeStep = h;
    return std::make_unique<Abm3Integrator>(p);
  }
  if (name == "rk4_fixed") {  // the classical Runge-Kutta method at fixed steps of h
    Rk4AdaptiveParams p;
    p.adaptive = false;
    p.timeStep = h;
    return std::make_unique<Rk4AdaptiveIntegrator>(p);
  }
  if (isAdaptiveStepper(name)) return makeAdaptiveStepper(name, h);
  if (name == "quasistatic") return std::make_unique<QuasistaticIntegrator>();  // scene defaults
  RadauOptions o;  // radau_iia_fixed: fixed steps of h, Newton must converge
  o.adaptive = false;
  o.initialStep = h;
  return std::make_unique<RadauIIA>(o);
}

// ---- one run --------------------------------------------------------------------------------

struct Outcome {
  bool ok = true;            // finite, bounded energy and displacement, every frame reported ok
  double growth = 0.0;       // max over frames of E / E0
  int invertedMax = 0;
  GuardStats guard;
  double wallSeconds = 0.0;
  std::string failure;
};

// driven: controlled nodes put energy in, so the growth is recorded but is no failure (the
// guard's energy balance, which counts their work, is the test there).
Outcome run(System& s, std::unique_ptr<Integrator> integrator, double h, int frames,
            bool guarded, double energyScale, bool driven = false) {
  Outcome out;
  StabilityGuard* guard = nullptr;
  if (guarded) {
    auto g = std::make_unique<StabilityGuard>(std::move(integrator));
    guard = g.get();
    integrator = std::move(g);
  }
  const double restPotential = s.potentialEnergy(s.mesh.rest.reshaped());
  const double e0 = std::max(totalEnergy(s, restPotential), energyScale);
  std::vector<double> restVolume;
  const Eigen::Map<const Eigen::Matrix3Xd> rest(s.mesh.rest.data(), 3, s.numNodes());
  for (const Tet& t : s.mesh.tets) restVolume.push_back(tetVolume(rest, t));
  const bool inversionFails = !toleratesInversion(s);
  const auto t0 = std::chrono::steady_clock::now();
  for (int f = 0; f < frames; ++f) {
    const StepReport r = integrator->advance(s, h);
    const bool finite = s.state.x.allFinite() && s.state.v.allFinite();
    const double e = finite ? totalEnergy(s, restPotential) : INFINITY;
    out.growth = std::max(out.growth, e / e0);
    TetCounts bad;
    if (finite) bad = countBadTets(s, restVolume);
    out.invertedMax = std::max(out.invertedMax, bad.inverted);
    const double reach = finite ? (s.state.x - s.mesh.rest.reshaped()).lpNorm<Eigen::Infinity>() : INFINITY;
    const char* problem = !r.ok ? r.failure.c_str()
                          : !finite ? "non-finite state"
                          : !driven && out.growth > kBlowUpGrowth ? "energy above 10x its start"
                          : reach > 10.0 * kBlock ? "node beyond 10 block sizes"
                          : inversionFails && bad.collapsed > 0 ? "inverted or flat tets, which the model cannot take"
                          : nullptr;
    if (problem) {
      out.ok = false;
      char buf[400];
      std::snprintf(buf, sizeof buf, "frame %d (t = %.3g s): %s", f, s.state.t, problem);
      out.failure = buf;
      break;
    }
  }
  out.wallSeconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (guard) out.guard = guard->stats();
  return out;
}

// The run whose energy growth a row shows: the bare one, unless only the guarded one passed
// (a failed cell shows the growth the guard could not prevent).
const Outcome& shownRun(const Outcome& bare, const Outcome& guarded) {
  return !bare.ok && guarded.ok ? guarded : bare;
}

// Inverted tets at any frame of either run (a model that cannot take them stops the bare run
// at the first; one that can, such as the linear tensor-mass model, may keep many).
int invertedMax(const Outcome& bare, const Outcome& guarded) {
  return std::max(bare.invertedMax, guarded.invertedMax);
}

std::string csvText(std::string s) {
  for (char& c : s)
    if (c == ',' || c == '\n' || c == '"') c = ';';
  return s;
}

// Opens a CSV file for writing; a file that cannot be written ends the run (exit 1).
std::ofstream openCsv(const std::string& path) {
  std::ofstream csv(path);
  if (!csv) {
    std::fprintf(stderr, "bench_stability_sweep: cannot write %s\n", path.c_str());
    std::exit(1);
  }
  return csv;
}

// ---- 1. the grid ----------------------------------------------------------------------------

struct Grid {
  std::vector<double> young, poisson, steps;
  std::vector<std::string> models, integrators;
};

Grid grid(bool quick) {
  Grid g;
  if (quick) {
    g.young = {1e4, 1e8};
    g.poisson = {0.3, 0.49};
    g.steps = {1e-4, 1e-2};
    g.models = {"edge_length", "stvk_displacement"};
    g.integrators = {"symplectic_euler", "backward_euler"};
    g.integrators.insert(g.integrators.end(), kAdaptiveIntegrators.begin(),
                         kAdaptiveIntegrators.end());
    return g;
  }
  g.young = {1e3, 1e4, 1e5, 1e6, 1e7, 1e8, 1e9};
  g.poisson = {0.3, 0.45, 0.49, 0.4999};
  g.steps = {1e-5, 1e-4, 1e-3, 1e-2, 1e-1};
  g.models = registry().presetNames();
  g.integrators = kIntegrators;
  g.integrators.insert(g.integrators.end(), kAdaptiveIntegrators.begin(),
                       kAdaptiveIntegrators.end());
  g.integrators.push_back("quasistatic");
  return g;
}

// Radau IIA at small fixed steps is the costly part of the grid; it runs the two correct
// energies on their fast paths only: edge_length_literal and stvk_displacement evaluate the
// same StVK polynomial as edge_length by slower formulas, and the printed sign of Eq 5 of
// Jeffrey, "A non-linear anisotropic Finite Element Method for surgical simulation"
// (stvk_displacement_paper_literal) is the slowest path of all.
bool inGrid(const std::string& integrator, const std::string& model) {
  return runsPair(integrator, model) &&
         (integrator != "radau_iia_fixed" || model == "edge_length" || model == "tensor_mass");
}

int framesFor(double h) { return std::max(50, static_cast<int>(std::ceil(0.005 / h))); }

void sweepGrid(const Grid& g, const std::string& path) {
  std::ofstream csv = openCsv(path);
  csv << "integrator,model,young,poisson,step,outcome,energy_growth,inverted_max,"
         "guard_recoveries,guard_halvings,guard_failures,wall_seconds,guarded_wall_seconds,failure\n";
  const Mesh mesh = blockMesh();
  std::size_t pairs = 0;
  for (const std::string& integrator : g.integrators)
    for (const std::string& model : g.models) pairs += inGrid(integrator, model);
  const std::size_t total = pairs * g.young.size() * g.poisson.size() * g.steps.size();
  std::size_t done = 0;
  for (const std::string& integrator : g.integrators)
    for (const std::string& model : g.models) {
      if (!inGrid(integrator, model)) continue;
      int stable = 0, recovered = 0, failed = 0;
      for (double young : g.young)
        for (double poisson : g.poisson)
          for (double h : g.steps) {
            auto bare = blockSystem(model, young, poisson, mesh);
            shear(*bare, 0.1);
            const Outcome a = run(*bare, makeStepper(integrator, h), h, framesFor(h), false, 0.0);
            Outcome b;
            if (!a.ok) {
              auto guarded = blockSystem(model, young, poisson, mesh);
              shear(*guarded, 0.1);
              b = run(*guarded, makeStepper(integrator, h), h, framesFor(h), true, 0.0);
            }
            const std::string outcome = a.ok ? "stable" : b.ok ? "recovered" : "failed";
            stable += a.ok;
            recovered += !a.ok && b.ok;
            failed += !a.ok && !b.ok;
            csv << integrator << ',' << model << ',' << young << ',' << poisson << ',' << h << ','
                << outcome << ',' << shownRun(a, b).growth << ',' << invertedMax(a, b) << ','
                << b.guard.recoveries << ',' << b.guard.halvings << ',' << b.guard.failures << ','
                << a.wallSeconds << ',' << b.wallSeconds << ','
                << csvText(a.ok ? "" : b.ok ? a.failure : b.failure) << std::endl;  // flushed: a stopped run keeps its rows
            ++done;
          }
      std::printf("[%3zu%%] grid %-18s %-33s stable %3d  recovered %3d  failed %3d\n",
                  100 * done / total, integrator.c_str(), model.c_str(), stable, recovered, failed);
      std::fflush(stdout);
    }
}

// ---- 2. the explicit limit ------------------------------------------------------------------

double shortestEdge(const Mesh& mesh) {
  double shortest = INFINITY;
  for (const Tet& t : mesh.tets)
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j)
        shortest = std::min(shortest, (mesh.rest.col(t[i]) - mesh.rest.col(t[j])).norm());
  return shortest;
}

// Largest eigenvalue of M^-1 (-K) at rest on the free DOFs (power iteration).
double omegaMax(const System& s) {
  const Eigen::SparseMatrix<double> K = bench::negativeStiffness(s, s.mesh.rest.reshaped());
  Eigen::VectorXd v = Eigen::VectorXd::Ones(s.numDofs());
  double lambda = 0.0;
  for (int it = 0; it < 500; ++it) {
    Eigen::VectorXd w = K * v;
    for (int d = 0; d < s.numDofs(); ++d) w[d] = s.isConstrained[d] ? 0.0 : w[d] / s.mass[d];
    const double next = w.norm() / v.norm();
    v = w / w.norm();
    if (std::abs(next - lambda) < 1e-10 * next) break;
    lambda = next;
  }
  return std::sqrt(lambda);
}

bool stableAt(const std::string& integrator, const std::string& model, double young,
              double poisson, const Mesh& mesh, double h) {
  auto s = blockSystem(model, young, poisson, mesh);
  shear(*s, 0.1);
  return run(*s, makeStepper(integrator, h), h, 300, false, 0.0).ok;
}

double explicitLimit(const std::string& integrator, const std::string& model, double young,
                     double poisson, const Mesh& mesh) {
  double lo = -10.0, hi = -1.0;  // log10 h
  if (stableAt(integrator, model, young, poisson, mesh, std::pow(10.0, hi))) return std::pow(10.0, hi);
  if (!stableAt(integrator, model, young, poisson, mesh, std::pow(10.0, lo))) return 0.0;
  for (int i = 0; i < 16; ++i) {
    const double mid = 0.5 * (lo + hi);
    (stableAt(integrator, model, young, poisson, mesh, std::pow(10.0, mid)) ? lo : hi) = mid;
  }
  return std::pow(10.0, lo);
}

void sweepCriticalStep(const Grid& g, bool quick, const std::string& path) {
  std::ofstream csv = openCsv(path);
  csv << "model,young,poisson,shortest_edge,wave_speed,predicted_hc,two_over_omega_max,"
         "limit_symplectic_euler,limit_newtonian\n";
  const Mesh mesh = blockMesh();
  const double L = shortestEdge(mesh);
  const std::vector<std::string> models =
      quick ? std::vector<std::string>{"edge_length"} : std::vector<std::string>{"edge_length", "stvk_displacement", "tensor_mass"};
  for (const std::string& model : models)
    for (double young : g.young)
      for (double poisson : {0.3, 0.49}) {
        const Material m = Material::isotropic(young, poisson, kDensity);
        const ElasticConstants& k = m.elasticConstants();
        const double c = std::sqrt((k.lambda + 2.0 * k.mu) / kDensity);
        auto s = blockSystem(model, young, poisson, mesh);
        const double wmax = s->hasStiffness() ? omegaMax(*s) : NAN;
        const double se = explicitLimit("symplectic_euler", model, young, poisson, mesh);
        const double nw = explicitLimit("newtonian", model, young, poisson, mesh);
        csv << model << ',' << young << ',' << poisson << ',' << L << ',' << c << ',' << L / c
            << ',' << 2.0 / wmax << ',' << se << ',' << nw << '\n';
        std::printf("[limit] %-18s E %8.0e nu %.2f: h_c = L/c %.3e  2/omega_max %.3e  "
                    "symplectic %.3e  newtonian %.3e\n",
                    model.c_str(), young, poisson, L / c, 2.0 / wmax, se, nw);
        std::fflush(stdout);
      }
}

// ---- 3. extreme cases -----------------------------------------------------------------------

struct Case {
  std::string name;
  double heightScale = 1.0;
  bool driven = false;                 // controlled nodes move (see run())
  std::function<void(System&)> setup;  // initial state, controlled sets
  double duration = 0.3;               // s
};

std::vector<int> topNodes(const Mesh& mesh) {
  const double top = mesh.rest.row(2).maxCoeff();
  std::vector<int> nodes;
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (mesh.rest(2, n) > top - 1e-12) nodes.push_back(n);
  return nodes;
}

// Each top node follows the path of a rotation by up to `degrees` about the vertical axis of
// the block, reached at time `over` (20 keyframes).
void twistTop(System& s, double degrees, double over) {
  const Eigen::Vector2d centre(0.5 * kBlock, 0.5 * kBlock);
  for (int n : topNodes(s.mesh)) {
    ControlledSet set;
    set.nodes = {n};
    const Eigen::Vector2d r = s.mesh.rest.col(n).head<2>() - centre;
    for (int k = 0; k <= 20; ++k) {
      const double a = degrees * M_PI / 180.0 * k / 20.0;
      const Eigen::Vector2d rotated(std::cos(a) * r.x() - std::sin(a) * r.y(),
                                    std::sin(a) * r.x() + std::cos(a) * r.y());
      set.path.times.push_back(over * k / 20.0);
      set.path.offsets.push_back(Eigen::Vector3d(rotated.x() - r.x(), rotated.y() - r.y(), 0.0));
    }
    s.controlled.push_back(set);
  }
  s.updateConstraints();
}

std::vector<Case> extremeCases() {
  std::vector<Case> cases;
  cases.push_back({"compression_80pct", 1.0, true, [](System& s) {
                     ControlledSet set;
                     set.nodes = topNodes(s.mesh);
                     set.path.times = {0.0, 0.2};
                     set.path.offsets = {Eigen::Vector3d::Zero(), Eigen::Vector3d(0, 0, -0.8 * kBlock)};
                     s.controlled.push_back(set);
                     s.updateConstraints();
                   }});
  cases.push_back({"forced_inversion", 1.0, false, [](System& s) {
                     // The top corner node pushed through the block to below its neighbours.
                     const std::vector<int> top = topNodes(s.mesh);
                     int corner = top.front();
                     for (int n : top)
                       if (s.mesh.rest.col(n).sum() > s.mesh.rest.col(corner).sum()) corner = n;
                     s.state.x.segment<3>(3 * corner) -= Eigen::Vector3d(0.5, 0.5, 1.5) * kBlock / 3.0;
                   }});
  cases.push_back({"twist_180deg", 1.0, true, [](System& s) { twistTop(s, 180.0, 0.2); }});
  cases.push_back({"impact_20m_per_s", 1.0, false, [](System& s) {
                     for (int n = 0; n < s.numNodes(); ++n)
                       if (s.mesh.nodeTags[n] == 0) s.state.v[3 * n + 2] = -20.0;
                   }});
  cases.push_back({"sliver_elements", 0.02, false, [](System& s) { shear(s, 0.1); }});
  return cases;
}

// The extreme cases for every stepper and model, or those of `onlyIntegrators`,
// `onlyModels` and `onlyCases` when given (empty: all).
void sweepExtremes(bool quick, const std::string& path,
                   const std::vector<std::string>& onlyIntegrators,
                   const std::vector<std::string>& onlyModels,
                   const std::vector<std::string>& onlyCases) {
  std::ofstream csv = openCsv(path);
  csv << "case,integrator,model,step,outcome,energy_growth,inverted_max,guard_recoveries,"
         "guard_halvings,guard_failures,wall_seconds,failure\n";
  const double young = 1e4, poisson = 0.45;
  std::vector<std::string> models =
      quick ? std::vector<std::string>{"edge_length", "teran_muscle_inversion"} : std::vector<std::string>{"edge_length", "stvk_displacement", "tensor_mass"};
  if (!quick)  // the Adamss models and the muscle tissue
    for (const TissuePreset& t : registry().tissuePresets()) models.push_back(t.name);
  std::vector<std::pair<std::string, double>> steppers =
      quick ? std::vector<std::pair<std::string, double>>{{"backward_euler", 1e-3}, {"quasistatic", 0.05}}
            : std::vector<std::pair<std::string, double>>{
                  {"symplectic_euler", 1e-4}, {"newtonian", 1e-4}, {"backward_euler", 1e-3},
                  {"backward_euler", 1e-2}, {"radau_iia_fixed", 1e-3}, {"abm3_fixed", 1e-4},
                  {"rk4_fixed", 1e-4}};
  // The adaptive steppers of the Adamss chapter (frames of h, see makeAdaptiveStepper).
  if (!quick)
    steppers.insert(steppers.end(),
                    {{"backward_euler_adaptive", 1e-3}, {"abm3", 1e-3}, {"rk4_adaptive", 1e-3},
                     {"quasistatic", 1e-3}});
  models.erase(std::remove_if(models.begin(), models.end(),
                              [&](const std::string& m) { return !bench::selected(onlyModels, m); }),
               models.end());
  steppers.erase(std::remove_if(steppers.begin(), steppers.end(),
                                [&](const auto& st) { return !bench::selected(onlyIntegrators, st.first); }),
                 steppers.end());
  std::vector<Case> cases = extremeCases();
  std::vector<std::string> caseNames;
  for (const Case& c : cases) caseNames.push_back(c.name);
  bench::requireKnown("bench_stability_sweep", "case", onlyCases, caseNames);
  for (const Case& c : cases)
    for (const auto& [integrator, h] : steppers)
      for (const std::string& model : models) {
        if (!bench::selected(onlyCases, c.name) || !runsPair(integrator, model) ||
            (integrator == "quasistatic" && c.name == "impact_20m_per_s") ||
            (quick && isActivated(model) && integrator != "quasistatic"))
          continue;
        const Mesh mesh = blockMesh(c.heightScale);
        const int frames = static_cast<int>(std::ceil(c.duration / h));
        Outcome o[2];
        for (int guarded = 0; guarded < 2; ++guarded) {
          auto s = blockSystem(model, young, poisson, mesh);
          c.setup(*s);
          // Growth against the larger of the initial energy and mu V / 2, the energy of a
          // unit strain of the whole block.
          const double scale = 0.5 * ElasticConstants::isotropic(young, poisson).mu *
                               kBlock * kBlock * kBlock;
          o[guarded] = run(*s, makeStepper(integrator, h), h, frames, guarded == 1, scale,
                           c.driven);
        }
        const std::string outcome = o[0].ok ? "stable" : o[1].ok ? "recovered" : "failed";
        csv << c.name << ',' << integrator << ',' << model << ',' << h << ',' << outcome << ','
            << shownRun(o[0], o[1]).growth << ',' << invertedMax(o[0], o[1]) << ','
            << o[1].guard.recoveries << ','
            << o[1].guard.halvings << ',' << o[1].guard.failures << ',' << o[0].wallSeconds << ','
            << csvText(o[0].ok ? "" : o[1].ok ? o[0].failure : o[1].failure) << std::endl;
        std::printf("[extreme] %-18s %-16s h %.0e %-26s %-9s inverted %3d  guard halvings %ld\n",
                    c.name.c_str(), integrator.c_str(), h, model.c_str(), outcome.c_str(),
                    invertedMax(o[0], o[1]), o[1].guard.halvings);
        std::fflush(stdout);
      }
}

}  // namespace
}  // namespace tt

int main(int argc, char** argv) {
  tt::tools::CommandLine options(argc, argv,
                                 "bench_stability_sweep [--quick] [--out DIR] [--integrators a,b] "
                                 "[--models a,b] [--grid-only | --extremes-only [--cases a,b]]");
  const bool quick = options.flag("--quick");
  const bool gridOnly = options.flag("--grid-only");
  const bool extremesOnly = options.flag("--extremes-only");
  const std::string out = options.text("--out", ".");
  // empty: those of the grid
  const std::vector<std::string> integrators = options.list("--integrators", {});
  const std::vector<std::string> models = options.list("--models", {});
  const std::vector<std::string> cases = options.list("--cases", {});
  options.finish();
  if (gridOnly && extremesOnly)
    options.fail("--grid-only and --extremes-only exclude each other, expected one of them");
  if (!cases.empty() && !extremesOnly) options.fail("--cases expects --extremes-only beside it");
  std::error_code error;
  std::filesystem::create_directories(out, error);
  if (error) {
    std::fprintf(stderr, "bench_stability_sweep: cannot create %s: %s\n", out.c_str(),
                 error.message().c_str());
    return 1;
  }
  const double wall0 = tt::bench::wallSeconds(), cpu0 = tt::bench::cpuSeconds();
  if (extremesOnly) {  // the extreme cases of the chosen integrators and models, nothing else
    tt::sweepExtremes(quick, out + "/extreme_cases.csv", integrators, models, cases);
    std::printf("wrote %s/extreme_cases.csv in %.0f s (CPU %.0f s)\n", out.c_str(),
                tt::bench::wallSeconds() - wall0, tt::bench::cpuSeconds() - cpu0);
    return 0;
  }
  tt::Grid g = tt::grid(quick);
  tt::bench::keepOnly("bench_stability_sweep", "integrator", g.integrators, integrators);
  tt::bench::keepOnly("bench_stability_sweep", "model", g.models, models);
  tt::sweepGrid(g, out + "/stability_sweep.csv");
  if (gridOnly) {  // no stale files of an earlier run beside this grid
    std::filesystem::remove(out + "/critical_step.csv", error);
    std::filesystem::remove(out + "/extreme_cases.csv", error);
  } else {
    tt::sweepCriticalStep(g, quick, out + "/critical_step.csv");
    tt::sweepExtremes(quick, out + "/extreme_cases.csv", {}, {}, {});
  }
  std::printf("wrote %s/stability_sweep.csv%s in %.0f s (CPU %.0f s)\n", out.c_str(),
              gridOnly ? "" : ", critical_step.csv and extreme_cases.csv",
              tt::bench::wallSeconds() - wall0, tt::bench::cpuSeconds() - cpu0);
  return 0;
}
