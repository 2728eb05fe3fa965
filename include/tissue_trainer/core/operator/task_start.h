#pragma once
// When the scripted operator's task clock starts. The operator holds the first keyframe
// until the simulation has published its first status (its scene is loaded and it steps), so
// that a slow start-up (a large mesh takes seconds to load and factor) never finds the tool
// already deep in the tissue; after waitTimeout without a status it starts anyway. Then it
// holds for startDelay more, and the task time runs from 0.
namespace tt {

class TaskStart {
 public:
  enum class Wait {
    kWaiting,     // no status yet, the timeout not reached
    kSimulation,  // the first status came
    kTimedOut,    // no status within waitTimeout: started without it
    kNoWait,      // waitTimeout 0: the task clock starts at once
  };

  // Throws std::invalid_argument unless both are finite and >= 0 (s).
  TaskStart(double waitTimeout, double startDelay);

  // Every tick, with the time since the operator started (s, non-decreasing) and whether the
  // simulation's status has arrived: the task time (s; < 0 while waiting or holding).
  double taskTime(double elapsed, bool simulationSeen);

  Wait wait() const { return wait_; }
  // The time (since the operator started) the wait ended; meaningful once wait() is not
  // kWaiting.
  double waitEnded() const { return waitEnded_; }
  double waitTimeout() const { return waitTimeout_; }

 private:
  double waitTimeout_, startDelay_;
  Wait wait_;
  double waitEnded_ = 0.0;
};

}  // namespace tt
