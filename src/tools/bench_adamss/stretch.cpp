#include <cstdio>

#include "experiments.h"

namespace tt {
namespace bench_adamss {

int runStretch(const Args&) {
  std::fprintf(stderr, "bench_adamss: stretch is not built yet\n");
  return 2;
}

}  // namespace bench_adamss
}  // namespace tt
