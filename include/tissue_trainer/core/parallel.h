#pragma once
// Threads for the core's per-element loops (force, energy and stiffness of the tet models).
//
// The thread count is one process-wide setting, 1 by default (tests and single-threaded
// callers see the plain sequential loops). With n > 1 threads the results are bitwise
// reproducible for that n: work is split into n fixed contiguous ranges whatever the runtime
// does, and partial results are combined in a fixed order. Different n agree to round-off.
// Without OpenMP in the build, threadCount() stays 1.
#include <algorithm>
#include <type_traits>
#include <utility>
#include <vector>

namespace tt {

constexpr int kMaxThreads = 64;

// Sets the number of threads of the per-element loops (clamped to [1, kMaxThreads]).
void setThreadCount(int threads);
int threadCount();
// The hardware threads of this machine (at least 1).
int hardwareThreads();

// A non-owning reference to a callable void(int part, int begin, int end): no allocation,
// one indirect call per range (never per element).
class RangeFunction {
 public:
  template <class F, class = std::enable_if_t<!std::is_same_v<std::decay_t<F>, RangeFunction>>>
  RangeFunction(F&& f)  // NOLINT: implicit by design, like std::function
      : object_(const_cast<void*>(static_cast<const void*>(&f))),
        call_([](void* o, int part, int begin, int end) {
          (*static_cast<std::remove_reference_t<F>*>(o))(part, begin, end);
        }) {}
  void operator()(int part, int begin, int end) const { call_(object_, part, begin, end); }

 private:
  void* object_;
  void (*call_)(void*, int, int, int);
};

// [count * part / parts, count * (part + 1) / parts): the part-th of `parts` contiguous ranges.
inline int rangeBegin(int count, int parts, int part) {
  return static_cast<int>(static_cast<long long>(count) * part / parts);
}

// Runs body(part, begin, end) for the `parts` contiguous ranges of [0, count), one range per
// thread when parts <= threads (empty ranges are still visited).
void parallelRanges(int parts, int count, RangeFunction body);

}  // namespace tt
