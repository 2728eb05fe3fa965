// bench_adamss shear: the simple shear experiments of "Adamss: Advanced Anisotropic Mass-Spring
// System", Sec. 2.8.1 (Figs. 2.26, 2.27): the Hunter law (Eq. 2.153, Table 2.1) through the
// virtual hexahedron on the voxel (6 tets) and the 4 x 4 x 8 cuboid (768 tets), the frame
// aligned with the grid (fibre x, sheet y, sheet-normal z). The face with normal n at the upper
// end moves along d in small steps, each brought to equilibrium (tissue_cli shear,
// integrate/specimen_loading.h); the work of the controlled face (Eqs. 2.151-2.152) is compared
// with the energy stored. The energy of the homogeneous shear F = I + gamma d (x) n, which the
// free lateral faces can only lower, is written beside it.
#include <Eigen/Dense>
#include <cstdio>
#include <fstream>
#include <string>
#include <vector>

#include "specimens.h"
#include "tissue_trainer/core/integrate/specimen_loading.h"

namespace tt {
namespace bench_adamss {

namespace {

constexpr double kMaxShear = 0.5;

// The planes of Sec. 2.8.1 (normal of the moved face, direction of motion): fibre-normal,
// sheet-fibre, normal-sheet, then each with the two axes exchanged.
struct Plane {
  int normal, direction;
};
constexpr Plane kPlanes[] = {{0, 2}, {1, 0}, {2, 1}, {2, 0}, {0, 1}, {1, 2}};

std::string planeName(const Plane& p) {
  const char* letter = "fsn";
  return {letter[p.normal], letter[p.direction]};
}

struct Summary {
  std::string specimen, plane;
  double gamma = 0.0, work = 0.0, energy = 0.0, homogeneous = 0.0;
  double maxDifference = 0.0;  // max |work / energy - 1| over the steps with gamma >= 0.1
  std::string failure;
};

}  // namespace

int runShear(const Args& args) {
  return reportingErrors("shear", [&] {
    CommonOptions o;
    if (!parseCommon("shear", args, o)) return 2;
    const int steps = o.quick ? 5 : 20;
    struct Specimen {
      const char* name;
      Box box;
    };
    std::vector<Specimen> specimens = {{"voxel", {{1, 1, 1}, "six"}}};
    if (!o.quick) specimens.push_back({"cuboid_4x4x8", {{4, 4, 8}, "six"}});

    std::ofstream csv = openCsv(o.out + "/shear.csv");
    csv << "specimen,plane,shear,work_J,energy_J,homogeneous_energy_J,relative_difference\n";
    std::vector<Summary> summaries;
    bool ok = true;
    for (const Specimen& s : specimens) {
      for (const Plane& p : kPlanes) {
        Scene scene = specimenScene(s.box, kAlignedFibres, kHunterVirtualHexahedron);
        const double volume =
            s.box.cells[0] * s.box.cells[1] * s.box.cells[2] * kVoxel * kVoxel * kVoxel;
        Summary sum;
        sum.specimen = s.name;
        sum.plane = planeName(p);
        const SpecimenRun run = shearSpecimen(
            scene.system, p.normal, p.direction, kMaxShear, steps, equilibriumParams(scene),
            [&](const ShearRow& r) {
              Eigen::Matrix3d F = Eigen::Matrix3d::Identity();
              F(p.direction, p.normal) = r.shear;
              const double homogeneous = volume * hunterEnergy(Eigen::Matrix3d::Identity(), F);
              const double difference = r.energy > 0.0 ? r.work / r.energy - 1.0 : 0.0;
              if (r.shear >= 0.1 - 1e-12)
                sum.maxDifference = std::max(sum.maxDifference, std::abs(difference));
              sum.gamma = r.shear;
              sum.work = r.work;
              sum.energy = r.energy;
              sum.homogeneous = homogeneous;
              char line[256];
              std::snprintf(line, sizeof line, "%s,%s,%.6g,%.9g,%.9g,%.9g,%.6g\n", s.name,
                            sum.plane.c_str(), r.shear, r.work, r.energy, homogeneous, difference);
              csv << line;
            });
        if (!run.ok) {
          sum.failure = run.failure;
          ok = false;
        }
        summaries.push_back(sum);
      }
    }
    csv.close();

    std::printf(
        "Simple shear to gamma = %.2f (Sec. 2.8.1), Hunter law through the virtual "
        "hexahedron, %d steps; plane = normal of the moved face, then its direction "
        "(f fibre x, s sheet y, n sheet-normal z)\n",
        kMaxShear, steps);
    std::printf("%-14s %-5s %6s %13s %13s %13s %12s %14s\n", "specimen", "plane", "gamma",
                "work (J)", "energy (J)", "work/energy-1", "max |w/e-1|", "energy/homog.");
    for (const Summary& s : summaries) {
      std::printf("%-14s %-5s %6.3f %13.6e %13.6e %13.3e %12.3e %14.4f%s\n", s.specimen.c_str(),
                  s.plane.c_str(), s.gamma, s.work, s.energy, s.work / s.energy - 1.0,
                  s.maxDifference, s.energy / s.homogeneous,
                  s.failure.empty() ? "" : "  (stopped)");
      if (!s.failure.empty()) std::printf("    %s\n", s.failure.c_str());
    }
    std::printf("CSV: %s/shear.csv\n", o.out.c_str());
    plot(o, "shear");
    return ok ? 0 : 3;
  });
}

}  // namespace bench_adamss
}  // namespace tt
