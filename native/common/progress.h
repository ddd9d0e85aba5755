// Progress reporting and cancellation for long native calls (DESIGN.md §3).
//
// A solver calls `report(fraction, stage)` as often as it likes; the user's
// callback runs at most every `min_interval` seconds (plus always at 0 and 1).
// When the callback returns false, report() throws paramorph::Cancelled, so the
// solver unwinds without leaving partial results behind.
#pragma once

#include <chrono>
#include <functional>
#include <string>

#include "common/errors.h"

namespace paramorph {

class Progress {
 public:
  /// fraction in [0, 1]; stage is a short human-readable name. Return false to cancel.
  using Callback = std::function<bool(double fraction, const std::string& stage)>;

  Progress() = default;
  explicit Progress(Callback callback, double min_interval_seconds = 0.2)
      : callback_(std::move(callback)), min_interval_(min_interval_seconds) {}

  /// Throttled report; throws Cancelled when the callback returns false.
  void report(double fraction, const std::string& stage) {
    if (!callback_) return;
    const auto now = std::chrono::steady_clock::now();
    const bool edge = fraction <= 0.0 || fraction >= 1.0;
    if (!edge && started_ &&
        std::chrono::duration<double>(now - last_).count() < min_interval_)
      return;
    started_ = true;
    last_ = now;
    if (!callback_(fraction, stage)) throw Cancelled();
  }

  bool active() const { return static_cast<bool>(callback_); }

 private:
  Callback callback_;
  double min_interval_ = 0.2;
  bool started_ = false;
  std::chrono::steady_clock::time_point last_{};
};

}  // namespace paramorph
