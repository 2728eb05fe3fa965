#pragma once
// Force between two contact models, for a haptic loop (1 kHz) fed by a slower simulation
// (50-100 Hz): F(x, t) = f0 - K (x - x0) of the latest model, and when a new model arrives
// the output is blended from what was felt to the new model over blendTime, so that no step
// reaches the hand. Time is an explicit input (the bridge's clock, s); nothing here reads a
// clock.
#include <cstdint>
#include <limits>

#include <Eigen/Core>

#include "tissue_trainer/core/haptics/contact_model.h"

namespace tt {

enum class ExtrapolationMode {
  kLinear,         // f0 - K (x - x0)
  kZeroOrderHold,  // f0: the device feels the force of the position the model was taken at
};

enum class BlendShape {
  kLinear,      // w = s
  kSmoothstep,  // w = 3 s^2 - 2 s^3: also continuous in force rate at both ends
};

// What is blended when a model arrives at device position xs, with weight w going 0 -> 1.
enum class BlendMethod {
  // (1 - w) F_old(x) + w F_new(x): the old field keeps being extrapolated during the blend,
  // so its error grows as the device moves away from where it was taken.
  kFields,
  // F_new(x) + (1 - w) (F_old(xs) - F_new(xs)): the new field at once, plus the jump it
  // would have made, frozen at xs and faded out. Same continuity, less lag error
  // (bench_haptics compares them).
  kOffset,
};

struct ExtrapolatorOptions {
  ExtrapolationMode mode = ExtrapolationMode::kLinear;
  double blendTime = 0.015;  // s; 0 switches to a new model at once
  BlendShape blendShape = BlendShape::kSmoothstep;
  BlendMethod blendMethod = BlendMethod::kOffset;
  // Models whose stiffness has a larger Frobenius norm (N/m) are rejected as malformed.
  double maxStiffness = std::numeric_limits<double>::infinity();
  // This many stale sequences in a row mean the simulation restarted (its sequence began
  // again): the extrapolator resets and takes the last of them. 0: never.
  int restartAfterStale = 5;
};

struct ExtrapolatorCounters {
  std::uint64_t accepted = 0;
  std::uint64_t malformed = 0;       // non-finite numbers or stiffness above maxStiffness
  std::uint64_t staleSequence = 0;   // sequence not above the last accepted one
  std::uint64_t restarts = 0;        // resets after restartAfterStale stale models in a row
};

enum class ModelVerdict { kAccepted, kMalformed, kStaleSequence };

class ForceExtrapolator {
 public:
  // Throws std::invalid_argument for a negative or non-finite blend time, or a
  // non-positive maxStiffness or a negative restartAfterStale.
  explicit ForceExtrapolator(const ExtrapolatorOptions& options = {});

  // Offers a model taken in at tReceive (bridge clock), when the device was at xDevice (the
  // blend starts from the force felt there; kFields does not need it, and a non-finite
  // xDevice is replaced by the model's x0). A malformed model or
  // one whose sequence is not above the last accepted one is dropped and counted; the
  // previous model stays in force (until restartAfterStale of them in a row restart it).
  ModelVerdict submit(const ContactModel& model, double tReceive, const Eigen::Vector3d& xDevice);

  // The force on the tool (N) at device position x and time tNow; zero before any model.
  Eigen::Vector3d force(const Eigen::Vector3d& x, double tNow) const;

  // The field force() evaluates at tNow (blend included).
  LinearForceField field(double tNow) const;

  // Seconds since the last accepted model arrived; +inf before the first one. The stamp is
  // not used: it may come from another machine's clock.
  double modelAge(double tNow) const;

  bool hasModel() const { return hasModel_; }
  const ExtrapolatorCounters& counters() const { return counters_; }
  const ExtrapolatorOptions& options() const { return options_; }

  // Forgets every model and sequence number (for a restarted simulation).
  void reset();

 private:
  double blendWeight(double tNow) const;
  LinearForceField fieldOf(const ContactModel& model) const;

  ExtrapolatorOptions options_;
  LinearForceField from_;   // kFields: the field the output is blending away from
  LinearForceField to_;     // the latest model's field
  Eigen::Vector3d offset_ = Eigen::Vector3d::Zero();  // kOffset: the jump being faded out
  double blendStart_ = 0.0;
  double lastReceive_ = 0.0;
  std::uint64_t lastSequence_ = 0;
  int consecutiveStale_ = 0;
  bool hasModel_ = false;
  ExtrapolatorCounters counters_;
};

}  // namespace tt
