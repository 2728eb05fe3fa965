#include "tissue_trainer/core/integrate/stability_guard.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <limits>

#include "frame_guard.h"

namespace tt {
namespace {

// The share of the carried sums that the next frame keeps: they forget in about 100 frames, so
// that the energy swing of a stable step does not add up over a session, while a growing mode
// outgrows the loss.
constexpr double kCarriedKeeps = 0.99;

std::string format(const char* pattern, double a, double b = 0.0, double c = 0.0,
                   double d = 0.0, double e = 0.0) {
  char text[320];
  std::snprintf(text, sizeof text, pattern, a, b, c, d, e);
  return text;
}

// In the mesh file's node numbers (mesh.numbering), as the scene and its files name nodes.
std::string dofName(const Mesh& mesh, Eigen::Index dof) {
  const int node = mesh.numbering.nodeToFile(static_cast<int>(dof / 3));
  return "DOF " + std::to_string(3 * node + dof % 3) + " (node " + std::to_string(node) + " " +
         "xyz"[dof % 3] + ")";
}

// The first non-finite entry of v, or -1.
Eigen::Index firstNonFinite(const Eigen::VectorXd& v) {
  for (Eigen::Index i = 0; i < v.size(); ++i)
    if (!std::isfinite(v[i])) return i;
  return -1;
}

// Adds what `piece` did to `total`; a rejected piece's steps count as rejected.
void addWork(StepReport& total, const StepReport& piece, bool accepted) {
  (accepted ? total.substeps : total.rejected) += piece.substeps;
  total.rejected += piece.rejected;
  total.newtonIterations += piece.newtonIterations;
  total.linearIterations += piece.linearIterations;
  total.jacobians += piece.jacobians;
  if (!accepted) return;
  if (std::isnan(total.errorEstimate) || piece.errorEstimate > total.errorEstimate)
    total.errorEstimate = piece.errorEstimate;
  total.lastStep = piece.lastStep;
}

}  // namespace

void GuardStats::add(const GuardFrame& frame) {
  ++frames;
  halvings += frame.halvings;
  if (!frame.ok) ++failures;
  else if (frame.halvings > 0) ++recoveries;
  if (frame.cutShort) ++cutShort;
  if (!frame.reason.empty()) lastReason = frame.reason;
}

StabilityGuard::StabilityGuard(std::unique_ptr<Integrator> inner, StabilityGuardParams params)
    : inner_(std::move(inner)), params_(params) {}

double StabilityGuard::now() const {
  if (params_.wallClock) return params_.wallClock();
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

StepReport StabilityGuard::advance(System& system, double frameTime) {
  frameClock_ = now();
  prepare(system);
  StepReport report;
  GuardFrame& guard = lastFrame_;
  guard = GuardFrame{};
  const Eigen::Index badLoad = firstNonFinite(system.externalForce);
  if (badLoad >= 0) {  // no step can help: fail before touching the state
    guard.reason = "non-finite external force at " + dofName(system.mesh, badLoad) +
                   format(" at t = %.9g s", system.state.t);
    report.failure = "stability guard: " + guard.reason + "; state kept";
    report.ok = false;
  } else {
    startFrame(system);
    for (int depth = startDepth_;; ++depth) {
      StepReport work;
      const std::string problem = attempt(system, frameTime, depth, work);
      addWork(report, work, problem.empty());
      if (problem.empty()) {
        carryExcess();
        keepDepth(depth, guard.halvings > 0);
        measured_ = system.state;  // where end_ was measured
        if (!std::isnan(cutShortAt_)) {
          guard.cutShort = true;
          guard.reason = format("frame cut short for the wall-time budget at t = %.9g s "
                                "(steps of 1/%.0f)", cutShortAt_, double(1 << depth));
        }
        break;
      }
      system.state = frameStart_;
      if (!stoppedForBudget_) guard.reason = problem;
      const std::string spent = budgetSpent();
      if (depth >= params_.maxHalvings || !spent.empty()) {
        report.failure = "stability guard: " + guard.reason + ", still failing after " +
                         std::to_string(depth) + " halvings (steps of 1/" +
                         std::to_string(1 << depth) + ")" + (spent.empty() ? "" : "; " + spent) +
                         "; state restored";
        report.ok = false;
        // Out of time before out of halvings: the next frame starts one halving deeper, so
        // that frames too slow to retry within the budget still make progress.
        if (!spent.empty() && depth < params_.maxHalvings) {
          startDepth_ = depth + 1;
          calmFrames_ = 0;
        }
        // The restored state is where frameBalance_ was measured: the next frame continues
        // from it, carried sum included, which forgets a little even so.
        measured_ = frameStart_;
        end_ = frameBalance_;
        forgetCarried();
        break;
      }
      ++guard.halvings;
    }
    inner_->setStepDivisor(1);
  }
  report.wallSeconds = now() - frameClock_;
  guard.ok = report.ok;
  stats_.add(guard);
  return report;
}

void StabilityGuard::keepDepth(int depth, bool rolledBack) {
  if (rolledBack) {
    startDepth_ = depth;
    calmFrames_ = 0;
  } else if (startDepth_ > 0 && ++calmFrames_ >= params_.relaxAfter) {
    --startDepth_;
    calmFrames_ = 0;
  }
}

void StabilityGuard::prepare(const System& system) {
  const Mesh& mesh = system.mesh;
  const std::size_t elements = mesh.tets.size() + mesh.hexes.size();
  if (prepared_ != &system || preparedElements_ != elements) {
    corruptCheck_ = CorruptElementCheck(mesh);
    preparedElements_ = elements;
    prepared_ = &system;
  }
  checkVolumes_ = std::any_of(system.models.begin(), system.models.end(),
                              [](const auto& m) { return !m->toleratesInversion(); });
}

void StabilityGuard::startFrame(const System& system) {
  frameStart_ = system.state;
  // A frame that starts where the last one ended has its energies measured already (the
  // models with energy do not change between frames); the loads (contact) may have.
  const State& s = system.state;
  if (s.t == measured_.t && s.x.size() == measured_.x.size() && s.x == measured_.x &&
      s.v == measured_.v) {
    frameBalance_ = end_;
    measureLoads(system, frameBalance_);
  } else {
    measure(system, frameBalance_);
    carried_ = {};  // the state was changed from outside: the excess restarts
  }
  measured_.t = std::numeric_limits<double>::quiet_NaN();  // end_ is about to change
  loadForce_ = system.externalForce;
  for (const auto& model : system.models)
    if (model->isBodyLoad()) model->addForce(system.state.x, system.state.v, loadForce_);
  loadRate_ = 0.0;
  for (Eigen::Index dof = 0; dof < loadForce_.size(); ++dof)
    if (!system.isConstrained[dof] && system.mass[dof] > 0.0)
      loadRate_ += 0.5 * loadForce_[dof] * loadForce_[dof] / system.mass[dof];
}

std::string StabilityGuard::attempt(System& system, double frameTime, int depth,
                                    StepReport& work) {
  const int pieces = 1 << depth;
  inner_->setStepDivisor(pieces);
  flows_ = {};
  stoppedForBudget_ = false;
  cutShortAt_ = std::numeric_limits<double>::quiet_NaN();
  const double t0 = frameStart_.t;
  for (int i = 0; i < pieces; ++i) {
    const double start = system.state.t;
    const double end = detail::substepEnd(t0, frameTime, i, pieces);
    pieceX_ = system.state.x;
    pieceT_ = start;
    if (i == 0) pieceStart_ = frameBalance_;
    else std::swap(pieceStart_, end_);
    // One piece takes the frame time itself, so that a frame that passes is bit-identical.
    const double pieceClock = now();
    const StepReport step = inner_->advance(system, pieces == 1 ? frameTime : end - start);
    notePieceTime(now() - pieceClock);
    addWork(work, step, true);
    std::string problem = step.ok ? check(system, step.lastStep) : "integrator failed: " + step.failure;
    if (!problem.empty())
      return problem + format(" in t = [%.9g, %.9g] s", start, end);
    if (i + 1 < pieces && !budgetSpent().empty()) {
      // A retry stops and fails. The frame's first attempt keeps the pieces it made, all
      // checked, and ends the frame early: a frame that starts deep still advances, within
      // the budget and one piece.
      if (depth == startDepth_) {
        cutShortAt_ = end;
        return {};
      }
      stoppedForBudget_ = true;
      return format("stopped for the budget at t = %.9g s", end);
    }
  }
  return {};
}

void StabilityGuard::notePieceTime(double seconds) {
  constexpr double kNewWeight = 0.2;  // the mean follows a change of cost within a few frames
  typicalPiece_ = typicalPiece_ == 0.0 ? seconds : (1.0 - kNewWeight) * typicalPiece_ + kNewWeight * seconds;
}

double StabilityGuard::wallBudget() const {
  if (params_.wallBudget <= 0.0) return 0.0;
  return std::max(params_.wallBudget, params_.wallBudgetSteps * typicalPiece_);
}

std::string StabilityGuard::budgetSpent() const {
  const double budget = wallBudget();
  if (budget <= 0.0) return {};
  const double used = now() - frameClock_;
  if (used < budget) return {};
  return format("the frame's wall-time budget of %.3g ms is spent (%.3g ms)", 1e3 * budget,
                1e3 * used);
}

std::string StabilityGuard::check(const System& system, double lastStep) {
  std::string problem = checkFinite(system);
  if (problem.empty() && checkVolumes_) problem = checkVolumes(system);
  if (problem.empty()) problem = checkEnergy(system, lastStep);
  return problem;
}

std::string StabilityGuard::checkFinite(const System& system) const {
  const State& s = system.state;
  if (s.x.allFinite() && s.v.allFinite()) return {};
  const Eigen::Index x = firstNonFinite(s.x);
  if (x >= 0) return "non-finite position at " + dofName(system.mesh, x);
  return "non-finite velocity at " + dofName(system.mesh, firstNonFinite(s.v));
}

std::string StabilityGuard::checkVolumes(const System& system) const {
  const Eigen::Map<const Eigen::Matrix3Xd> x(system.state.x.data(), 3, system.numNodes());
  const std::vector<CorruptElement> corrupt = corruptCheck_.find(x, params_.minVolumeRatio);
  if (corrupt.empty()) return {};
  const CorruptElement& worst = *std::min_element(
      corrupt.begin(), corrupt.end(), [](const CorruptElement& a, const CorruptElement& b) {
        return a.volumeRatio < b.volumeRatio;
      });
  // The tet's number in the mesh file (mesh.numbering), which the user can look up.
  const std::string element =
      !worst.hex ? "tet " + std::to_string(system.mesh.numbering.tetToFile(worst.index))
                 : "hex " + std::to_string(worst.index) + " (tet " +
                       std::to_string(worst.subTet % 6) + " of its " +
                       (worst.subTet < 6 ? "six" : "five") + "-tet split)";
  return element + format(" inverted or flat (volume %.3g of rest, limit %.3g; elements at or "
                          "below it: %.0f)",
                          worst.volumeRatio, params_.minVolumeRatio, double(corrupt.size()));
}

void StabilityGuard::addFlows(const System& system) {
  const Eigen::VectorXd& x1 = system.state.x;
  for (Eigen::Index dof = 0; dof < x1.size(); ++dof)
    if (!system.isConstrained[dof])
      flows_.work += 0.5 * (pieceStart_.loadForce[dof] + end_.loadForce[dof]) * (x1[dof] - pieceX_[dof]);
  if (!system.controlled.empty())
    for (size_t k = 0; k < system.constrainedDofs.size(); ++k) {
      const int dof = system.constrainedDofs[k];
      flows_.work -= 0.5 * (pieceStart_.constrainedForce[k] + end_.constrainedForce[k]) *
                     (x1[dof] - pieceX_[dof]);
    }
  flows_.damping -= 0.5 * (pieceStart_.dampingPower + end_.dampingPower) * (system.state.t - pieceT_);
}

std::string StabilityGuard::checkEnergy(const System& system, double lastStep) {
  measure(system, end_);
  addFlows(system);
  const Balance& b0 = frameBalance_;
  const double startEnergy = b0.kinetic + b0.elastic;
  const double endEnergy = end_.kinetic + end_.elastic;
  const double excess =
      endEnergy + end_.body - startEnergy - b0.body - flows_.work - flows_.damping;
  const double scale = std::max({startEnergy, std::abs(flows_.work),
                                 std::abs(end_.body - b0.body), loadRate_ * lastStep * lastStep});
  const double budget = (params_.energyGrowth - 1.0) * scale + params_.energySlack;
  if (excess > budget)
    return format("energy grew by %.3g J more than the work done on the system (budget %.3g J; "
                  "kinetic + elastic %.3g J at the frame's start, %.3g J after)",
                  excess, budget, startEnergy, endEnergy);
  frame_.excess = excess;
  frame_.work = std::abs(flows_.work);
  frame_.bodyChange = std::abs(end_.body - b0.body);
  frame_.startEnergy = startEnergy;
  frame_.kick = loadRate_ * lastStep * lastStep;
  // A frame that adds nothing passes: no halving of it can undo what the frames before did.
  if (carried_.excess <= 0.0 || excess <= 0.0) return {};
  const double carried = kCarriedKeeps * carried_.excess + excess;
  const double carriedScale = std::max({carried_.startEnergy,
                                        kCarriedKeeps * carried_.work + frame_.work,
                                        kCarriedKeeps * carried_.bodyChange + frame_.bodyChange,
                                        std::max(carried_.kick, frame_.kick)});
  const double carriedBudget = (params_.energyGrowth - 1.0) * carriedScale + params_.energySlack;
  if (carried <= carriedBudget) return {};
  return format("energy grew by %.3g J more than the work done on the system over the last %.0f "
                "frames (budget %.3g J; kinetic + elastic %.3g J when the growth began, %.3g J now)",
                carried, carried_.frames + 1.0, carriedBudget, carried_.startEnergy, endEnergy);
}

void StabilityGuard::carryExcess() {
  if (carried_.excess <= 0.0) carried_ = {0.0, 0.0, 0.0, frame_.startEnergy, 0.0, 0};
  forgetCarried();
  carried_.excess += frame_.excess;
  carried_.work += frame_.work;
  carried_.bodyChange += frame_.bodyChange;
  carried_.kick = std::max(carried_.kick, frame_.kick);
  ++carried_.frames;
  if (carried_.excess <= 0.0) carried_ = {};
}

void StabilityGuard::forgetCarried() {
  carried_.excess *= kCarriedKeeps;
  carried_.work *= kCarriedKeeps;
  carried_.bodyChange *= kCarriedKeeps;
}

void StabilityGuard::measure(const System& system, Balance& b) {
  measureLoads(system, b);
  measureEnergies(system, b);
}

void StabilityGuard::measureLoads(const System& system, Balance& b) const {
  const State& s = system.state;
  b.loadForce = system.externalForce;
  for (const auto& model : system.models)
    if (!model->hasEnergy()) model->addForce(s.x, s.v, b.loadForce);
}

void StabilityGuard::measureEnergies(const System& system, Balance& b) {
  const State& s = system.state;
  b.kinetic = b.dampingPower = 0.0;
  for (Eigen::Index dof = 0; dof < s.v.size(); ++dof) {
    if (system.isConstrained[dof]) continue;
    b.kinetic += 0.5 * system.mass[dof] * s.v[dof] * s.v[dof];
    b.dampingPower += system.damping[dof] * s.v[dof] * s.v[dof];
  }
  b.elastic = b.body = 0.0;
  // The controlled DOFs' work needs the models' forces there; without them the energy is enough.
  const bool controlled = !system.controlled.empty();
  if (controlled) modelForce_.setZero(s.x.size());
  for (const auto& model : system.models) {
    if (!model->hasEnergy()) continue;
    const double e = controlled ? model->addForce(s.x, s.v, modelForce_) : model->energy(s.x);
    (model->isBodyLoad() ? b.body : b.elastic) += e;
  }
  if (!controlled) return;
  b.constrainedForce.resize(static_cast<Eigen::Index>(system.constrainedDofs.size()));
  for (size_t k = 0; k < system.constrainedDofs.size(); ++k)
    b.constrainedForce[k] = modelForce_[system.constrainedDofs[k]];
}

Integrator& unguarded(Integrator& integrator) {
  auto* guard = dynamic_cast<StabilityGuard*>(&integrator);
  return guard ? guard->inner() : integrator;
}

const StabilityGuard* guardOf(const Integrator& integrator) {
  return dynamic_cast<const StabilityGuard*>(&integrator);
}

}  // namespace tt
