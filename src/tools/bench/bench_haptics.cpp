// Haptic force extrapolation on the nonlinear wall probe (f = k d + k3 d^3 along a tilted
// normal, k = 200 N/m, k3 = 1e6 N/m^3, device 2 to 11 mm deep on an elliptic path): RMS and
// maximum force error against the exact wall force at 1 kHz for zero-order hold and linear
// extrapolation (no blend; 15 ms smoothstep blend of the offset or of the fields; 5 ms blend
// of the offset), at 50 and 100 Hz simulation rate, several device speeds and two model
// latencies (0 and half a simulation period); then nanoseconds per tick of the
// full pipeline (extrapolator + safety filter + loop statistics), median of repeats.
// The error columns are of the extrapolator output (before the safety filter).
//   bench_haptics [--quick] [--repeats N=9]   (--quick: one repeat)
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "common/command_line.h"
#include "tissue_trainer/core/haptics/haptic_pipeline.h"
#include "tissue_trainer/core/haptics/wall_probe.h"

namespace {

using namespace tt;
using Clock = std::chrono::steady_clock;

WallProbe baseProbe() {
  WallProbe p;
  p.wall.normal = Eigen::Vector3d(0.2, -0.1, 1.0).normalized();
  p.center = Eigen::Vector3d(0.0, 0.0, -0.007);
  p.a = Eigen::Vector3d(0.0, 0.0, 0.004);
  p.b = Eigen::Vector3d(0.003, 0.002, 0.0);
  p.duration = 5.0;
  return p;
}

void errorTable() {
  ExtrapolatorOptions hold, linear, offset15, fields15, offset5;
  hold.mode = ExtrapolationMode::kZeroOrderHold;
  hold.blendTime = 0.0;
  linear.blendTime = 0.0;
  offset15.blendTime = fields15.blendTime = 0.015;
  offset15.blendMethod = offset5.blendMethod = BlendMethod::kOffset;
  fields15.blendMethod = BlendMethod::kFields;
  offset5.blendTime = 0.005;
  std::printf("force error vs exact wall force, 1 kHz haptic loop, %.0f s per row (N)\n",
              baseProbe().duration);
  std::printf("%5s %6s %6s %5s | %13s | %20s | %20s | %20s | %20s | %5s\n", "simHz", "lat_ms",
              "v_cm/s", "f_rms", "hold rms/max", "linear rms/max/step", "offset15", "fields15",
              "offset5", "ratio");
  for (double simHz : {50.0, 100.0}) {
    for (double latencyPeriods : {0.0, 0.5}) {
      for (double frequency : {0.25, 1.0, 4.0, 8.0}) {
        WallProbe p = baseProbe();
        p.simPeriod = 1.0 / simHz;
        p.latency = latencyPeriods * p.simPeriod;
        p.frequency = frequency;
        const ForceErrorStats h = measureExtrapolationError(p, hold);
        std::printf("%5.0f %6.1f %6.1f %5.2f | %6.4f %6.4f", simHz, 1e3 * p.latency,
                    100.0 * p.peakSpeed(), h.rmsForce, h.rms, h.max);
        double offsetRms = 0.0;
        for (const ExtrapolatorOptions* o : {&linear, &offset15, &fields15, &offset5}) {
          const ForceErrorStats e = measureExtrapolationError(p, *o);
          std::printf(" | %6.4f %6.4f %6.4f", e.rms, e.max, e.maxStep);
          if (o == &offset15) offsetRms = e.rms;
        }
        std::printf(" | %5.3f\n", offsetRms / h.rms);
      }
    }
  }
  std::printf("rms and max error (N); step: largest output change between two 1 ms ticks (N);\n"
              "linear: no blend; offsetT / fieldsT: T ms smoothstep blend of the offset / of the\n"
              "fields; ratio: offset15 rms / hold rms\n");
}

// Nanoseconds per tick of f(), median over repeats of `ticks` ticks.
template <class Tick>
double medianNsPerTick(Tick&& f, int ticks, int repeats) {
  std::vector<double> ns;
  for (int r = 0; r < repeats; ++r) {
    const auto t0 = Clock::now();
    for (int i = 0; i < ticks; ++i) f(i);
    ns.push_back(std::chrono::duration<double, std::nano>(Clock::now() - t0).count() / ticks);
  }
  std::nth_element(ns.begin(), ns.begin() + repeats / 2, ns.end());
  return ns[repeats / 2];
}

void timing(int repeats) {
  const WallProbe p = baseProbe();
  const int period = 1000, ticks = 200000, modelEvery = 20;
  std::vector<Eigen::Vector3d> positions(period);
  std::vector<ContactModel> models(period / modelEvery);
  for (int i = 0; i < period; ++i) positions[i] = p.device(1e-3 * i);
  for (int k = 0; k < period / modelEvery; ++k)
    models[k] = p.wall.model(positions[k * modelEvery], 0, 1e-3 * k * modelEvery);

  HapticPipeline pipeline;
  std::uint64_t sequence = 0;
  long tick = 0;
  Eigen::Vector3d sink = Eigen::Vector3d::Zero();
  const double full = medianNsPerTick(
      [&](int i) {
        const double t = 1e-3 * static_cast<double>(tick++);
        if (i % modelEvery == 0) {
          ContactModel m = models[(i % period) / modelEvery];
          m.sequence = ++sequence;
          pipeline.submit(m, t, positions[i % period]);
        }
        sink += pipeline.tick(positions[i % period], t, true);
      },
      ticks, repeats);

  ForceExtrapolator extrapolator;
  extrapolator.submit(models[0], 0.0, positions[0]);
  const double extrapolate = medianNsPerTick(
      [&](int i) { sink += extrapolator.force(positions[i % period], 1e-3 * (i % 10)); }, ticks, repeats);

  SafetyFilter safety;
  long safetyTick = 0;
  const double filter = medianNsPerTick(
      [&](int i) {
        sink += safety.step(Eigen::Vector3d(0.0, 0.0, 1.0 + 0.5 * (i % 7)), 1e-3 * static_cast<double>(safetyTick++),
                            0.0, true);
      },
      ticks, repeats);

  std::printf("\nns per tick, median of %d repeats of %d ticks (model every %d ticks):\n", repeats,
              ticks, modelEvery);
  std::printf("  full pipeline (submit + extrapolate + safety + loop stats): %.1f\n", full);
  std::printf("  extrapolator force() alone: %.1f\n", extrapolate);
  std::printf("  safety filter step() alone: %.1f\n", filter);
  std::printf("  (checksum %.3g; requested-to-sent safety counters: rate-limited %llu, clamped %llu)\n",
              sink.sum(), static_cast<unsigned long long>(pipeline.safety().counters().rateLimited),
              static_cast<unsigned long long>(pipeline.safety().counters().forceClamped));
}

}  // namespace

int main(int argc, char** argv) {
  tt::tools::CommandLine options(argc, argv, "bench_haptics [--quick] [--repeats N]");
  const bool quick = options.flag("--quick");
  const int repeats = options.positiveInteger("--repeats", quick ? 1 : 9);
  options.finish();
  errorTable();
  timing(repeats);
  return 0;
}
