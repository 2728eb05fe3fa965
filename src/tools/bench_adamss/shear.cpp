#include <cstdio>

#include "experiments.h"

namespace tt {
namespace bench_adamss {

int runShear(const Args&) {
  std::fprintf(stderr, "bench_adamss: shear is not built yet\n");
  return 2;
}

}  // namespace bench_adamss
}  // namespace tt
