// guard_overhead SCENE.yaml [FRAMES]: what the stability guard costs on a scene that needs no
// help. Two copies of the scene advance frame by frame in turn, one through the guard and one
// through the integrator alone; prints the median and total step times of both, the overhead,
// and whether the two end in the same state. Exit 3 when the guard had to step in (the
// comparison is then not one of overhead), 2 on bad input.
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "tissue_trainer/core/error.h"
#include "tissue_trainer/core/integrate/stability_guard.h"
#include "tissue_trainer/core/scene/scene.h"

namespace {

double median(std::vector<double> v) {
  std::nth_element(v.begin(), v.begin() + v.size() / 2, v.end());
  return v[v.size() / 2];
}

double sum(const std::vector<double>& v) {
  double s = 0.0;
  for (double x : v) s += x;
  return s;
}

// Times one advance (s).
double timed(tt::Integrator& integrator, tt::Scene& scene, tt::StepReport& report) {
  const auto start = std::chrono::steady_clock::now();
  report = integrator.advance(scene.system, scene.frameTime);
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || argc > 3) {
    std::fprintf(stderr, "usage: guard_overhead SCENE.yaml [FRAMES]\n");
    return 2;
  }
  const int frames = argc == 3 ? std::atoi(argv[2]) : 500;
  if (frames < 1) {
    std::fprintf(stderr, "FRAMES expects a positive integer, got '%s'\n", argv[2]);
    return 2;
  }
  tt::Scene guarded, plain;
  try {
    guarded = tt::loadScene(argv[1]);
    plain = tt::loadScene(argv[1]);
  } catch (const tt::InputError& e) {
    std::fprintf(stderr, "%s\n", e.what());
    return 2;
  }
  if (!dynamic_cast<tt::StabilityGuard*>(guarded.integrator.get()))
    guarded.integrator = std::make_unique<tt::StabilityGuard>(std::move(guarded.integrator));
  tt::Integrator& alone = tt::unguarded(*plain.integrator);

  std::vector<double> withGuard, without;
  for (int f = 1; f <= frames; ++f) {
    tt::StepReport a, b;
    if (f % 2) {  // alternate which goes first
      withGuard.push_back(timed(*guarded.integrator, guarded, a));
      without.push_back(timed(alone, plain, b));
    } else {
      without.push_back(timed(alone, plain, b));
      withGuard.push_back(timed(*guarded.integrator, guarded, a));
    }
    if (!a.ok || !b.ok || a.halvings > 0) {
      std::printf("frame %d: the guard stepped in (%s); no overhead to measure\n", f,
                  a.ok ? a.guardReason.c_str() : a.failure.c_str());
      return 3;
    }
  }
  const bool same = guarded.system.state.x == plain.system.state.x &&
                    guarded.system.state.v == plain.system.state.v;
  const double a = median(withGuard), b = median(without);
  std::printf("guard_overhead %s: %d frames, step median %.3f ms guarded, %.3f ms alone: "
              "overhead %+.3f ms, %+.1f%% (medians), %+.1f%% (totals); identical states: %s\n",
              guarded.name.c_str(), frames, 1e3 * a, 1e3 * b, 1e3 * (a - b), 100.0 * (a / b - 1.0),
              100.0 * (sum(withGuard) / sum(without) - 1.0), same ? "yes" : "no");
  return 0;
}
