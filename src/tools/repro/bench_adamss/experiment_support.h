#pragma once
// What the bench_adamss experiments volume, scaling and mesh_independence share: their
// command line, the cuboid meshes, the Adamss force models they build without a scene (the
// Hunter law of Table 2.1, the volume term of Eq. 2.86 and an isotropic law, each through the
// virtual hexahedron of Sec. 2.4.2), the volume of a deformed mesh, CSV files, the log-log
// fit and the plots (scripts/report/adamss_plots.py).
#include <Eigen/Core>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "experiments.h"
#include "tissue_trainer/core/material/hunter.h"
#include "tissue_trainer/core/material/neo_hookean.h"
#include "tissue_trainer/core/material/volume.h"
#include "tissue_trainer/core/mesh/corrupt_elements.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/adamss/virtual_hexahedron.h"

namespace tt {
namespace bench_adamss {

// --- the command line ------------------------------------------------------------------------

struct Options {
  std::string out = std::string(TT_SOURCE_ROOT) + "/docs/report/adamss";
  bool quick = false;
  bool plot = true;                 // --no-plot: the CSV files only
  std::vector<std::string> values;  // of the experiment's own options, in the order named
};

// Reads --quick, --out DIR, --no-plot and the experiment's options `named` (each "--name" takes
// one value, empty when not given); bad input is one error line and exit 2. False (with the
// reason on stderr) when the output folder cannot be made.
inline bool parseOptions(const char* experiment, const Args& args,
                         const std::vector<std::string>& named, Options& o) {
  const std::string tool = std::string("bench_adamss ") + experiment;
  std::string usage = tool + " [--quick] [--out DIR] [--no-plot]";
  for (const std::string& n : named) usage += " [--" + n + " VALUE]";
  tools::CommandLine options(tool, args, usage);
  o.quick = options.flag("--quick");
  o.plot = !options.flag("--no-plot");
  o.out = options.text("--out", o.out);
  o.values.clear();
  for (const std::string& n : named) o.values.push_back(options.text("--" + n, ""));
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

// --- meshes and models -------------------------------------------------------------------------

// A cuboid of cells.x x cells.y x cells.z cells spanning [0, size], split as asked (kNone:
// hexahedra).
inline Mesh cuboid(const Eigen::Vector3i& cells, const Eigen::Vector3d& size, TetSplit split) {
  Mesh mesh = boxGrid(cells.x() + 1, cells.y() + 1, cells.z() + 1, size, split);
  mesh.fillDefaults();
  return mesh;
}

// The same fibre frame (columns fibre, sheet, sheet-normal) for every tet and hex.
inline void setFibreFrame(Mesh& mesh, const Eigen::Matrix3d& frame) {
  mesh.fibreFrame.assign(mesh.tets.size(), frame);
  mesh.hexFibreFrame.assign(mesh.hexes.size(), frame);
}

// A frame whose fibre has polar angle theta and azimuth phi (degrees) in the mesh's axes; the
// sheet is the polar unit vector, the sheet-normal completes a right-handed frame.
inline Eigen::Matrix3d sphericalFrame(double thetaDegrees, double phiDegrees) {
  const double t = thetaDegrees * M_PI / 180.0, p = phiDegrees * M_PI / 180.0;
  const Eigen::Vector3d fibre(std::sin(t) * std::cos(p), std::sin(t) * std::sin(p), std::cos(t));
  const Eigen::Vector3d sheet(std::cos(t) * std::cos(p), std::cos(t) * std::sin(p), -std::sin(t));
  Eigen::Matrix3d frame;
  frame << fibre, sheet, fibre.cross(sheet);
  return frame;
}

// A law through the virtual hexahedron (shape-function F), one constant set for material 0.
template <class Law>
std::unique_ptr<ForceModel> virtualHexahedron(const Mesh& mesh,
                                              const typename Law::Constants& constants) {
  return std::make_unique<adamss::VirtualHexahedronModel<Law>>(
      mesh, std::vector<typename Law::Constants>{constants}, LawOptions{},
      adamss::DeformationGradientSource::kShapeFunctions);
}

// The Hunter pole-zero law with Table 2.1 (Eq. 2.153).
inline std::unique_ptr<ForceModel> hunterModel(const Mesh& mesh) {
  return virtualHexahedron<HunterLaw>(mesh, HunterConstants::table21());
}

// The volume term p (det F - 1)^2 of Eq. 2.86, p in Pa.
inline std::unique_ptr<ForceModel> volumeModel(const Mesh& mesh, double p) {
  VolumeLaw::Constants k;
  k.stiffness = p;
  return virtualHexahedron<VolumeLaw>(mesh, k);
}

inline std::unique_ptr<ForceModel> neoHookeanModel(const Mesh& mesh, const Material& material) {
  return virtualHexahedron<NeoHookeanLaw>(mesh, NeoHookeanLaw::constants(material));
}

// The volume of the mesh at positions x (3n): tets exactly, hexes as the sum of their six-tet
// split ("Adamss: Advanced Anisotropic Mass-Spring System", Sec. 2.9.1).
inline double meshVolume(const Mesh& mesh, const Eigen::VectorXd& x) {
  const Eigen::Map<const Eigen::Matrix3Xd> positions(x.data(), 3, mesh.numNodes());
  double volume = 0.0;
  for (const Tet& t : mesh.tets) volume += tetVolume(positions, t);
  for (const Hex& h : mesh.hexes) volume += hexVolumeFromTets(positions, h, true);
  return volume;
}

// The volume the volume term sees (Eq. 2.86 through the virtual hexahedron): tets exactly,
// each hex as V0 det F at its centre, for the axis-aligned box hexes of boxGrid (there column i
// of F(0) is the mean of the nodes on the hex's upper face i minus that of its lower face, over
// the edge length). Hourglass modes change meshVolume but not this.
inline double centreVolume(const Mesh& mesh, const Eigen::VectorXd& x) {
  const Eigen::Map<const Eigen::Matrix3Xd> positions(x.data(), 3, mesh.numNodes());
  double volume = 0.0;
  for (const Tet& t : mesh.tets) volume += tetVolume(positions, t);
  for (const Hex& h : mesh.hexes) {
    Eigen::Vector3d lo = mesh.rest.col(h[0]), hi = lo;
    for (int p : h) lo = lo.cwiseMin(mesh.rest.col(p)), hi = hi.cwiseMax(mesh.rest.col(p));
    const Eigen::Vector3d centre = 0.5 * (lo + hi), edge = hi - lo;
    Eigen::Matrix3d F = Eigen::Matrix3d::Zero();
    for (int p : h)
      for (int i = 0; i < 3; ++i)
        F.col(i) += (mesh.rest(i, p) > centre[i] ? 0.25 : -0.25) / edge[i] * x.segment<3>(3 * p);
    volume += edge.prod() * F.determinant();
  }
  return volume;
}

// The nodes whose rest coordinate `axis` is within 1e-9 m of `value`.
inline std::vector<int> nodesAt(const Mesh& mesh, int axis, double value) {
  std::vector<int> nodes;
  for (int n = 0; n < mesh.numNodes(); ++n)
    if (std::abs(mesh.rest(axis, n) - value) < 1e-9) nodes.push_back(n);
  return nodes;
}

// --- output ----------------------------------------------------------------------------------

// Opens DIR/NAME for writing; a file that cannot be written ends the run (exit 1).
inline FILE* openCsv(const Options& o, const std::string& name) {
  const std::string path = o.out + "/" + name;
  FILE* f = std::fopen(path.c_str(), "w");
  if (!f) {
    std::fprintf(stderr, "bench_adamss: cannot write %s\n", path.c_str());
    std::exit(1);
  }
  return f;
}

// Draws DIR/EXPERIMENT.png from the experiment's CSV with scripts/report/adamss_plots.py
// (unless --no-plot).
// A missing python or matplotlib is a warning, not a failure (the CSV is the result).
inline void drawPlot(const char* experiment, const Options& o) {
  if (!o.plot) return;
  const std::string command = std::string("/usr/bin/python3 ") + TT_SOURCE_ROOT +
                              "/scripts/report/adamss_plots.py " + experiment + " '" + o.out +
                              "'";
  if (std::system(command.c_str()) == 0)
    std::printf("drew %s/%s.png\n", o.out.c_str(), experiment);
  else
    std::fprintf(stderr, "bench_adamss %s: no plot (%s failed)\n", experiment, command.c_str());
}

// Least-squares slope of log(y) against log(x).
inline double logLogSlope(const std::vector<double>& x, const std::vector<double>& y) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    sx += lx, sy += ly, sxx += lx * lx, sxy += lx * ly;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

// (max - min) / |mean| of the values.
inline double relativeSpread(const std::vector<double>& v) {
  if (v.empty()) return std::nan("");
  double lo = v.front(), hi = v.front(), sum = 0.0;
  for (double x : v) lo = std::min(lo, x), hi = std::max(hi, x), sum += x;
  return (hi - lo) / std::abs(sum / static_cast<double>(v.size()));
}

}  // namespace bench_adamss
}  // namespace tt
