// The simulated network link of the relay node: delay, jitter, loss, outages (drop and hold),
// reordering, capacity, and the seeded draws.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <limits>
#include <map>
#include <stdexcept>
#include <vector>

#include "tissue_trainer/core/haptics/network_channel.h"

namespace tt {
namespace {

constexpr double kPeriod = 0.01;  // s: the simulation's contact models come at 100 Hz

struct Delivery {
  std::uint64_t id;
  double sent, due;
};

// Offers n messages (id i at i * period), polls every 0.1 ms, and returns what arrived (with
// its exact delivery time) in the order it arrived; `verdicts` gets the verdict of every offer.
std::vector<Delivery> run(NetworkChannel& channel, int n, std::vector<ChannelVerdict>* verdicts = nullptr,
                          double period = kPeriod) {
  std::vector<Delivery> out;
  std::map<std::uint64_t, double> sentAt;
  const double step = 1e-4;
  long next = 0;
  for (long k = 0; next < n || channel.inFlight() > 0; ++k) {
    const double t = k * step;
    while (next < n && next * period <= t + 1e-12) {
      const ChannelVerdict v = channel.offer(next, next * period);
      if (verdicts) verdicts->push_back(v);
      sentAt[next] = next * period;
      ++next;
    }
    std::uint64_t id;
    for (double due = channel.nextDue(); channel.popDue(t, id); due = channel.nextDue())
      out.push_back({id, sentAt[id], due});
  }
  return out;
}

bool inOrder(const std::vector<Delivery>& d) {
  for (std::size_t i = 1; i < d.size(); ++i)
    if (d[i].id < d[i - 1].id) return false;
  return true;
}

TEST(NetworkChannel, EmptyProfileDeliversEverythingAtOnceInOrder) {
  NetworkChannel channel(NetworkProfile{});
  const auto d = run(channel, 500);
  ASSERT_EQ(d.size(), 500u);
  EXPECT_TRUE(inOrder(d));
  for (const auto& x : d) EXPECT_EQ(x.due, x.sent);
  EXPECT_EQ(channel.counters().delivered, 500u);
}

TEST(NetworkChannel, ConstantDelayIsNeverShorterNorLonger) {
  NetworkProfile p;
  p.delay = 0.020;
  NetworkChannel channel(p);
  channel.offer(7, 1.0);
  std::uint64_t id = 0;
  EXPECT_FALSE(channel.popDue(1.0199, id));
  EXPECT_DOUBLE_EQ(channel.nextDue(), 1.020);
  EXPECT_TRUE(channel.popDue(1.020, id));
  EXPECT_EQ(id, 7u);
  EXPECT_FALSE(channel.popDue(5.0, id));
  EXPECT_TRUE(std::isinf(channel.nextDue()));
}

TEST(NetworkChannel, JitterStaysInItsBandAndKeepsTheStreamInOrder) {
  NetworkProfile p;
  p.delay = 0.020;
  p.jitter = 0.015;  // more than the message period: without the ordering, messages would cross
  NetworkChannel channel(p);
  const auto d = run(channel, 4000);
  ASSERT_EQ(d.size(), 4000u);
  EXPECT_TRUE(inOrder(d));
  double lo = 1e9, hi = -1e9;
  for (const auto& x : d) {
    const double latency = x.due - x.sent;
    lo = std::min(lo, latency);
    hi = std::max(hi, latency);
  }
  // The ordering only ever raises a delivery time, up to the previous one's (at most
  // delay + jitter after its own send).
  EXPECT_GE(lo, p.delay - p.jitter - 1e-9);
  EXPECT_LE(hi, p.delay + p.jitter + 1e-9);
  EXPECT_LT(lo, p.delay - 0.9 * p.jitter);  // the band is used, both ends
  EXPECT_GT(hi, p.delay + 0.9 * p.jitter);
}

TEST(NetworkChannel, LossDropsTheAskedFraction) {
  NetworkProfile p;
  p.loss = 0.3;
  p.seed = 11;
  NetworkChannel channel(p);
  std::vector<ChannelVerdict> verdicts;
  const int n = 20000;
  const auto d = run(channel, n, &verdicts);
  const auto& c = channel.counters();
  EXPECT_EQ(c.offered, static_cast<std::uint64_t>(n));
  EXPECT_EQ(c.lost + c.delivered, c.offered);
  EXPECT_EQ(d.size(), c.delivered);
  // Binomial standard deviation sqrt(0.3 * 0.7 / n) = 0.0032: six of them.
  EXPECT_NEAR(static_cast<double>(c.lost) / n, 0.3, 0.02);
  EXPECT_TRUE(inOrder(d));
}

TEST(NetworkChannel, OneSeedOneRunAndEffectsDrawIndependently) {
  NetworkProfile p;
  p.delay = 0.01;
  p.jitter = 0.004;
  p.loss = 0.2;
  p.seed = 5;
  NetworkChannel a(p), b(p);
  const auto da = run(a, 2000), db = run(b, 2000);
  ASSERT_EQ(da.size(), db.size());
  for (std::size_t i = 0; i < da.size(); ++i) {
    EXPECT_EQ(da[i].id, db[i].id);
    EXPECT_EQ(da[i].due, db[i].due);
  }
  p.seed = 6;
  NetworkChannel other(p);
  const auto dOther = run(other, 2000);
  int same = 0;
  for (std::size_t i = 0; i < std::min(da.size(), dOther.size()); ++i) same += da[i].id == dOther[i].id;
  EXPECT_LT(same, static_cast<int>(da.size()));

  // Without loss (same seed): the survivors of the lossy run keep their jitter (delivery
  // times from the same draws, unless the ordering raised one behind a message now kept).
  p.seed = 5;
  p.loss = 0.0;
  NetworkChannel lossless(p);
  const auto dAll = run(lossless, 2000);
  std::map<std::uint64_t, double> due;
  for (const auto& x : dAll) due[x.id] = x.due;
  int matching = 0;
  for (const auto& x : da) matching += std::abs(due.at(x.id) - x.due) < 1e-9;
  EXPECT_GT(matching, static_cast<int>(0.9 * da.size()));
}

TEST(NetworkChannel, ReorderedMessagesAreOvertakenByThoseBehindThem) {
  NetworkProfile p;
  p.delay = 0.005;
  p.reorder = 0.1;
  p.reorderDelay = 0.025;  // 2.5 periods: the next two messages overtake it
  p.seed = 3;
  NetworkChannel channel(p);
  const auto d = run(channel, 5000);
  ASSERT_EQ(d.size(), 5000u);
  const auto& c = channel.counters();
  EXPECT_NEAR(static_cast<double>(c.reordered) / 5000, 0.1, 0.03);
  // Each reordered message arrives delay + reorderDelay after it was sent, after the messages
  // sent within reorderDelay behind it that were not reordered themselves.
  std::map<std::uint64_t, std::size_t> position;
  for (std::size_t i = 0; i < d.size(); ++i) position[d[i].id] = i;
  std::uint64_t late = 0;
  for (const auto& x : d) {
    const double latency = x.due - x.sent;
    if (latency < p.delay + p.reorderDelay - 1e-9) continue;
    ++late;
    EXPECT_NEAR(latency, p.delay + p.reorderDelay, 1e-9);
    const std::uint64_t next = x.id + 1;
    if (next < 5000 && d[position[next]].due - d[position[next]].sent < p.delay + 1e-9)
      EXPECT_GT(position[x.id], position[next]) << "message " << x.id;
  }
  EXPECT_EQ(late, c.reordered);
}

TEST(NetworkChannel, DropOutagesRemoveRunsNoLongerThanTheOutage) {
  NetworkProfile p;
  p.burstProbability = 0.02;
  p.burstMin = 0.05;
  p.burstMax = 0.15;
  p.burstMode = BurstMode::kDrop;
  p.seed = 8;
  NetworkChannel channel(p);
  std::vector<ChannelVerdict> verdicts;
  const int n = 20000;
  run(channel, n, &verdicts);
  const auto& c = channel.counters();
  EXPECT_EQ(c.burstDropped + c.delivered, c.offered);
  EXPECT_GT(c.outages, 0u);
  // Runs of dropped messages: each spans at most one outage (burstMax) and at least burstMin
  // (unless two outages follow each other at once).
  int longest = 0, shortest = n, runs = 0;
  for (int i = 0; i < n;) {
    if (verdicts[i] != ChannelVerdict::kBurstDropped) {
      ++i;
      continue;
    }
    int j = i;
    while (j < n && verdicts[j] == ChannelVerdict::kBurstDropped) ++j;
    longest = std::max(longest, j - i);
    shortest = std::min(shortest, j - i);
    ++runs;
    i = j;
  }
  // Messages every 10 ms: an outage of L s drops ceil(L / 10 ms) messages.
  EXPECT_GE(shortest, 5);
  EXPECT_LE(static_cast<std::uint64_t>(runs), c.outages);
  EXPECT_LE(static_cast<double>(longest) * kPeriod, p.burstMax * (c.outages - runs + 1) + kPeriod);
  // About one outage per 1 / burstProbability messages outside outages.
  const double between = static_cast<double>(n - c.burstDropped) / c.outages;
  EXPECT_NEAR(between, 1.0 / p.burstProbability, 0.25 / p.burstProbability);
}

TEST(NetworkChannel, HoldOutagesReleaseEverythingTogetherAtTheEnd) {
  NetworkProfile p;
  p.delay = 0.002;
  p.burstProbability = 0.01;
  p.burstMin = p.burstMax = 0.2;
  p.burstMode = BurstMode::kHold;
  p.seed = 21;
  NetworkChannel channel(p);
  // A period that no outage length is a multiple of: the first message after an outage is
  // never sent at the very instant it ends (it would then leave with the held ones).
  const auto d = run(channel, 10000, nullptr, 0.0073);
  const auto& c = channel.counters();
  ASSERT_EQ(d.size(), 10000u);  // nothing is lost in hold mode
  EXPECT_TRUE(inOrder(d));
  EXPECT_GT(c.outages, 10u);
  // Held messages leave together: the groups that arrive at one instant are the outages.
  std::uint64_t grouped = 0;
  double longestWait = 0.0;
  for (std::size_t i = 0; i < d.size();) {
    std::size_t j = i;
    while (j < d.size() && d[j].due == d[i].due) ++j;
    if (j - i > 1) grouped += j - i;
    for (std::size_t k = i; k < j; ++k) longestWait = std::max(longestWait, d[k].due - d[k].sent);
    i = j;
  }
  EXPECT_EQ(grouped, c.held);
  EXPECT_NEAR(longestWait, p.burstMax + p.delay, 1e-9);
}

TEST(NetworkChannel, AFullQueueRefusesNewMessages) {
  NetworkProfile p;
  p.delay = 1.0;
  NetworkChannel channel(p, 4);
  for (int i = 0; i < 4; ++i) EXPECT_EQ(channel.offer(i, 0.01 * i), ChannelVerdict::kScheduled);
  EXPECT_EQ(channel.offer(4, 0.05), ChannelVerdict::kOverflow);
  EXPECT_EQ(channel.counters().overflow, 1u);
  std::uint64_t id;
  ASSERT_TRUE(channel.popDue(1.0, id));
  EXPECT_EQ(id, 0u);
  EXPECT_EQ(channel.offer(5, 0.06), ChannelVerdict::kScheduled);
}

TEST(NetworkChannel, RejectsProfilesOutOfRange) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto bad = [](auto change) {
    NetworkProfile p;
    change(p);
    EXPECT_THROW(NetworkChannel{p}, std::invalid_argument);
  };
  bad([](NetworkProfile& p) { p.delay = -0.001; });
  bad([nan](NetworkProfile& p) { p.jitter = nan; });
  bad([](NetworkProfile& p) { p.loss = 1.5; });
  bad([](NetworkProfile& p) { p.reorder = -0.1; });
  bad([](NetworkProfile& p) { p.burstProbability = 2.0; });
  bad([](NetworkProfile& p) {
    p.burstMin = 0.2;
    p.burstMax = 0.1;
  });
  bad([](NetworkProfile& p) { p.reorderDelay = std::numeric_limits<double>::infinity(); });
  EXPECT_THROW(NetworkChannel(NetworkProfile{}, 0), std::invalid_argument);
  NetworkProfile full;
  full.loss = 1.0;  // the whole range is allowed
  NetworkChannel everythingLost(full);
  EXPECT_EQ(everythingLost.offer(1, 0.0), ChannelVerdict::kLost);
}

}  // namespace
}  // namespace tt
