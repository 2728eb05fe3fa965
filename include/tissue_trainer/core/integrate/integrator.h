#pragma once
// The interface of the time integrators. advance() moves the system's state forward by one
// frame time (possibly in several substeps) and reports what it did.
#include <limits>
#include <string>

#include "tissue_trainer/core/system.h"

namespace tt {

struct StepReport {
  int substeps = 0;          // accepted internal steps
  int rejected = 0;          // rejected internal steps (adaptive methods)
  int newtonIterations = 0;
  int linearIterations = 0;  // CG/GMRES iterations, or LU solves
  int jacobians = 0;         // stiffness assemblies or finite-difference Jacobians
  double errorEstimate = std::numeric_limits<double>::quiet_NaN();  // local error, if known
  double lastStep = 0.0;     // last internal step size (s)
  double wallSeconds = 0.0;
  bool ok = true;            // false: the step failed (non-finite state, no convergence)
  std::string failure;       // why, when !ok
};

class Integrator {
 public:
  virtual ~Integrator() = default;
  virtual const char* name() const = 0;
  // Implicit methods need every model's analytic stiffness.
  virtual bool needsStiffness() const { return false; }
  virtual StepReport advance(System& system, double frameTime) = 0;
  // For the stability guard's retries: integrators that cut a frame into steps of a set
  // length make those steps `divisor` times shorter (1 restores the set length). The others
  // take their steps from the frame time, which the guard already cuts.
  void setStepDivisor(int divisor) { stepDivisor_ = divisor; }

 protected:
  int stepDivisor() const { return stepDivisor_; }

 private:
  int stepDivisor_ = 1;
};

}  // namespace tt
