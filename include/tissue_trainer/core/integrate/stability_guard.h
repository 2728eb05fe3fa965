#pragma once
// A runtime stability guard around any integrator. It is an Integrator itself (a decorator),
// so scenes and nodes use it in place of the one it wraps. Each frame it keeps the state,
// lets the wrapped integrator advance and checks the result:
//   finite  every position and velocity is a finite number;
//   volume  no element is corrupt (CorruptElementCheck in mesh/corrupt_elements.h): no tet's signed
//           volume fell to minVolumeRatio of its rest volume or below (inverted or flat), no
//           hex stopped being a simple polyhedron (a tet of its six- or five-tet split
//           inverted or flat); only when a model of the system does not tolerate inversion
//           (ForceModel::toleratesInversion);
//   energy  the energy balance below stays within its budget.
// A frame that fails a check (or that the wrapped integrator reports failed) is rolled back
// and done again in 2 equal pieces, then in 4, ..., down to 2^maxHalvings pieces, until an
// attempt passes; integrators with a set step length shorten it by the same factor
// (Integrator::setStepDivisor: the explicit schemes and fixed-step Radau IIA), so every halving
// halves the step. The checks run after every piece and an attempt passes only as a whole: an
// unstable first step can look harmless and only shows in the steps after it. The following
// frames start with the step that passed (an instability near equilibrium grows from a tiny
// seed and would show only frames later); after relaxAfter frames that pass at once the guard
// tries a step twice as long again. When the last attempt fails too, or the external force is
// not finite, the frame's initial state is restored and the report says ok = false, which
// check failed, on which element or DOF and in which time interval.
//
// Energy balance from the frame's start t0 to the end t1 of each piece: E = kinetic energy of
// the free DOFs + the energy of the models that have one (elastic, gravity). W = work done by
// what has no energy: the external force and the models without energy (contact) on the free
// DOFs, and the controlled DOFs moving against the other models' forces, each by the
// trapezoidal rule 1/2 (f(a) + f(b)) . (x(b) - x(a)) over every piece [a, b]. D = work of the
// damping, -1/2 (P(a) + P(b)) (b - a) with P = sum c v^2. An exact step has E1 - E0 = W + D.
// The check fails when
//   E1 - E0 - W - D > (energyGrowth - 1) * max(S0, |W|, |dB|, L h^2) + energySlack
// with S0 the kinetic + elastic energy at t0, dB the change of the body loads' energy, h the
// wrapped integrator's last internal step and L = 1/2 sum f^2 / m over the free DOFs of the body
// loads and the external force (L h^2 is the kinetic energy they give in one step from rest:
// forward Euler's first step gains it before anything moves). Beyond the work put in, the
// energy may grow by (energyGrowth - 1) times the energy in play in the frame. An unstable step
// multiplies the energy by orders of magnitude in a frame. A slower growth (a step just above
// the stable limit, or one step per frame) is caught by the excess carried over frames: each
// frame that passes adds its excess E1 - E0 - W - D to a sum that keeps 99 % of itself from
// frame to frame (it forgets in about 100 frames, so that the energy swing of a stable step
// does not add up over a session) and restarts at zero when it falls to zero or below
// (numerical dissipation earns no credit). A frame whose own excess is positive fails when the
// sum with it exceeds (energyGrowth - 1) * max(S, sum |W|, sum |dB|, max L h^2) + energySlack,
// with S the kinetic + elastic energy where the sum last started and the sums kept the same
// way (a frame that adds nothing passes: halving it cannot undo what the frames before did). A
// growth of r per frame is caught once the energy is about (energyGrowth - 1) (0.01 + r) / r
// times S: 10x at r = 0.1, 18x at 0.01. A frame that fails restores the state and keeps the
// sum, which still forgets a little; a state changed from outside between frames restarts it.
//
// Real time: with a wall-clock budget per frame (wallBudget > 0; the simulation node gives it a
// few frame periods, or as many typical steps where one step takes longer) the guard starts no further attempt, and stops an attempt other than the
// frame's first between its pieces, once the frame has used the budget: the frame then fails
// as above (state restored),
// so that a frame it cannot make stable costs the node a few periods, not seconds, and the
// next frame starts with one halving more than the last attempt (a frame too slow to be
// retried within the budget then still gets its shorter steps, one frame later). The frame's
// first attempt, when it runs out of budget between its pieces, keeps the pieces it made (each
// checked) and ends the frame there, before its end time (GuardFrame::cutShort): a frame that
// starts deep costs the budget and one piece, and the simulation falls behind the wall clock
// instead of stalling, until the frames that pass at once have relaxed the step again.
//
// When every check passes at once the wrapped integrator has advanced the frame exactly as it
// would alone (bit-identical state); the guard only adds its measurements. After a rollback,
// integrators with history between frames (newtonian) restart from the restored state.
#include <Eigen/Core>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "tissue_trainer/core/integrate/integrator.h"
#include "tissue_trainer/core/mesh/corrupt_elements.h"

namespace tt {

struct StabilityGuardParams {
  int maxHalvings = 6;           // the last attempt takes 2^maxHalvings pieces
  double energyGrowth = 10.0;    // > 1, see the energy balance above
  double energySlack = 1e-9;     // J
  double minVolumeRatio = 0.01;  // a tet at or below this fraction of its rest volume fails
  int relaxAfter = 25;           // frames passed at once before the step is doubled again
  double wallBudget = 0.0;       // s of wall-clock time per frame for the retries; 0: none
  // With a budget, it is at least this many times the wall time one piece (one inner step)
  // typically takes (a running mean over the pieces made), so that where one step costs more
  // than wallBudget a frame that fails can still be halved once instead of failing at once.
  double wallBudgetSteps = 0.0;
  // Seconds on a monotonic clock; empty: std::chrono::steady_clock. Tests give a simulated
  // clock, so that what the budget does does not depend on how busy the machine is.
  std::function<double()> wallClock;
};

// What the guard did in the frame it advanced last (StabilityGuard::lastFrame).
struct GuardFrame {
  bool ok = true;          // the frame passed, at once or after halvings
  int halvings = 0;        // times the guard rolled the frame back and halved the step
  std::string reason;      // the last problem found in the frame (recovered or not)
  bool cutShort = false;   // the frame ended early for the wall-time budget
};

// What a guard did, summed over frames (StabilityGuard::stats, or add() over the frames).
struct GuardStats {
  long frames = 0;         // frames checked
  long recoveries = 0;     // frames that passed only after rolling back and halving
  long halvings = 0;       // rollbacks followed by a halving, all frames
  long failures = 0;       // frames that failed every attempt
  long cutShort = 0;       // frames ended early for the wall-time budget
  std::string lastReason;  // the last problem found (recovered or not)

  void add(const GuardFrame& frame);
};

class StabilityGuard : public Integrator {
 public:
  explicit StabilityGuard(std::unique_ptr<Integrator> inner, StabilityGuardParams params = {});

  const char* name() const override { return inner_->name(); }
  bool needsStiffness() const override { return inner_->needsStiffness(); }
  StepReport advance(System& system, double frameTime) override;

  Integrator& inner() { return *inner_; }
  const StabilityGuardParams& params() const { return params_; }
  void setWallBudget(double seconds, double steps = 0.0) {
    params_.wallBudget = seconds;
    params_.wallBudgetSteps = steps;
  }
  // The frame's budget now: max(wallBudget, wallBudgetSteps x the typical piece); 0: none.
  double wallBudget() const;
  const GuardStats& stats() const { return stats_; }
  const GuardFrame& lastFrame() const { return lastFrame_; }

 private:
  // What the energy check needs from one instant.
  struct Balance {
    double kinetic = 0.0, elastic = 0.0, body = 0.0;  // J
    double dampingPower = 0.0;          // sum of c v^2 over the free DOFs (W)
    Eigen::VectorXd loadForce;          // external + models without energy (N, all DOFs)
    Eigen::VectorXd constrainedForce;   // models with energy, at system.constrainedDofs
  };
  // Energy flows since the frame's start (J).
  struct Flows {
    double work = 0.0;     // by loads, contact and controlled DOFs
    double damping = 0.0;  // by the damping (<= 0)
  };
  // The energy excess carried over the frames since it was last zero (J).
  struct Carried {
    double excess = 0.0;      // sum of E1 - E0 - W - D, > 0 while carried
    double work = 0.0;        // sum of |W|
    double bodyChange = 0.0;  // sum of |dB|
    double startEnergy = 0.0; // kinetic + elastic where the sum started
    double kick = 0.0;        // the largest L h^2 of the frames summed
    int frames = 0;
  };

  void prepare(const System& system);
  // Where the next frame starts, after this one passed at `depth`.
  void keepDepth(int depth, bool rolledBack);
  void startFrame(const System& system);
  // Advances the frame in 2^depth pieces; empty when every piece passed, else what was found.
  std::string attempt(System& system, double frameTime, int depth, StepReport& work);
  // The budget's verdict: empty while wall time is left (or there is no budget).
  std::string budgetSpent() const;
  void notePieceTime(double seconds);
  std::string check(const System& system, double lastStep);
  std::string checkFinite(const System& system) const;
  std::string checkVolumes(const System& system) const;
  std::string checkEnergy(const System& system, double lastStep);
  // Adds the frame that passed (its last energy check) to the carried excess.
  void carryExcess();
  // Keeps 99 % of the carried sums (each frame, passed or failed).
  void forgetCarried();
  // Adds the flows from the piece's start (pieceT_, pieceX_, pieceStart_) to now (end_).
  void addFlows(const System& system);
  void measure(const System& system, Balance& b);
  void measureLoads(const System& system, Balance& b) const;
  void measureEnergies(const System& system, Balance& b);

  std::unique_ptr<Integrator> inner_;
  StabilityGuardParams params_;
  GuardStats stats_;
  GuardFrame lastFrame_;
  const System* prepared_ = nullptr;
  CorruptElementCheck corruptCheck_;  // the mesh's tets, and each hex through its splits
  std::size_t preparedElements_ = 0;  // tets + hexes when corruptCheck_ was built
  bool checkVolumes_ = false;
  int startDepth_ = 0;  // the next frame's first attempt takes 2^startDepth_ pieces
  int calmFrames_ = 0;  // frames passed at once since startDepth_ last changed
  State frameStart_;
  State measured_;  // the state end_ belongs to after a frame that passed
  Balance frameBalance_, pieceStart_, end_;
  Eigen::VectorXd pieceX_, modelForce_, loadForce_;
  double pieceT_ = 0.0;
  Flows flows_;
  Carried carried_, frame_;  // frame_: the current frame so far, as carried_ would add it
  double loadRate_ = 0.0;  // L = 1/2 sum f^2 / m of the body loads and external force (J/s^2)
  double now() const;
  double frameClock_ = 0.0;  // when this frame began (s, wallClock)
  double typicalPiece_ = 0.0;  // running mean of one piece's wall time (s)
  bool stoppedForBudget_ = false;  // the last attempt stopped between pieces for the budget
  double cutShortAt_ = 0.0;  // NaN, or where the last attempt ended its frame early (s)
};

// The integrator a guard wraps, or `integrator` itself when it is not a guard.
Integrator& unguarded(Integrator& integrator);
// The guard `integrator` is, or nullptr when it runs unguarded.
const StabilityGuard* guardOf(const Integrator& integrator);

}  // namespace tt
