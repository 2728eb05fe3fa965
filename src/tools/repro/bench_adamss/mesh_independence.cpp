// Mesh independence ("Adamss: Advanced Anisotropic Mass-Spring System", Secs. 2.1.2 and
// 2.1.4: the anisotropy is the material's, not the mesh's; the behaviour is independent of
// the resolution and partly of the topology). The quasi-static uniaxial stretch of
// specimen_loading.h (lower face fixed, upper face moved along the axis and held laterally,
// each step to equilibrium) of a 1 cm cube to 15 % strain, on every mesh topology of the
// chapter at two resolutions: hexahedra, five tets per cell (the same split in every cell:
// neighbouring faces do not conform), five mirrored, six, six mirrored, six mirrored with every
// node moved at random by up to 20 % of a cell along each axis in which it is not on a face of
// the cube, and unstructured tets from TetGen (Debian's tetgen, quality bound 1.4, about as
// many tets as the six-tet split; left out, with a line saying so, where tetgen is missing).
//
// Cases, each through the virtual hexahedron (Sec. 2.4.2):
//   hunter_aligned  the Hunter law (Table 2.1), fibres along z, stretched along z: the exact
//                   state is homogeneous, P_zz = lambda w_11'((lambda^2 - 1)/2) = 4425.18 Pa at
//                   15 %, on every mesh;
//   hunter_rotated  the same with the fibre frame of Fig. 2.25 (theta = 49.6, phi = 21.25 deg,
//                   as the text of Sec. 2.8.1; the caption prints 21.75),
//                   stretched along z: the clamped ends make the state inhomogeneous, so the
//                   meshes can differ;
//   neo_hookean     an isotropic law (E = 10 kPa, nu = 0.45) stretched along x, y and z: any
//                   difference between the axes is anisotropy made by the mesh.
// Reported: the stress at 15 % per mesh, its spread across meshes per case and resolution,
// and for neo_hookean the spread between the three axes per mesh.
//   bench_adamss mesh_independence [--quick] [--out DIR] [--no-plot]
//   -> DIR/mesh_independence.csv (every step), DIR/mesh_independence_summary.csv, .png
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "experiment_support.h"
#include "tissue_trainer/core/integrate/specimen_loading.h"
#include "tissue_trainer/core/mesh/mesh_io.h"

namespace tt {
namespace bench_adamss {
namespace {

constexpr double kCube = 0.01;      // m
constexpr double kMaxStrain = 0.15;
constexpr int kStretchSteps = 5;
const char* const kAxisNames[3] = {"x", "y", "z"};

struct Topology {
  const char* name;
  TetSplit split;
  bool jittered;
  bool tetgen = false;
};

bool haveTetgen() { return std::system("command -v tetgen >/dev/null 2>&1") == 0; }

std::vector<Topology> topologies() {
  std::vector<Topology> all = {
      {"hex", TetSplit::kNone, false},          {"five", TetSplit::kFive, false},
      {"five_mirrored", TetSplit::kFiveMirrored, false}, {"six", TetSplit::kSix, false},
      {"six_mirrored", TetSplit::kSixMirrored, false},
      {"jittered_six_mirrored", TetSplit::kSixMirrored, true}};
  if (haveTetgen()) all.push_back({"tetgen", TetSplit::kNone, false, true});
  else std::printf("tetgen not found: the unstructured TetGen mesh is left out\n");
  return all;
}

// The cube meshed by TetGen: a piecewise linear complex of its six faces, tets of at most the
// six-tet split's volume and radius-edge ratio 1.4.
Mesh tetgenCube(int cells) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::temp_directory_path() / ("tt_bench_adamss_tetgen_" + std::to_string(cells));
  fs::create_directories(dir);
  std::ofstream poly(dir / "cube.poly");
  poly << "8 3 0 0\n";
  for (int k = 0; k < 8; ++k)
    poly << k + 1 << ' ' << (k & 1) * kCube << ' ' << (k >> 1 & 1) * kCube << ' '
         << (k >> 2 & 1) * kCube << '\n';
  poly << "6 0\n";
  for (const char* face : {"1 2 4 3", "5 6 8 7", "1 2 6 5", "3 4 8 7", "1 3 7 5", "2 4 8 6"})
    poly << "1\n4 " << face << '\n';
  poly << "0\n0\n";
  poly.close();
  const double cell = kCube / cells;
  char command[512];
  std::snprintf(command, sizeof command, "cd '%s' && tetgen -pq1.4a%.6gQ cube.poly >/dev/null 2>&1",
                dir.c_str(), cell * cell * cell / 6.0);
  if (std::system(command) != 0)
    throw std::runtime_error("tetgen failed on " + (dir / "cube.poly").string());
  return readMesh((dir / "cube.1.ele").string());
}

struct Case {
  const char* name;
  bool isotropic;
  Eigen::Matrix3d frame;
  std::vector<int> axes;
};

Mesh specimenMesh(const Topology& topology, int cells) {
  if (topology.tetgen) return tetgenCube(cells);
  Mesh mesh = cuboid(Eigen::Vector3i::Constant(cells), Eigen::Vector3d::Constant(kCube),
                     topology.split);
  if (!topology.jittered) return mesh;
  std::mt19937 rng(11);
  const double cell = kCube / cells;
  std::uniform_real_distribution<double> jitter(-0.2 * cell, 0.2 * cell);
  for (int n = 0; n < mesh.numNodes(); ++n)
    for (int i = 0; i < 3; ++i) {
      const double c = mesh.rest(i, n);
      const double shift = jitter(rng);
      if (c > 1e-9 && c < kCube - 1e-9) mesh.rest(i, n) += shift;
    }
  return mesh;
}

struct Row {
  std::string caseName, mesh;
  int cells = 0, axis = 0;
  double strain = 0.0, stress = 0.0;
};

struct Final {
  double stress = std::nan("");
  bool ok = false;
  std::string failure;
};

Final stretch(const Case& c, const Topology& topology, int cells, int axis,
              std::vector<Row>& rows) {
  Mesh mesh = specimenMesh(topology, cells);
  setFibreFrame(mesh, c.frame);
  System s(mesh, {Material::isotropic(10e3, 0.45, 1000.0)});
  if (c.isotropic) s.models.push_back(neoHookeanModel(s.mesh, s.materials[0]));
  else s.models.push_back(hunterModel(s.mesh));
  Final out;
  double lastStrain = -1.0;
  const SpecimenRun run =
      stretchSpecimen(s, axis, kMaxStrain, kStretchSteps, EquilibriumParams{},
                      [&](const StretchRow& r) {
                        rows.push_back({c.name, topology.name, cells, axis, r.strain, r.stress});
                        out.stress = r.stress;
                        lastStrain = r.strain;
                      });
  out.ok = run.ok && std::abs(lastStrain - kMaxStrain) < 1e-12 && std::isfinite(out.stress);
  out.failure = run.failure;
  // The solve's residual leaves out the moved face's nodes, whose force gives the stress.
  if (run.ok && !std::isfinite(out.stress))
    out.failure = "the force on the moved face is not finite (the free nodes converged)";
  if (!out.ok) out.stress = std::nan("");
  return out;
}

}  // namespace

int runMeshIndependence(const Args& args) {
  Options o;
  if (!parseOptions("mesh_independence", args, {}, o)) return 2;
  Eigen::Matrix3d aligned;
  aligned << Eigen::Vector3d::UnitZ(), Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY();
  const std::vector<Case> cases = {
      {"hunter_aligned", false, aligned, {2}},
      {"hunter_rotated", false, sphericalFrame(49.6, 21.25), {2}},
      {"neo_hookean", true, Eigen::Matrix3d::Identity(), {0, 1, 2}}};
  const std::vector<int> resolutions = o.quick ? std::vector<int>{2} : std::vector<int>{3, 6};

  const std::vector<Topology> kTopologies = topologies();
  std::vector<Row> rows;
  // (case, cells) -> mesh -> axis -> final stress
  std::map<std::pair<std::string, int>, std::map<std::string, std::map<int, Final>>> finals;
  for (const Case& c : cases)
    for (int cells : resolutions)
      for (const Topology& t : kTopologies)
        for (int axis : c.axes) {
          const Final f = stretch(c, t, cells, axis, rows);
          finals[{c.name, cells}][t.name][axis] = f;
          std::printf("progress mesh_independence %s %d^3 %s along %s: %s\n", c.name, cells,
                      t.name, kAxisNames[axis],
                      f.ok ? (std::to_string(f.stress) + " Pa").c_str() : f.failure.c_str());
          std::fflush(stdout);
        }

  FILE* csv = openCsv(o, "mesh_independence.csv");
  std::fprintf(csv, "case,mesh,cells,axis,strain,stress_pa\n");
  for (const Row& r : rows)
    std::fprintf(csv, "%s,%s,%d,%s,%.9g,%.12g\n", r.caseName.c_str(), r.mesh.c_str(), r.cells,
                 kAxisNames[r.axis], r.strain, r.stress);
  std::fclose(csv);

  FILE* summary = openCsv(o, "mesh_independence_summary.csv");
  std::fprintf(summary, "case,cells,mesh,axis,stress_pa,ok,spread_across_meshes,"
                        "spread_between_axes,failure\n");
  std::printf("\nUniaxial stretch to %g %% of a 1 cm cube (stress P at the end, Pa); spread = "
              "(max - min) / mean\n",
              100 * kMaxStrain);
  for (const Case& c : cases)
    for (int cells : resolutions) {
      const auto& byMesh = finals[{c.name, cells}];
      for (int axis : c.axes) {
        std::vector<double> across;
        for (const auto& [mesh, byAxis] : byMesh)
          if (byAxis.at(axis).ok) across.push_back(byAxis.at(axis).stress);
        const double spreadMeshes = relativeSpread(across);
        std::printf("%-15s %d^3 along %s: spread across %zu meshes %.3e\n", c.name, cells,
                    kAxisNames[axis], across.size(), spreadMeshes);
        for (const Topology& t : kTopologies) {
          const auto& byAxis = byMesh.at(t.name);
          std::vector<double> axes;
          for (const auto& [a, f] : byAxis)
            if (f.ok) axes.push_back(f.stress);
          const double spreadAxes = c.axes.size() > 1 && axes.size() == c.axes.size()
                                        ? relativeSpread(axes)
                                        : std::nan("");
          const Final& f = byAxis.at(axis);
          std::fprintf(summary, "%s,%d,%s,%s,%.12g,%d,%.6g,%.6g,%s\n", c.name, cells, t.name,
                       kAxisNames[axis], f.stress, f.ok, spreadMeshes, spreadAxes,
                       f.failure.c_str());
          std::printf("    %-22s %14.6f Pa%s", t.name, f.stress, f.ok ? "" : " (failed)");
          if (c.axes.size() > 1 && axis == c.axes.back())
            std::printf("   spread between axes %.3e", spreadAxes);
          std::printf("\n");
        }
      }
    }
  std::fclose(summary);
  drawPlot("mesh_independence", o);
  std::printf("wrote %s/mesh_independence.csv and mesh_independence_summary.csv\n",
              o.out.c_str());
  return 0;
}

}  // namespace bench_adamss
}  // namespace tt
