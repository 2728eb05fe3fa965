#pragma once
// Hands the loop thread's force samples to the publisher thread without a lock or an
// allocation on the loop's side: a single-producer single-consumer ring of fixed size, and a
// POSIX semaphore to wake the publisher (sem_post never blocks). When the publisher falls a
// whole ring behind, the newest sample is dropped and counted; the loop never waits.
#include <semaphore.h>
#include <time.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstddef>
#include <cstdint>

#include <Eigen/Core>

namespace tt_nodes {

struct ForceSample {
  std::uint64_t tick = 0;
  double time = 0.0;  // the tick's monotonic time (s); the publisher makes the ROS stamp
  Eigen::Vector3d force = Eigen::Vector3d::Zero();
};

class ForceSampleQueue {
 public:
  ForceSampleQueue() { sem_init(&ready_, 0, 0); }
  ~ForceSampleQueue() { sem_destroy(&ready_); }
  ForceSampleQueue(const ForceSampleQueue&) = delete;
  ForceSampleQueue& operator=(const ForceSampleQueue&) = delete;

  // Producer (the loop thread). False when the ring is full (the sample is dropped).
  bool push(const ForceSample& s) {
    const std::size_t head = head_.load(std::memory_order_relaxed);
    if (head - tail_.load(std::memory_order_acquire) == kSize) {
      dropped_.fetch_add(1, std::memory_order_relaxed);
      return false;
    }
    slots_[head % kSize] = s;
    head_.store(head + 1, std::memory_order_release);
    sem_post(&ready_);
    return true;
  }

  // Consumer (the publisher thread). False when empty.
  bool pop(ForceSample& s) {
    const std::size_t tail = tail_.load(std::memory_order_relaxed);
    if (tail == head_.load(std::memory_order_acquire)) return false;
    s = slots_[tail % kSize];
    tail_.store(tail + 1, std::memory_order_release);
    return true;
  }

  // Consumer: waits up to timeoutSeconds for a push (or a wake()).
  void wait(double timeoutSeconds) {
    timespec deadline;
    clock_gettime(CLOCK_REALTIME, &deadline);
    const long ns = deadline.tv_nsec + static_cast<long>(timeoutSeconds * 1e9);
    deadline.tv_sec += ns / 1000000000L;
    deadline.tv_nsec = ns % 1000000000L;
    while (sem_timedwait(&ready_, &deadline) == -1 && errno == EINTR) {
    }
  }
  void wake() { sem_post(&ready_); }

  std::uint64_t dropped() const { return dropped_.load(std::memory_order_relaxed); }

 private:
  static constexpr std::size_t kSize = 256;
  std::array<ForceSample, kSize> slots_;
  std::atomic<std::size_t> head_{0}, tail_{0};
  std::atomic<std::uint64_t> dropped_{0};
  sem_t ready_;
};

}  // namespace tt_nodes
