// Progress reporting and cancellation for long native calls (DESIGN.md §3).
//
// A solver calls `report(fraction, stage)` as often as it likes; the user's
// callback runs at most every `min_interval` seconds (plus always at 0 and 1).
// When the callback returns false, report() throws paramorph::Cancelled, so the
// solver unwinds without leaving partial results behind.
#pragma once

#include <algorithm>
#include <chrono>
#include <functional>
#include <string>
#include <utility>

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

/// A slice [lo, hi] of a parent Progress: nested stages report their own
/// 0..1 and the parent sees one monotone fraction.
class ProgressWindow {
 public:
  ProgressWindow(Progress* parent = nullptr, double lo = 0.0, double hi = 1.0)
      : parent_(parent), lo_(lo), hi_(hi) {}
  /// Monotone: a fraction below one already reported is raised to it.
  void report(double fraction, const std::string& stage) {
    if (!parent_) return;
    fraction = std::min(1.0, std::max(fraction, last_));
    last_ = fraction;
    parent_->report(lo_ + (hi_ - lo_) * fraction, stage);
  }
  /// Whether reports go anywhere.
  bool active() const { return parent_ != nullptr; }
  /// The part [a, b] of this window (0 <= a <= b <= 1), for a nested stage.
  ProgressWindow part(double a, double b) const {
    return ProgressWindow(parent_, lo_ + (hi_ - lo_) * a, lo_ + (hi_ - lo_) * b);
  }

 private:
  Progress* parent_;
  double lo_, hi_;
  double last_ = 0.0;
};

/// Runs work(Progress*) as one stage of a longer call: the work reports its
/// own 0..1, which the parent sees inside [lo, hi] under `name`; a cancel
/// from the parent's callback unwinds through it (Cancelled). Without a
/// parent, work gets nullptr (and skips its reports).
template <typename Work>
auto run_stage(const std::string& name, double lo, double hi, Progress* parent, Work&& work) {
  ProgressWindow window(parent, lo, hi);
  Progress inner(
      [&window, &name](double fraction, const std::string&) {
        window.report(fraction, name);
        return true;
      },
      0.0);
  return work(parent ? &inner : nullptr);
}

}  // namespace paramorph
