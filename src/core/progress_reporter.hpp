#pragma once
// Thread-safe bridge between parallel work and a user's ProgressCallback: counts work done,
// calls the callback at most ~1000 times, serialized, and turns a "stop" answer into Cancelled.

#include <clustersurf/core/errors.hpp>
#include <clustersurf/core/progress.hpp>

#include <algorithm>
#include <atomic>
#include <cstdint>
#include <mutex>
#include <string>

namespace clustersurf::detail {

class ProgressReporter {
 public:
  ProgressReporter(const ProgressCallback& callback, std::string stage, std::uint64_t total)
      : callback_(callback),
        stage_(std::move(stage)),
        total_(static_cast<double>(total > 0 ? total : 1)),
        step_((total > 0 ? total : 1) / 1000 + 1) {
    report(0.0);
  }

  /// Adds `amount` units of work done; may call the callback. Throws Cancelled once cancelled.
  void advance(std::uint64_t amount) {
    const std::uint64_t before = done_.fetch_add(amount, std::memory_order_relaxed);
    if (callback_ && (before + amount) / step_ != before / step_) {
      std::unique_lock lock(mutex_, std::try_to_lock);
      if (lock.owns_lock() && !callback_(stage_, std::min(1.0, static_cast<double>(before + amount) / total_)))
        cancelled_.store(true);
    }
    check();
  }
  /// Throws Cancelled if the callback asked to stop.
  void check() const {
    if (cancelled_.load(std::memory_order_relaxed)) throw Cancelled();
  }
  /// Reports completion (fraction 1).
  void finish() { report(1.0); }

 private:
  void report(double fraction) {
    if (!callback_) return;
    const std::lock_guard lock(mutex_);
    if (!callback_(stage_, fraction)) throw Cancelled();
  }
  const ProgressCallback& callback_;
  std::string stage_;
  double total_;
  std::uint64_t step_;
  std::atomic<std::uint64_t> done_{0};
  std::atomic<bool> cancelled_{false};
  std::mutex mutex_;
};

}  // namespace clustersurf::detail
