#include <cstdio>

#include "experiments.h"

namespace tt {
namespace bench_adamss {

int runSpringFit(const Args&) {
  std::fprintf(stderr, "bench_adamss: spring_fit is not built yet\n");
  return 2;
}

}  // namespace bench_adamss
}  // namespace tt
