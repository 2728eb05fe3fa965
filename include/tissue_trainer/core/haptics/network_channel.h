#pragma once
// A simulated network link for the network relay node: each message offered at time t is
// dropped or given a delivery time by a profile (delay, jitter, independent loss, outages that
// drop or hold messages, reordering). The channel never sees the messages themselves, only an
// id per message, so it serves any message type.
//
// Delivery, per message, in this order:
//  - an outage in progress (started by an earlier message) drops the message (BurstMode::kDrop)
//    or holds it until the outage ends (kHold: everything held leaves together, as a TCP
//    stream does after a stall); otherwise an outage of uniform length in [burstMin, burstMax]
//    starts at this message with probability burstProbability, and this message is its first;
//  - a message not held is lost with probability loss;
//  - the delivery time is the send time (t, or the outage's end) + delay + a uniform jitter in
//    [-jitter, +jitter], never before the send time;
//  - the stream is in order (a later message never overtakes an earlier one: delivery times
//    are raised to the previous one's), except for a message picked with probability reorder:
//    it is delayed by reorderDelay more and leaves the ordered stream, so the messages behind
//    it overtake it.
// Every message draws the same four random numbers from a seeded 64-bit Mersenne Twister
// (outage, loss, reorder, jitter), so one seed gives the same run whatever the profile, and
// switching one effect on does not change the draws of another.
// Time is an explicit input; nothing here reads a clock.
#include <cstddef>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

namespace tt {

enum class BurstMode { kDrop, kHold };

struct NetworkProfile {
  double delay = 0.0;             // s, >= 0
  double jitter = 0.0;            // s, >= 0: uniform in [-jitter, +jitter] added to the delay
  double loss = 0.0;              // 0..1, independent drop probability per message
  double reorder = 0.0;           // 0..1, probability that a message is held back and overtaken
  double reorderDelay = 0.0;      // s, >= 0: how much longer a reordered message takes
  double burstProbability = 0.0;  // 0..1, per message: an outage starts at this message
  double burstMin = 0.0;          // s, outage length, uniform in [burstMin, burstMax]
  double burstMax = 0.0;
  BurstMode burstMode = BurstMode::kDrop;
  std::uint64_t seed = 1;
};

enum class ChannelVerdict { kScheduled, kLost, kBurstDropped, kOverflow };

struct ChannelCounters {
  std::uint64_t offered = 0;
  std::uint64_t delivered = 0;
  std::uint64_t lost = 0;           // independent loss
  std::uint64_t burstDropped = 0;   // offered during an outage in drop mode
  std::uint64_t held = 0;           // offered during an outage in hold mode (delivered later)
  std::uint64_t reordered = 0;
  std::uint64_t overflow = 0;       // the queue was full
  std::uint64_t outages = 0;
};

class NetworkChannel {
 public:
  // Throws std::invalid_argument for a non-finite or out-of-range profile value,
  // burstMin > burstMax, or capacity 0. capacity bounds the messages in flight.
  explicit NetworkChannel(const NetworkProfile& profile, std::size_t capacity = 4096);

  // The message `id` was sent at time t (s; offers come in non-decreasing time).
  ChannelVerdict offer(std::uint64_t id, double t);
  // The next message due at or before t, in delivery order: true and its id, else false.
  bool popDue(double t, std::uint64_t& id);
  // Delivery time of the next message (+inf when none is in flight).
  double nextDue() const;
  std::size_t inFlight() const { return queue_.size(); }

  const ChannelCounters& counters() const { return counters_; }
  const NetworkProfile& profile() const { return profile_; }

 private:
  struct Flight {
    double due;
    std::uint64_t order;  // ties leave in the order they were scheduled
    std::uint64_t id;
  };
  static bool later(const Flight& a, const Flight& b);
  double uniform();  // [0, 1) from the next 53 bits of the generator

  NetworkProfile profile_;
  std::size_t capacity_;
  std::mt19937_64 rng_;
  std::vector<Flight> queue_;  // a min-heap on (due, order)
  std::uint64_t order_ = 0;
  double outageEnd_ = -std::numeric_limits<double>::infinity();  // s; an outage lasts until then
  double lastOrdered_ = -1e300;  // delivery time of the last message of the ordered stream
  ChannelCounters counters_;
};

}  // namespace tt
