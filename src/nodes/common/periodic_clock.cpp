#include "periodic_clock.h"

#include <pthread.h>
#include <sched.h>

#include <cerrno>
#include <cmath>
#include <cstring>

namespace tt_nodes {

namespace {

constexpr std::int64_t kNsPerS = 1000000000;

std::int64_t toNs(const timespec& t) { return std::int64_t(t.tv_sec) * kNsPerS + t.tv_nsec; }

timespec fromNs(std::int64_t ns) {
  timespec t;
  t.tv_sec = ns / kNsPerS;
  t.tv_nsec = ns % kNsPerS;
  return t;
}

}  // namespace

double monotonicSeconds() {
  timespec t;
  clock_gettime(CLOCK_MONOTONIC, &t);
  return double(t.tv_sec) + 1e-9 * double(t.tv_nsec);
}

PeriodicClock::PeriodicClock(double periodSeconds)
    : periodNs_(std::llround(periodSeconds * 1e9)) {
  clock_gettime(CLOCK_MONOTONIC, &next_);
}

bool PeriodicClock::waitNext(int maxLag) {
  next_ = fromNs(toNs(next_) + periodNs_);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &next_, nullptr) == EINTR) {
  }
  timespec now;
  clock_gettime(CLOCK_MONOTONIC, &now);
  if (toNs(now) - toNs(next_) > maxLag * periodNs_) {
    next_ = now;
    return true;
  }
  return false;
}

std::string tryRealtime(int priority) {
  sched_param param{};
  param.sched_priority = priority;
  const int err = pthread_setschedparam(pthread_self(), SCHED_FIFO, &param);
  return err == 0 ? std::string() : std::string(std::strerror(err));
}

}  // namespace tt_nodes
