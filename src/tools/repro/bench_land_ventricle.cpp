// Problem 2 of Land et al., "Verification of cardiac mechanics software: benchmark problems
// and solutions for testing active and passive material behaviour" (Proc. R. Soc. A 2015,
// Sec. 2c(ii)): passive inflation of the truncated ellipsoid left ventricle (endocardium
// r_s = 7, r_l = 17 mm; epicardium r_s = 10, r_l = 20 mm; truncated at z = 5 mm,
// mesh/generators.h truncatedEllipsoid), the base fixed, the isotropic Guccione law
// (C = 10 kPa, b_f = b_t = b_fs = 1) with the volumetric penalty of material/guccione.h, and a
// follower pressure of 10 kPa on the endocardium ramped linearly over the load steps of the
// quasistatic integrator. Prints the deformed z of the endocardial and epicardial apex beside
// the consensus of the paper's Fig. 6, for meshes of transmural x meridional x circumferential
// cells T x 4T x 8T, with DOFs, linear solves (Newton iterations and the pseudo-time steps of
// solve/equilibrium.h that take over where an apex wedge's check tets invert) and time.
//   bench_land_ventricle [--quick] [--cells T,T,...=1,2,3] [--split none|six=none]
//                        [--bulk-modulus KPA=500] [--load-steps N=20]
// (--quick: T = 1 only)
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <string>
#include <vector>

#include "common/command_line.h"
#include "tissue_trainer/core/integrate/quasistatic.h"
#include "tissue_trainer/core/material/guccione.h"
#include "tissue_trainer/core/mesh/generators.h"
#include "tissue_trainer/core/model/follower_pressure.h"
#include "tissue_trainer/core/model/hyperelastic.h"
#include "tissue_trainer/core/model/time_curve.h"

namespace {

using namespace tt;

// Fig. 6 of the paper as read by the public solutions that quote it (docs/verification.md).
constexpr double kConsensusEndo = -26.6, kConsensusEpi = -28.3;  // mm

struct VentricleResult {
  int dofs = 0;
  int solves = 0;  // Newton iterations and pseudo-time steps (equilibrium.h)
  double endo = 0.0, epi = 0.0;  // mm
  double seconds = 0.0;
  bool ok = true;
  std::string failure;
};

// The endocardial faces: the boundary triangles whose nodes all lie in layer 0.
std::vector<FollowerPressureModel::Face> endocardium(const Mesh& mesh, const EllipsoidShape& shape) {
  const int firstRing = shape.transmural + 1, perLayer = shape.meridional * shape.circumferential;
  const auto inLayer0 = [&](int n) {
    return n == 0 || (n >= firstRing && n < firstRing + perLayer);
  };
  std::vector<FollowerPressureModel::Face> faces;
  for (const Triangle& t : mesh.surface)
    if (inLayer0(t[0]) && inLayer0(t[1]) && inLayer0(t[2])) faces.push_back({t[0], t[1], t[2]});
  return faces;
}

VentricleResult solveVentricle(int cells, TetSplit split, double bulkModulus, int loadSteps) {
  EllipsoidShape shape;
  shape.transmural = cells, shape.meridional = 4 * cells, shape.circumferential = 8 * cells;
  Mesh mesh = truncatedEllipsoid(shape, split);
  System s(mesh, {Material::isotropic(1e4, 0.45, 1000.0)});
  s.models.push_back(std::make_unique<HyperelasticModel<GuccioneLaw>>(
      s.mesh, std::vector<GuccioneConstants>{{1e4, 1.0, 1.0, 1.0, 1e3 * bulkModulus}},
      LawOptions{}));
  s.models.push_back(std::make_unique<FollowerPressureModel>(
      endocardium(s.mesh, shape), TimeCurve::piecewiseLinear({0.0, 1.0}, {0.0, 1e4})));
  EquilibriumParams params;
  params.preconditioner = EquilibriumParams::Preconditioning::kCholesky;
  params.absoluteTolerance = 1e-10;
  params.relativeTolerance = 1e-10;
  params.maxNewtonIterations = 200;
  QuasistaticIntegrator quasistatic(params);
  VentricleResult r;
  r.dofs = s.numDofs() - static_cast<int>(s.constrainedDofs.size());
  const auto start = std::chrono::steady_clock::now();
  for (int step = 0; step < loadSteps && r.ok; ++step) {
    const StepReport report = quasistatic.advance(s, 1.0 / loadSteps);
    r.solves += report.jacobians;
    r.ok = report.ok;
    r.failure = report.failure;
  }
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  r.endo = 1e3 * s.state.x[3 * ellipsoidNode(shape, 0, 0, 0) + 2];
  r.epi = 1e3 * s.state.x[3 * ellipsoidNode(shape, shape.transmural, 0, 0) + 2];
  return r;
}

}  // namespace

int main(int argc, char** argv) {
  tools::CommandLine cl(argc, argv,
                        "bench_land_ventricle [--quick] [--cells T,T,...] [--split none|six] "
                        "[--bulk-modulus KPA] [--load-steps N]");
  const bool quick = cl.flag("--quick");
  const std::vector<std::string> cells =
      cl.list("--cells", quick ? std::vector<std::string>{"1"}
                               : std::vector<std::string>{"1", "2", "3"});
  const std::string splitName = cl.text("--split", "none");
  const double bulk = cl.positiveNumber("--bulk-modulus", 500.0);
  const int loadSteps = cl.positiveInteger("--load-steps", 20);
  cl.finish();
  if (splitName != "none" && splitName != "six")
    cl.fail("--split: expected none or six, got '" + splitName + "'");
  const TetSplit split = splitName == "none" ? TetSplit::kNone : TetSplit::kSix;
  std::vector<int> sizes;
  for (const std::string& c : cells) {
    const int n = std::atoi(c.c_str());
    if (n < 1) cl.fail("--cells: expected integers >= 1, got '" + c + "'");
    sizes.push_back(n);
  }
  std::printf("Land et al. 2015, problem 2: apex z (mm); split %s, bulk modulus %g kPa, "
              "%d load steps\n", splitName.c_str(), bulk, loadSteps);
  std::printf("%-10s %8s %8s %9s %9s %9s %9s %8s\n", "cells", "DOFs", "solves", "endo",
              "(consens)", "epi", "(consens)", "time (s)");
  int failures = 0;
  for (int n : sizes) {
    const VentricleResult r = solveVentricle(n, split, bulk, loadSteps);
    const std::string label =
        std::to_string(n) + "x" + std::to_string(4 * n) + "x" + std::to_string(8 * n);
    if (!r.ok) {
      std::printf("%-10s %8d failed: %s\n", label.c_str(), r.dofs, r.failure.c_str());
      ++failures;
      continue;
    }
    std::printf("%-10s %8d %8d %9.3f %9.1f %9.3f %9.1f %8.2f\n", label.c_str(), r.dofs, r.solves,
                r.endo, kConsensusEndo, r.epi, kConsensusEpi, r.seconds);
  }
  return failures == 0 ? 0 : 1;
}
