// bench_adamss: the verification experiments of "Adamss: Advanced Anisotropic Mass-Spring
// System" (Sec. 2.8), its mesh-independence claim (Sec. 2.1.2) and the statements of its
// discussion (Sec. 2.9).
//   bench_adamss EXPERIMENT [--quick] [--out DIR] [--no-plot] [options]
// (bench_adamss --help lists the experiments; bench_adamss EXPERIMENT --help, its options)
#include <cstdio>
#include <cstring>
#include <string>

#include "experiments.h"

namespace {

struct Experiment {
  const char* name;
  int (*run)(const tt::bench_adamss::Args&);
  const char* what;
};

const Experiment kExperiments[] = {
    {"stretch", tt::bench_adamss::runStretch, "uniaxial stretch against the Hunter law (Sec. 2.8.1)"},
    {"spring_fit", tt::bench_adamss::runSpringFit,
     "cubic springs: Table 2.2 and a least-squares fit (Sec. 2.8.1)"},
    {"shear", tt::bench_adamss::runShear, "simple shear: work against energy (Sec. 2.8.1)"},
    {"volume", tt::bench_adamss::runVolume, "volume preservation under gravity (Sec. 2.8.2)"},
    {"scaling", tt::bench_adamss::runScaling, "1000 implicit steps against size (Sec. 2.8.3)"},
    {"mesh_independence", tt::bench_adamss::runMeshIndependence,
     "one stretch on hex and tet meshes (Sec. 2.1.2)"},
    {"oscillation", tt::bench_adamss::runOscillation,
     "volume oscillation: explicit, ABM3 and backward Euler (Sec. 2.9.3)"},
    {"locking", tt::bench_adamss::runLocking, "tet locking against the volume term's p (Sec. 2.9.1)"},
    {"resolution", tt::bench_adamss::runResolution,
     "a spring cantilever at three resolutions (Sec. 2.1.4)"},
};

void printUsage() {
  std::printf("usage: bench_adamss EXPERIMENT [--quick] [--out DIR] [--no-plot] [options]\n"
              "experiments (bench_adamss EXPERIMENT --help: its options):\n");
  for (const Experiment& e : kExperiments) std::printf("  %-18s %s\n", e.name, e.what);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc >= 2 && (std::strcmp(argv[1], "--help") == 0 || std::strcmp(argv[1], "-h") == 0)) {
    printUsage();
    return 0;
  }
  for (const Experiment& e : kExperiments)
    if (argc >= 2 && argv[1] == std::string(e.name))
      return e.run(tt::bench_adamss::Args(argv + 2, argv + argc));
  std::string names;
  for (const Experiment& e : kExperiments) names += std::string(names.empty() ? "" : ", ") + e.name;
  std::fprintf(stderr, "bench_adamss: %s, expected an experiment: one of %s (bench_adamss --help)\n",
               argc < 2 ? "no experiment" : ("unknown experiment '" + std::string(argv[1]) + "'").c_str(),
               names.c_str());
  return 2;
}
