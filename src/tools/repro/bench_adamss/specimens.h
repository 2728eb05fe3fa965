#pragma once
// Shared pieces of the Sec. 2.8.1 experiments of bench_adamss ("Adamss: Advanced Anisotropic
// Mass-Spring System"): the command-line options, the specimens as scenes (a box of 5 mm
// voxels with the fibre frame and force models given), the energy and work of a quasi-static
// stretch, and an evaluation of the Hunter law (Eq. 2.153, Table 2.1) written out apart from
// the law the models use (material/hunter.h), so that the theory curves do not share its code.
#include <unistd.h>

#include <Eigen/Dense>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "experiments.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/scene/scene.h"
#include "tissue_trainer/core/solve/equilibrium.h"

namespace tt {
namespace bench_adamss {

// --- options ---------------------------------------------------------------------------------

struct CommonOptions {
  std::string out = std::string(TT_SOURCE_ROOT) + "/docs/report/adamss";
  bool quick = false;
  bool plot = true;
};

// --out DIR, --quick, --no-plot; anything else is one error line and exit 2. False (with the
// reason on stderr) when the output folder cannot be made.
inline bool parseCommon(const char* experiment, const Args& args, CommonOptions& o) {
  const std::string tool = std::string("bench_adamss ") + experiment;
  tools::CommandLine options(tool, args, tool + " [--quick] [--out DIR] [--no-plot]");
  o.quick = options.flag("--quick");
  o.plot = !options.flag("--no-plot");
  o.out = options.text("--out", o.out);
  options.finish();
  std::error_code error;
  std::filesystem::create_directories(o.out, error);
  if (error) {
    std::fprintf(stderr, "%s: cannot create %s: %s\n", tool.c_str(), o.out.c_str(),
                 error.message().c_str());
    return false;
  }
  return true;
}

// Draws DIR/<experiment>.png from its CSV with scripts/report/adamss_material.py; a missing
// Python or matplotlib is a note, not a failure of the experiment.
inline void plot(const CommonOptions& o, const char* experiment) {
  if (!o.plot) return;
  std::fflush(stdout);  // the table before the script's own lines
  const std::string command = "/usr/bin/python3 '" + std::string(TT_SOURCE_ROOT) +
                              "/scripts/report/adamss_material.py' '" + o.out + "' " + experiment;
  if (std::system(command.c_str()) != 0)
    std::fprintf(stderr, "bench_adamss %s: no plot (%s failed)\n", experiment, command.c_str());
}

// Runs an experiment's body, turning an exception (a scene or file problem) into one line on
// stderr and exit code 1.
template <class Body>
int reportingErrors(const char* experiment, const Body& body) {
  try {
    return body();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "bench_adamss %s: %s\n", experiment, e.what());
    return 1;
  }
}

// A CSV file for writing; throws std::runtime_error when it cannot be opened.
inline std::ofstream openCsv(const std::string& path) {
  std::ofstream out(path);
  if (!out) throw std::runtime_error("cannot write " + path);
  return out;
}

// --- specimens -------------------------------------------------------------------------------

inline constexpr double kVoxel = 0.005;  // m: the 5 mm resolution of Sec. 2.8.1
inline const char* const kAxisName[3] = {"x", "y", "z"};
inline const char* const kFrameAxisName[3] = {"fibre", "sheet", "normal"};

struct Box {
  int cells[3] = {1, 1, 1};
  const char* split = "six";  // six (tets, 6 per voxel) or none (hexes)
};

// A scene of the box with `fibres` (a YAML map) and `forceModels` (a YAML list), read by the
// scene loader from a file in the temporary folder. The material entry's elastic constants are
// not used by these models (the Hunter law and the springs carry their own).
inline Scene specimenScene(const Box& box, const std::string& fibres,
                           const std::string& forceModels) {
  char mesh[256];
  std::snprintf(mesh, sizeof mesh,
                "{generator: box, nodes: [%d, %d, %d], size: [%.17g, %.17g, %.17g], split: %s}",
                box.cells[0] + 1, box.cells[1] + 1, box.cells[2] + 1, box.cells[0] * kVoxel,
                box.cells[1] * kVoxel, box.cells[2] * kVoxel, box.split);
  const std::string yaml = "name: specimen\nmesh: " + std::string(mesh) + "\nfibres: " + fibres +
                           "\nmaterials:\n  - {young_modulus: 3, poisson_ratio: 0.3, "
                           "stress_unit: kPa}\nforce_models: " +
                           forceModels + "\nintegrator: {type: quasistatic}\n";
  const std::filesystem::path path =
      std::filesystem::temp_directory_path() /
      ("bench_adamss_specimen_" + std::to_string(::getpid()) + ".yaml");
  std::ofstream(path) << yaml;
  Scene scene = loadScene(path.string());
  std::filesystem::remove(path);
  return scene;
}

inline const char* const kAlignedFibres = "{direction: [1, 0, 0], sheet: [0, 1, 0]}";
inline const char* const kHunterVirtualHexahedron = "[{type: virtual_hexahedron, law: hunter}]";

// The equilibrium settings of the scene's quasistatic integrator.
inline EquilibriumParams equilibriumParams(Scene& scene) {
  if (const auto* q = dynamic_cast<const QuasistaticIntegrator*>(&unguarded(*scene.integrator)))
    return q->params();
  return {};
}

// The energy of the force models (no body loads in these scenes).
inline double modelEnergy(const System& system) { return system.potentialEnergy(system.state.x); }

// --- the Hunter law (Eq. 2.153, Table 2.1), in Pa -----------------------------------------------

// Terms 11, 22, 33, 12, 13, 23 of the fibre frame (1 fibre, 2 sheet, 3 sheet-normal).
inline constexpr int kTermI[6] = {0, 1, 2, 0, 0, 1};
inline constexpr int kTermJ[6] = {0, 1, 2, 1, 2, 2};
inline constexpr double kHunterK[6] = {2842.0, 63.0, 310.0, 1000.0, 1000.0, 1000.0};
inline constexpr double kHunterA[6] = {0.318, 0.429, 1.037, 0.731, 0.731, 0.886};
inline constexpr double kHunterB[6] = {0.624, 2.48, 0.398, 2.0, 2.0, 2.0};

// w(e) = k e^2 / (a - e)^b and w'(e) of term t; NaN at or beyond the pole.
inline double hunterTerm(int t, double e) {
  if (!(e < kHunterA[t])) return std::nan("");
  return kHunterK[t] * e * e / std::pow(kHunterA[t] - e, kHunterB[t]);
}
inline double hunterTermSlope(int t, double e) {
  if (!(e < kHunterA[t])) return std::nan("");
  const double d = kHunterA[t] - e, k = kHunterK[t], b = kHunterB[t];
  return k * e * std::pow(d, -b - 1.0) * (2.0 * d + b * e);
}

// Energy density (Pa) at the Green strain Ef of the fibre frame.
inline double hunterEnergy(const Eigen::Matrix3d& Ef) {
  double w = 0.0;
  for (int t = 0; t < 6; ++t) w += hunterTerm(t, Ef(kTermI[t], kTermJ[t]));
  return w;
}

// S in the fibre frame: S_ii = w_ii', S_ij = S_ji = w_ij'/2 (each shear pair is written once in
// Eq. 2.153, so 2 dW/dC halves its derivative).
inline Eigen::Matrix3d hunterStress(const Eigen::Matrix3d& Ef) {
  Eigen::Matrix3d S;
  for (int t = 0; t < 6; ++t) {
    const int i = kTermI[t], j = kTermJ[t];
    S(i, j) = S(j, i) = (i == j ? 1.0 : 0.5) * hunterTermSlope(t, Ef(i, j));
  }
  return S;
}

// Uniaxial stretch lambda along fibre-frame axis l: the lateral strains stay zero (each term
// depends on its own strain component), F = diag with lambda at l, and the first
// Piola-Kirchhoff stress is P_ll = lambda w_ll'((lambda^2 - 1)/2).
inline double hunterUniaxialStress(int l, double lambda) {
  return lambda * hunterTermSlope(l, 0.5 * (lambda * lambda - 1.0));
}

// Energy density of F in the frame B (columns fibre, sheet, sheet-normal).
inline double hunterEnergy(const Eigen::Matrix3d& B, const Eigen::Matrix3d& F) {
  const Eigen::Matrix3d E = 0.5 * (F.transpose() * F - Eigen::Matrix3d::Identity());
  return hunterEnergy(B.transpose() * E * B);
}

// Uniaxial stress along the global axis z of the law turned to the frame B: the global S is
// s e_z (x) e_z, so the five Green strains E_xx, E_yy, E_xy, E_xz, E_yz are those at which the
// other five components of S = B S_f(B^T E B) B^T vanish, given E_zz = (lambda^2 - 1)/2 (Newton
// with a finite-difference Jacobian from the previous solution). With F e_z = lambda e_z (the
// material line along z stays along z and the force on the end face is along z), the nominal
// stress is P_zz = lambda s. `strain` holds the five strains (start and result).
inline double hunterRotatedUniaxialStress(const Eigen::Matrix3d& B, double lambda,
                                          Eigen::Matrix<double, 5, 1>& strain) {
  const double ezz = 0.5 * (lambda * lambda - 1.0);
  const auto globalStress = [&](const Eigen::Matrix<double, 5, 1>& u) {
    Eigen::Matrix3d E;
    E << u[0], u[2], u[3], u[2], u[1], u[4], u[3], u[4], ezz;
    return Eigen::Matrix3d(B * hunterStress(B.transpose() * E * B) * B.transpose());
  };
  const auto residual = [&](const Eigen::Matrix<double, 5, 1>& u) {
    const Eigen::Matrix3d S = globalStress(u);
    Eigen::Matrix<double, 5, 1> r;
    r << S(0, 0), S(1, 1), S(0, 1), S(0, 2), S(1, 2);
    return r;
  };
  for (int iteration = 0; iteration < 50; ++iteration) {
    const Eigen::Matrix<double, 5, 1> r = residual(strain);
    if (r.norm() < 1e-10) break;
    Eigen::Matrix<double, 5, 5> J;
    for (int c = 0; c < 5; ++c) {
      Eigen::Matrix<double, 5, 1> u = strain;
      u[c] += 1e-7;
      J.col(c) = (residual(u) - r) / 1e-7;
    }
    strain -= J.fullPivLu().solve(r);
  }
  if (!(residual(strain).norm() < 1e-6))
    throw std::runtime_error("the rotated uniaxial stress problem did not converge");
  return lambda * globalStress(strain)(2, 2);
}

// --- summaries -------------------------------------------------------------------------------

struct ErrorStats {
  double max = 0.0, sumSquares = 0.0;
  int count = 0;
  void add(double relative) {
    max = std::max(max, std::abs(relative));
    sumSquares += relative * relative;
    ++count;
  }
  double rms() const { return count ? std::sqrt(sumSquares / count) : 0.0; }
};

}  // namespace bench_adamss
}  // namespace tt
