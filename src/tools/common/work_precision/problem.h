#pragma once
// The problems of bench_work_precision (and bench_bullet_peer). Each builds a System for a
// force model by name, says how long to run and how finely to sample, and turns a sampled run
// into its error (against the analytic or reference value the report names) and its discrete
// error (against the exact solution of the same mesh and model, i.e. the integrator's own
// share). One source file per family: beam_problems.cpp (the cantilever, the large
// deflection, the spindle), patch_test.cpp, uniaxial_stretch.cpp, muscle_contraction.cpp.
#include <Eigen/Core>
#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/system.h"

namespace tt {
namespace work_precision {

constexpr double kPi = 3.14159265358979323846;
const double kNaN = std::nan("");

struct Trajectory {
  std::vector<double> t;
  std::vector<Eigen::VectorXd> x, v;
};

struct Errors {
  double error = kNaN;     // the error measure (relative)
  double discrete = kNaN;  // against the same mesh and model solved exactly (relative)
  std::string note;
};

// A number the report quotes (analytic values, references and their own accuracy).
struct Fact {
  std::string quantity;
  double value;
  std::string unit, meaning;
};

class Problem {
 public:
  virtual ~Problem() = default;
  virtual std::unique_ptr<System> build(const std::string& model) const = 0;
  // Reference solutions for these models (not timed); called once before the runs.
  virtual void prepare(const std::vector<std::string>& /*models*/) {}
  virtual Errors evaluate(const std::string& model, const Trajectory& run) const = 0;

  std::string name;
  double duration = 0.0;        // s simulated
  double sampleInterval = 0.0;  // s; the frame of the explicit and adaptive runs
  double bodySize = 0.0;        // m; a node moving 10 body sizes counts as a blow-up
  double lengthScale = 0.0, velocityScale = 0.0;  // absolute tolerances of Radau IIA
  double stableStep = 0.0;      // s; 2 / omega_max at rest
  std::vector<double> implicitSteps;  // s; the backward Euler sweep
  std::vector<Fact> facts;
  // The models this problem runs instead of the registry's presets (empty: the presets).
  std::vector<std::string> models;
  // A static problem (its answer is an equilibrium): the quasistatic solver runs it too.
  bool isStatic = false;
};

// The problems' names in the report's order.
const std::vector<std::string>& problemNames();
// The named problem (one of problemNames(); throws std::invalid_argument otherwise). quick:
// the reference solutions at relative tolerance 1e-6 instead of their tight default.
std::unique_ptr<Problem> makeProblem(const std::string& name, bool quick);

// Radau IIA at relative tolerance `tol`, the absolute ones scaled by the problem's lengths.
RadauOptions radauOptions(const Problem& p, double tol);

// Why a run counts as unstable ("" when it does not): a non-finite state, or a node that moved
// more than 10 body sizes from its rest position.
std::string blowUp(const Eigen::VectorXd& x, const Eigen::VectorXd& v,
                   const Eigen::VectorXd& rest, double bodySize);

// --- the cantilever beam --------------------------------------------------------------------

struct Beam {
  double length = 0.1, width = 0.01;  // m
  double young = 1e5, poisson = 0.3, density = 1000.0;  // Pa, -, kg/m^3
  int cellsAcross = 2;                 // cells along = 10 x cells across

  double inertia() const { return std::pow(width, 4) / 12.0; }
  // Euler-Bernoulli: tip deflection under a uniform load q = rho g A, q L^4 / (8 E I).
  double tipDeflection(double g) const {
    return density * g * width * width * std::pow(length, 4) / (8.0 * young * inertia());
  }
  // Euler-Bernoulli: first bending frequency, (beta L)^2 sqrt(E I / (rho A L^4)), rad/s.
  double firstOmega() const {
    const double betaL = 1.87510407;
    return betaL * betaL *
           std::sqrt(young * inertia() / (density * width * width * std::pow(length, 4)));
  }
};

// The beam (cantileverBeam: 10 cellsAcross cells along, the end x = 0 fixed) with one model,
// gravity along -z and mass-proportional damping.
std::unique_ptr<System> beamSystem(const Beam& beam, const std::string& model,
                                   double gravity, double dampingRate);

// The nodes of the beam's free end (x = length).
std::vector<int> tipNodes(const Mesh& mesh, double length);

// Mean displacement (or velocity, with rest = 0) of the given nodes.
Eigen::Vector3d meanOf(const Eigen::VectorXd& x, const Eigen::Matrix3Xd& rest,
                       const std::vector<int>& nodes);

// Static equilibrium by Newton's method with a sparse Cholesky solve of -K (the bench's own
// reference solver, not an integrator). Returns the Newton iterations, or kNoEquilibrium when a
// factorisation fails, a step is not finite or none falls below tolerance in 50 iterations: then
// x is no solution (a tangent singular at rest, as for springs without linear stiffness along
// an axis).
constexpr int kNoEquilibrium = -1;
int staticEquilibrium(const System& s, Eigen::VectorXd& x, double tolerance);

// |value - exact| / |exact|.
double relative(double value, double exact);

// The problems' own factories (problemNames() gives their names).
std::unique_ptr<Problem> makeCantileverStatic();
std::unique_ptr<Problem> makeCantileverVibration();
std::unique_ptr<Problem> makeBeamLargeDeflection(double referenceTolerance);
std::unique_ptr<Problem> makeSpindlePull(double referenceTolerance);
std::unique_ptr<Problem> makePatchTest();
std::unique_ptr<Problem> makeUniaxialStretch(double referenceTolerance);
std::unique_ptr<Problem> makeMuscleContraction();

}  // namespace work_precision
}  // namespace tt
