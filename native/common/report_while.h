// Long library calls that cannot report (one sparse factorisation: 11 s at
// a million faces) run on a thread of their own while the calling thread
// reports, so Esc acts within half a second (issue 20) and a million-face
// call never waits in silence (issue 28).
#pragma once

#include <chrono>
#include <exception>
#include <functional>
#include <future>
#include <memory>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>

#include "common/progress.h"

namespace paramorph {

/// Runs work() on a thread of its own and, while it runs, calls tick() every
/// 20 ms (tick reports, and may throw Cancelled). A cancel returns at once:
/// the thread then finishes alone and drops what it made, so `work` must own
/// everything it reads (capture copies or shared_ptrs, never references to
/// the caller's locals). Without a tick, runs work() here. Exceptions from
/// work() reach the caller.
template <typename Work>
auto report_while(Work work, const std::function<void()>& tick) -> decltype(work()) {
  using Result = decltype(work());
  if (!tick) return work();
  auto promise = std::make_shared<std::promise<Result>>();
  std::future<Result> done = promise->get_future();
  std::thread([work = std::move(work), promise]() mutable {
    try {
      if constexpr (std::is_void_v<Result>) {
        work();
        promise->set_value();
      } else {
        promise->set_value(work());
      }
    } catch (...) {
      promise->set_exception(std::current_exception());
    }
  }).detach();
  while (done.wait_for(std::chrono::milliseconds(20)) != std::future_status::ready) tick();
  return done.get();
}

/// The same, reporting `stage` at `fraction` to progress (none: runs here).
template <typename Work>
auto report_while(Work work, Progress* progress, double fraction, const std::string& stage) -> decltype(work()) {
  std::function<void()> tick;
  if (progress) tick = [progress, fraction, &stage] { progress->report(fraction, stage); };
  return report_while(std::move(work), tick);
}

}  // namespace paramorph
