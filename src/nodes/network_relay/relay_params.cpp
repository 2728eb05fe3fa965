#include "relay_params.h"

#include <cmath>
#include <cstdio>
#include <functional>

#include "../common/param_reader.h"

namespace tt_nodes {

namespace {

constexpr double kMaxMs = 60000.0;  // one minute: anything longer is a typo, not a network

// Runs one read; a ParamError becomes one line in `problems` (the other reads still run).
void collect(std::vector<std::string>& problems, const std::function<void()>& read) {
  try {
    read();
  } catch (const ParamError& e) {
    problems.push_back(e.what());
  }
}

}  // namespace

std::vector<std::string> readRelayParams(const ros::NodeHandle& privateNh, RelayParams& params) {
  const ParamReader p(privateNh);
  tt::NetworkProfile& n = params.profile;
  std::vector<std::string> problems;
  double burstMinMs = 0.0, burstMaxMs = 0.0;
  collect(problems, [&] { n.delay = 1e-3 * p.number("delay_ms", 0.0, 0.0, kMaxMs); });
  collect(problems, [&] { n.jitter = 1e-3 * p.number("jitter_ms", 0.0, 0.0, kMaxMs); });
  collect(problems, [&] { n.loss = p.number("loss", 0.0, 0.0, 1.0); });
  collect(problems, [&] { n.reorder = p.number("reorder", 0.0, 0.0, 1.0); });
  collect(problems, [&] { n.reorderDelay = 1e-3 * p.number("reorder_delay_ms", 0.0, 0.0, kMaxMs); });
  collect(problems, [&] { n.burstProbability = p.number("burst_probability", 0.0, 0.0, 1.0); });
  collect(problems, [&] { burstMinMs = p.number("burst_min_ms", 0.0, 0.0, kMaxMs); });
  collect(problems, [&] { burstMaxMs = p.number("burst_max_ms", 0.0, 0.0, kMaxMs); });
  collect(problems, [&] {
    n.burstMode = p.choice("burst_mode", {"drop", "hold"}, 0) == 0 ? tt::BurstMode::kDrop
                                                                    : tt::BurstMode::kHold;
  });
  collect(problems, [&] {
    const double seed = p.number("seed", 1.0, 0.0, 9007199254740992.0);  // exact in a double
    if (seed != std::floor(seed))
      throw ParamError(p.qualified("seed") + ": expected a whole number >= 0, got " +
                       std::to_string(seed));
    n.seed = static_cast<std::uint64_t>(seed);
  });
  collect(problems, [&] {
    const double queue = p.number("queue", 4096.0, 1.0, 1e6);
    if (queue != std::floor(queue))
      throw ParamError(p.qualified("queue") + ": expected a whole number in [1, 1e+06], got " +
                       std::to_string(queue));
    params.queue = static_cast<std::size_t>(queue);
  });
  if (burstMinMs > burstMaxMs)
    problems.push_back(p.qualified("burst_max_ms") + ": expected at least ~burst_min_ms (" +
                       std::to_string(burstMinMs) + "), got " + std::to_string(burstMaxMs));
  n.burstMin = 1e-3 * burstMinMs;
  n.burstMax = 1e-3 * std::max(burstMinMs, burstMaxMs);
  return problems;
}

std::string describe(const tt::NetworkProfile& p) {
  char line[400];
  std::snprintf(line, sizeof line,
                "delay %.1f ms, jitter %.1f ms, loss %.0f %%, reorder %.0f %% (+%.1f ms), "
                "outages %.1f %% per message of %.0f-%.0f ms (%s), seed %llu",
                1e3 * p.delay, 1e3 * p.jitter, 100.0 * p.loss, 100.0 * p.reorder,
                1e3 * p.reorderDelay, 100.0 * p.burstProbability, 1e3 * p.burstMin,
                1e3 * p.burstMax, p.burstMode == tt::BurstMode::kDrop ? "drop" : "hold",
                static_cast<unsigned long long>(p.seed));
  return line;
}

}  // namespace tt_nodes
