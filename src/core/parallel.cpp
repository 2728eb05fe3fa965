#include "tissue_trainer/core/parallel.h"

#include <Eigen/Core>
#include <atomic>
#include <thread>

#ifdef TT_HAVE_OPENMP
#include <omp.h>
#endif

namespace tt {
namespace {

std::atomic<int> configuredThreads{1};

// Eigen built with OpenMP splits large sparse matrix-vector products (the CG iterations of the
// implicit integrators) over Eigen::nbThreads() threads, all cores by default: tie it to the
// core's setting so that 1 means one thread everywhere. Row-wise products stay bitwise
// reproducible for any thread count.
const bool eigenThreadsSet = (Eigen::setNbThreads(1), true);

}  // namespace

void setThreadCount(int threads) {
#ifdef TT_HAVE_OPENMP
  configuredThreads = std::clamp(threads, 1, kMaxThreads);
  Eigen::setNbThreads(configuredThreads);
#else
  (void)threads;
  configuredThreads = 1;
#endif
}

int threadCount() { return configuredThreads; }

int hardwareThreads() { return std::max(1u, std::thread::hardware_concurrency()); }

void parallelRanges(int parts, int count, RangeFunction body) {
  parts = std::max(parts, 1);
  if (parts == 1) {
    body(0, 0, count);
    return;
  }
#ifdef TT_HAVE_OPENMP
#pragma omp parallel num_threads(parts)
  {
    // The ranges belong to the parts, not to the threads the runtime grants.
    for (int part = omp_get_thread_num(); part < parts; part += omp_get_num_threads())
      body(part, rangeBegin(count, parts, part), rangeBegin(count, parts, part + 1));
  }
#else
  for (int part = 0; part < parts; ++part)
    body(part, rangeBegin(count, parts, part), rangeBegin(count, parts, part + 1));
#endif
}

}  // namespace tt
