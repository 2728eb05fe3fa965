// The statements of the discussion of "Adamss: Advanced Anisotropic Mass-Spring System"
// (Secs. 2.9.1-2.9.3) and its resolution claim (Sec. 2.1.4), each as a small run:
//
// oscillation (Sec. 2.9.3): "When using the forward Euler method or the prediction-correction
// method, the volume of the system V oscillates around the original volume"; the implicit
// backward Euler "removed the unwanted oscillation of the volume". A cuboid of 2 x 2 x 4 cells
// (six-tet split, 2 x 2 x 4 cm) hangs from its fixed top face under gravity from rest: the
// Hunter law of Table 2.1 (fibres along the long axis) plus the volume term p (det F - 1)^2,
// p = 1e3 kPa, no damping. The same scene and the same step h for the forward (Eqs.
// 2.129-2.130) and the symplectic Euler methods, the fixed-step ABM3 predictor-corrector (Sec.
// 2.5.4, corrected) and the linearised backward Euler (Sec. 2.5.5). The volume oscillation is
// measured as half the range of dV/V0 over the second half of the run, and its fast part as
// the RMS of dV/V0 minus its running mean over 2 ms (the slow swing of the hanging body, which
// every integrator should keep, is thereby left out).
//
// locking (Secs. 2.9.1-2.9.2): tetrahedra "suffer from ... locking that occurs when a hard
// constraint on volume preservation is imposed ... The more the volume is allowed to change the
// less the effect of locking is observed", p being the parameter that allows it. A cantilever
// (1 x 1 x 4 cm, 2 x 2 x 8 cells, six-tet split, fixed at z = 0, load along -x) of a
// neo-Hookean law with nu = 0 (E = 10 kPa) plus the volume term with p = 0 .. 1e4 kPa, brought
// to equilibrium. Adding p raises the bulk modulus K = 2p + E/3 at a fixed shear modulus
// mu = E/2, so a beam that does not lock stiffens at most to Young's modulus
// E(p) = 9 K mu / (3 K + mu) (< 3 mu = 1.5 E): the tip deflection times E(p) / E stays near the
// deflection at p = 0. Their ratio is the locking factor (1: none).
//
// resolution (Sec. 2.1.4, "the system's behavior is independent of the mesh resolution"): the
// cantilever of the Table 2.2 springs (axial and torsion, area form; fibres along the beam)
// meshed at 2 x 2 x 4, 4 x 4 x 8 and 8 x 8 x 16 cells (six-tet split, 2 x 2 x 4 cm), fixed at
// z = 0, under the same acceleration of 1 m/s^2 along -x, brought to equilibrium; the probe is
// the centre of the free end face.
//
//   bench_adamss oscillation [--quick] [--out DIR] [--step H (s, default 5e-5)]
//   bench_adamss locking|resolution [--quick] [--out DIR]
//   -> DIR/oscillation.csv (integrator, t, volume_change; every 10th step),
//      DIR/oscillation_summary.csv, DIR/locking.csv, DIR/resolution.csv
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

#include "experiment_support.h"
#include "tissue_trainer/core/integrate/abm3.h"
#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/model/gravity.h"
#include "tissue_trainer/core/registry/registry.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace tt {
namespace bench_adamss {
namespace {

constexpr double kDensity = 1060.0;  // kg/m^3, myocardium
constexpr double kGravity = 9.81;    // m/s^2

Eigen::Matrix3d fibresAlongZ() {
  Eigen::Matrix3d frame;
  frame << Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY();
  return frame;
}

// A six-tet cuboid with fibres along z whose nodes at z = `fixedZ` are fixed.
Mesh heldCuboid(const Eigen::Vector3i& cells, const Eigen::Vector3d& size, double fixedZ) {
  Mesh mesh = cuboid(cells, size, TetSplit::kSix);
  setFibreFrame(mesh, fibresAlongZ());
  for (int n : nodesAt(mesh, 2, fixedZ)) mesh.nodeTags[n] = kFixedAll;
  return mesh;
}

// --- oscillation (Sec. 2.9.3) ------------------------------------------------------------------

constexpr double kOscillationP = 1e6;  // Pa (1e3 kPa)
constexpr double kOscillationStep = 5e-5;  // s, the default of --step
const Eigen::Vector3d kOscillationSize(0.02, 0.02, 0.04);

struct OscillationRun {
  std::string integrator;
  std::vector<double> t, change;
  bool ok = true;
  std::string failure;
  double amplitude = NAN, fastRms = NAN, mean = NAN;
};

std::unique_ptr<Integrator> makeIntegrator(const std::string& name, double h) {
  if (name == "backward_euler") {
    BackwardEulerParams params;
    params.backgroundRefactor = false;
    params.linearTolerance = 1e-10;
    params.linearMaxIterations = 5000;
    return std::make_unique<BackwardEulerIntegrator>(params);
  }
  if (name == "abm3") {
    Abm3Params params;
    params.adaptive = false;
    params.timeStep = h;
    return std::make_unique<Abm3Integrator>(params);
  }
  ExplicitEulerParams params;
  params.substep = h;
  params.symplectic = name == "symplectic_euler";
  return std::make_unique<ExplicitEulerIntegrator>(params);
}

// Half the range, and the RMS about a running mean over `window` samples, of the second half.
void measureOscillation(OscillationRun& run, std::size_t window) {
  const std::size_t n = run.change.size(), from = n / 2;
  if (!run.ok || n < 2 * window + 2) return;
  double lo = run.change[from], hi = lo, sum = 0.0, fast = 0.0;
  std::size_t counted = 0;
  for (std::size_t k = from; k < n; ++k) {
    lo = std::min(lo, run.change[k]), hi = std::max(hi, run.change[k]);
    sum += run.change[k];
    if (k < from + window / 2 || k + window / 2 >= n) continue;
    double local = 0.0;
    for (std::size_t j = k - window / 2; j < k + window / 2; ++j) local += run.change[j];
    const double d = run.change[k] - local / static_cast<double>(window);
    fast += d * d;
    ++counted;
  }
  run.amplitude = 0.5 * (hi - lo);
  run.mean = sum / static_cast<double>(n - from);
  run.fastRms = std::sqrt(fast / static_cast<double>(counted));
}

OscillationRun oscillate(const std::string& integratorName, double h, double duration) {
  OscillationRun run;
  run.integrator = integratorName;
  System s(heldCuboid(Eigen::Vector3i(2, 2, 4), kOscillationSize, kOscillationSize.z()),
           {Material::isotropic(1.0, 0.0, kDensity)});
  s.models.push_back(hunterModel(s.mesh));
  s.models.push_back(volumeModel(s.mesh, kOscillationP));
  s.models.push_back(std::make_unique<GravityModel>(s.mass, Eigen::Vector3d(0, 0, -kGravity)));
  s.updateConstraints();
  std::unique_ptr<Integrator> integrator = makeIntegrator(integratorName, h);
  const double v0 = meshVolume(s.mesh, s.state.x);
  const int steps = static_cast<int>(std::lround(duration / h));
  for (int k = 0; k <= steps; ++k) {
    run.t.push_back(s.state.t);
    run.change.push_back(meshVolume(s.mesh, s.state.x) / v0 - 1.0);
    if (k == steps) break;
    const StepReport r = integrator->advance(s, h);
    if (!r.ok || !s.state.x.allFinite() || std::abs(run.change.back()) > 1.0) {
      run.ok = false;
      run.failure = !r.ok ? r.failure : "diverged (non-finite state or |dV/V0| > 1)";
      break;
    }
  }
  measureOscillation(run, static_cast<std::size_t>(std::lround(2e-3 / h)));
  return run;
}

// --- locking (Secs. 2.9.1-2.9.2) and resolution (Sec. 2.1.4): cantilevers at equilibrium ------

// The mean x displacement of the nodes on the free end face (z = length), or NaN when the
// equilibrium was not reached.
double tipDeflection(System& s, double length, std::string& failure) {
  EquilibriumParams params;
  params.preconditioner = EquilibriumParams::Preconditioning::kCholesky;
  params.absoluteTolerance = 1e-10;
  const EquilibriumReport report = solveEquilibrium(s, params);
  if (!report.converged()) {
    failure = report.reason;
    return NAN;
  }
  const std::vector<int> tip = nodesAt(s.mesh, 2, length);
  double sum = 0.0;
  for (int n : tip) sum += s.state.x[3 * n] - s.mesh.rest(0, n);
  return sum / static_cast<double>(tip.size());
}

constexpr double kLockingYoung = 1e4;  // Pa
const Eigen::Vector3d kLockingSize(0.01, 0.01, 0.04);

struct LockingRow {
  double pKpa = 0.0, deflection = NAN, youngEffective = 0.0, lockingFactor = NAN;
  std::string failure;
};

// Young's modulus of the neo-Hookean law (mu = E/2, lambda = 0) with the volume term's bulk 2p.
double effectiveYoung(double p) {
  const double mu = 0.5 * kLockingYoung, bulk = 2.0 * p + kLockingYoung / 3.0;
  return 9.0 * bulk * mu / (3.0 * bulk + mu);
}

LockingRow bend(double pKpa, double acceleration) {
  LockingRow row;
  row.pKpa = pKpa;
  const Material material = Material::isotropic(kLockingYoung, 0.0, kDensity);
  System s(heldCuboid(Eigen::Vector3i(2, 2, 8), kLockingSize, 0.0), {material});
  s.models.push_back(neoHookeanModel(s.mesh, material));
  if (pKpa > 0.0) s.models.push_back(volumeModel(s.mesh, 1e3 * pKpa));
  s.models.push_back(std::make_unique<GravityModel>(s.mass, Eigen::Vector3d(-acceleration, 0, 0)));
  s.updateConstraints();
  row.deflection = -tipDeflection(s, kLockingSize.z(), row.failure);
  row.youngEffective = effectiveYoung(1e3 * pKpa);
  return row;
}

struct ResolutionRow {
  int cellsAcross = 0, tets = 0, nodes = 0;
  double deflection = NAN;
  std::string failure;
};

const Eigen::Vector3d kResolutionSize(0.02, 0.02, 0.04);
constexpr double kResolutionLoad = 1.0;  // m/s^2 along -x

ResolutionRow bendSprings(int n) {
  ResolutionRow row;
  row.cellsAcross = n;
  // E = 10 kPa, nu = 0: the preset's springs are Table 2.2's, without the volume term.
  System s(heldCuboid(Eigen::Vector3i(n, n, 2 * n), kResolutionSize, 0.0),
           {Material::isotropic(10e3, 0.0, kDensity)});
  for (auto& m : makePresetModels("adamss_springs", s.mesh, s.materials))
    s.models.push_back(std::move(m));
  s.models.push_back(
      std::make_unique<GravityModel>(s.mass, Eigen::Vector3d(-kResolutionLoad, 0, 0)));
  s.updateConstraints();
  row.tets = s.mesh.numTets();
  row.nodes = s.numNodes();
  row.deflection = -tipDeflection(s, kResolutionSize.z(), row.failure);
  return row;
}

}  // namespace

int runOscillation(const Args& args) {
  Options o;
  if (!parseOptions("oscillation", args, {"step"}, o)) return 2;
  const double duration = o.quick ? 0.02 : 0.1;
  const double h = o.values[0].empty() ? kOscillationStep : std::atof(o.values[0].c_str());
  if (!(h > 0.0) || h > 1e-3) {
    std::fprintf(stderr, "bench_adamss oscillation: --step: expected a step in (0, 1e-3] s, got '%s'\n",
                 o.values[0].c_str());
    return 2;
  }
  std::vector<OscillationRun> runs;
  for (const char* name : {"explicit_euler", "symplectic_euler", "abm3", "backward_euler"}) {
    runs.push_back(oscillate(name, h, duration));
    std::printf("progress oscillation %s%s\n", name, runs.back().ok ? "" : " (failed)");
    std::fflush(stdout);
  }
  FILE* csv = openCsv(o, "oscillation.csv");
  std::fprintf(csv, "integrator,t,volume_change\n");
  for (const OscillationRun& r : runs)
    for (std::size_t k = 0; k < r.t.size(); k += 10)
      std::fprintf(csv, "%s,%.6g,%.9g\n", r.integrator.c_str(), r.t[k], r.change[k]);
  std::fclose(csv);
  FILE* summary = openCsv(o, "oscillation_summary.csv");
  std::fprintf(summary, "integrator,step_s,duration_s,amplitude,fast_rms,mean_change,ok,failure\n");
  std::printf("\nVolume oscillation (Sec. 2.9.3): 2 x 2 x 4 cm hanging cuboid, Hunter + p (det F - "
              "1)^2 with p = 1e3 kPa, h = %g s, %g s; second half of the run\n",
              h, duration);
  std::printf("%-17s %14s %14s %14s\n", "integrator", "amplitude", "fast RMS", "mean dV/V0");
  for (const OscillationRun& r : runs) {
    std::fprintf(summary, "%s,%g,%g,%.6g,%.6g,%.6g,%d,%s\n", r.integrator.c_str(), h, duration, r.amplitude, r.fastRms, r.mean, r.ok,
                 r.failure.c_str());
    if (r.ok)
      std::printf("%-17s %14.3e %14.3e %14.3e\n", r.integrator.c_str(), r.amplitude, r.fastRms,
                  r.mean);
    else
      std::printf("%-17s failed at t = %.4g s: %s\n", r.integrator.c_str(), r.t.back(),
                  r.failure.c_str());
  }
  std::fclose(summary);
  std::printf("wrote %s/oscillation.csv and oscillation_summary.csv\n", o.out.c_str());
  return 0;
}

int runLocking(const Args& args) {
  Options o;
  if (!parseOptions("locking", args, {}, o)) return 2;
  const std::vector<double> pressures =
      o.quick ? std::vector<double>{0, 1e1, 1e2, 1e3} : std::vector<double>{0, 1, 1e1, 1e2, 1e3, 1e4};
  constexpr double kLoad = 2.0;  // m/s^2 along -x
  std::vector<LockingRow> rows;
  for (double p : pressures) rows.push_back(bend(p, kLoad));
  FILE* csv = openCsv(o, "locking.csv");
  std::fprintf(csv, "p_kpa,tip_deflection_m,young_effective_pa,locking_factor,failure\n");
  std::printf("\nLocking against p (Secs. 2.9.1-2.9.2): 1 x 1 x 4 cm cantilever, 2 x 2 x 8 cells of "
              "six tets, neo-Hookean E = 10 kPa, nu = 0, plus p (det F - 1)^2, %g m/s^2\n",
              kLoad);
  std::printf("%10s %16s %14s %15s\n", "p (kPa)", "deflection (mm)", "E(p) (kPa)",
              "locking factor");
  const double reference = rows.front().deflection * rows.front().youngEffective;
  for (LockingRow& r : rows) {
    r.lockingFactor = r.deflection * r.youngEffective / reference;
    std::fprintf(csv, "%g,%.9g,%.9g,%.6g,%s\n", r.pKpa, r.deflection, r.youngEffective,
                 r.lockingFactor, r.failure.c_str());
    std::printf("%10g %16.5f %14.4f %15.4f %s\n", r.pKpa, 1e3 * r.deflection,
                1e-3 * r.youngEffective, r.lockingFactor, r.failure.c_str());
  }
  std::fclose(csv);
  std::printf("wrote %s/locking.csv\n", o.out.c_str());
  return 0;
}

int runResolution(const Args& args) {
  Options o;
  if (!parseOptions("resolution", args, {}, o)) return 2;
  const std::vector<int> sizes = {2, 4, 8};  // under a second of CPU time, --quick or not
  std::vector<ResolutionRow> rows;
  for (int n : sizes) rows.push_back(bendSprings(n));
  FILE* csv = openCsv(o, "resolution.csv");
  std::fprintf(csv, "cells_across,tets,nodes,tip_deflection_m,change_from_previous_m,failure\n");
  std::printf("\nResolution (Sec. 2.1.4): 2 x 2 x 4 cm cantilever of the Table 2.2 springs, "
              "six-tet split, %g m/s^2 along -x; tip = mean of the free end face\n",
              kResolutionLoad);
  std::printf("%8s %7s %7s %16s %22s\n", "cells", "tets", "nodes", "deflection (mm)",
              "change from previous");
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ResolutionRow& r = rows[i];
    const double change = i ? r.deflection - rows[i - 1].deflection : NAN;
    std::fprintf(csv, "%d,%d,%d,%.9g,%.6g,%s\n", r.cellsAcross, r.tets, r.nodes, r.deflection,
                 change, r.failure.c_str());
    std::printf("%8d %7d %7d %16.5f %22.3e %s\n", r.cellsAcross, r.tets, r.nodes,
                1e3 * r.deflection, change, r.failure.c_str());
  }
  std::fclose(csv);
  std::printf("wrote %s/resolution.csv\n", o.out.c_str());
  return 0;
}

}  // namespace bench_adamss
}  // namespace tt
