#include "tissue_trainer/core/haptics/network_channel.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>

namespace tt {

namespace {

void requireRange(const char* name, double value, double lo, double hi) {
  if (!(std::isfinite(value) && value >= lo && value <= hi))
    throw std::invalid_argument(std::string("NetworkProfile::") + name + ": expected a number in [" +
                                std::to_string(lo) + ", " + std::to_string(hi) + "], got " +
                                std::to_string(value));
}

}  // namespace

NetworkChannel::NetworkChannel(const NetworkProfile& profile, std::size_t capacity)
    : profile_(profile), capacity_(capacity), rng_(profile.seed) {
  const double maxTime = 3600.0;
  requireRange("delay", profile.delay, 0.0, maxTime);
  requireRange("jitter", profile.jitter, 0.0, maxTime);
  requireRange("loss", profile.loss, 0.0, 1.0);
  requireRange("reorder", profile.reorder, 0.0, 1.0);
  requireRange("reorderDelay", profile.reorderDelay, 0.0, maxTime);
  requireRange("burstProbability", profile.burstProbability, 0.0, 1.0);
  requireRange("burstMin", profile.burstMin, 0.0, maxTime);
  requireRange("burstMax", profile.burstMax, profile.burstMin, maxTime);
  if (capacity == 0) throw std::invalid_argument("NetworkChannel: capacity must be positive");
  queue_.reserve(capacity);
}

bool NetworkChannel::later(const Flight& a, const Flight& b) {
  return a.due > b.due || (a.due == b.due && a.order > b.order);
}

double NetworkChannel::uniform() {
  return static_cast<double>(rng_() >> 11) * 0x1.0p-53;
}

ChannelVerdict NetworkChannel::offer(std::uint64_t id, double t) {
  ++counters_.offered;
  // The same four draws for every message, whatever the profile.
  const double uOutage = uniform(), uLoss = uniform(), uReorder = uniform(), uJitter = uniform();

  const NetworkProfile& p = profile_;
  bool held = false;
  if (t >= outageEnd_ && uOutage < p.burstProbability) {
    // The outage's length reuses the draw that started it (uOutage / burstProbability is
    // uniform in [0, 1) given that it started).
    outageEnd_ = t + p.burstMin + (p.burstMax - p.burstMin) * (uOutage / p.burstProbability);
    ++counters_.outages;
  }
  if (t < outageEnd_) {
    if (p.burstMode == BurstMode::kDrop) {
      ++counters_.burstDropped;
      return ChannelVerdict::kBurstDropped;
    }
    held = true;
  }
  if (!held && uLoss < p.loss) {
    ++counters_.lost;
    return ChannelVerdict::kLost;
  }
  if (queue_.size() >= capacity_) {
    ++counters_.overflow;
    return ChannelVerdict::kOverflow;
  }

  const double sent = held ? outageEnd_ : t;
  double due = std::max(sent, sent + p.delay + p.jitter * (2.0 * uJitter - 1.0));
  if (uReorder < p.reorder) {
    due += p.reorderDelay;
    ++counters_.reordered;
  } else {
    due = std::max(due, lastOrdered_);
    lastOrdered_ = due;
  }
  if (held) ++counters_.held;
  queue_.push_back({due, order_++, id});
  std::push_heap(queue_.begin(), queue_.end(), later);
  return ChannelVerdict::kScheduled;
}

bool NetworkChannel::popDue(double t, std::uint64_t& id) {
  if (queue_.empty() || queue_.front().due > t) return false;
  std::pop_heap(queue_.begin(), queue_.end(), later);
  id = queue_.back().id;
  queue_.pop_back();
  ++counters_.delivered;
  return true;
}

double NetworkChannel::nextDue() const {
  return queue_.empty() ? std::numeric_limits<double>::infinity() : queue_.front().due;
}

}  // namespace tt
