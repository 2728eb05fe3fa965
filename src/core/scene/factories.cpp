#include "tissue_trainer/core/scene/factories.h"

#include "tissue_trainer/core/integrate/backward_euler.h"
#include "tissue_trainer/core/integrate/explicit_euler.h"
#include "tissue_trainer/core/integrate/newtonian.h"
#include "tissue_trainer/core/integrate/radau_iia.h"
#include "tissue_trainer/core/model/edge_length.h"
#include "tissue_trainer/core/model/stvk_displacement.h"
#include "tissue_trainer/core/model/tensor_mass.h"

namespace tt {

const char* const kElasticModelNames =
    "edge_length, edge_length_literal, stvk_displacement, stvk_displacement_paper_literal, "
    "tensor_mass";

std::unique_ptr<ForceModel> makeElasticModel(const std::string& name, const Mesh& mesh,
                                             const std::vector<Material>& materials) {
  if (name == "edge_length") return std::make_unique<EdgeLengthModel>(mesh, materials);
  if (name == "edge_length_literal")
    return std::make_unique<EdgeLengthModel>(mesh, materials, EdgeLengthPath::kLiteral);
  if (name == "stvk_displacement") return std::make_unique<StvkDisplacementModel>(mesh, materials);
  if (name == "stvk_displacement_paper_literal")
    return std::make_unique<StvkDisplacementModel>(mesh, materials, AlphaSign::kPaperLiteral);
  if (name == "tensor_mass") return std::make_unique<TensorMassModel>(mesh, materials);
  return nullptr;
}

std::unique_ptr<ForceModel> makeForceModel(const YamlEntry& spec, const System& system) {
  const std::string type =
      spec["type"].choice({"edge_length", "stvk_displacement", "tensor_mass"});
  if (type == "edge_length") {
    spec.expectMap({"type", "path"});
    EdgeLengthPath path = EdgeLengthPath::kFast;
    if (spec.has("path")) parseEdgeLengthPath(spec["path"].choice({"fast", "literal"}), path);
    return std::make_unique<EdgeLengthModel>(system.mesh, system.materials, path);
  }
  if (type == "stvk_displacement") {
    spec.expectMap({"type", "alpha_sign"});
    AlphaSign sign = AlphaSign::kCorrect;
    if (spec.has("alpha_sign"))
      parseAlphaSign(spec["alpha_sign"].choice({"correct", "paper_literal"}), sign);
    return std::make_unique<StvkDisplacementModel>(system.mesh, system.materials, sign);
  }
  spec.expectMap({"type"});
  return std::make_unique<TensorMassModel>(system.mesh, system.materials);
}

std::unique_ptr<Integrator> makeIntegrator(const YamlEntry& spec) {
  const std::string type = spec["type"].choice(
      {"backward_euler", "newtonian", "radau_iia", "explicit_euler", "symplectic_euler"});
  if (type == "backward_euler") {
    spec.expectMap({"type", "substeps", "linear_tolerance", "linear_max_iterations",
                    "newton_iterations", "newton_tolerance", "require_convergence",
                    "warm_start"});
    BackwardEulerParams p;
    p.substeps = spec.integerAtLeast("substeps", 1, p.substeps);
    p.linearTolerance = spec.positive("linear_tolerance", p.linearTolerance);
    p.linearMaxIterations = spec.integerAtLeast("linear_max_iterations", 1, p.linearMaxIterations);
    p.newtonIterations = spec.integerAtLeast("newton_iterations", 1, p.newtonIterations);
    p.newtonTolerance = spec.positive("newton_tolerance", p.newtonTolerance);
    p.requireConvergence = spec.boolean("require_convergence", p.requireConvergence);
    p.warmStart = spec.boolean("warm_start", p.warmStart);
    return std::make_unique<BackwardEulerIntegrator>(p);
  }
  if (type == "newtonian") {
    spec.expectMap({"type", "time_step", "equal_steps", "force_threshold"});
    NewtonianParams p;
    p.substep = spec.positive("time_step", p.substep);
    p.assumeEqualSteps = spec.boolean("equal_steps", p.assumeEqualSteps);
    if (spec.has("force_threshold")) {
      const YamlEntry e = spec["force_threshold"];
      p.forceThreshold = e.number();
      if (p.forceThreshold < 0.0) e.fail("expected a non-negative force threshold (N)");
    }
    return std::make_unique<NewtonianIntegrator>(p);
  }
  if (type == "radau_iia") {
    spec.expectMap({"type", "jacobian", "abs_tol", "rel_tol", "adaptive", "initial_step",
                    "max_step", "max_newton_iterations"});
    RadauOptions o;
    if (spec.has("jacobian")) {
      const std::string j = spec["jacobian"].choice({"analytical", "numerical", "simplified"});
      o.jacobian = j == "analytical" ? RadauJacobian::kAnalytical
                   : j == "numerical" ? RadauJacobian::kNumerical : RadauJacobian::kSimplified;
    }
    o.absTol = spec.positive("abs_tol", o.absTol);
    o.relTol = spec.positive("rel_tol", o.relTol);
    o.adaptive = spec.boolean("adaptive", o.adaptive);
    o.initialStep = spec.positive("initial_step", o.initialStep);
    o.maxStep = spec.positive("max_step", o.maxStep);
    o.maxNewtonIterations = spec.integerAtLeast("max_newton_iterations", 1, o.maxNewtonIterations);
    return std::make_unique<RadauIIA>(o);
  }
  spec.expectMap({"type", "time_step"});
  ExplicitEulerParams p;
  p.substep = spec.positive("time_step", p.substep);
  p.symplectic = type == "symplectic_euler";
  return std::make_unique<ExplicitEulerIntegrator>(p);
}

}  // namespace tt
