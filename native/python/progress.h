// Bridges a Python progress callable to paramorph::Progress across a released GIL.
#pragma once

#include <pybind11/pybind11.h>

#include <exception>
#include <optional>

#include "common/progress.h"

namespace paramorph::python {

namespace py = pybind11;

/// progress(fraction: float, stage: str) -> bool | None; returning False cancels.
/// An exception raised by the callable cancels the run and is re-raised by
/// rethrow_if_failed() once the GIL is held again.
class PythonProgress {
 public:
  explicit PythonProgress(py::object callable) : callable_(std::move(callable)) {
    if (!callable_.is_none())
      progress_.emplace(
          [this](double fraction, const std::string& stage) {
            py::gil_scoped_acquire gil;
            try {
              py::object answer = callable_(fraction, stage);
              return answer.is_none() || answer.cast<bool>();
            } catch (...) {
              failure_ = std::current_exception();
              return false;
            }
          },
          0.2);
  }
  Progress* get() { return progress_ ? &*progress_ : nullptr; }
  void rethrow_if_failed() {
    if (failure_) std::rethrow_exception(failure_);
  }

 private:
  py::object callable_;
  std::optional<Progress> progress_;
  std::exception_ptr failure_;
};

/// Runs fn() without the GIL, translating a callback's own exception.
template <typename Fn>
auto run_without_gil(PythonProgress& progress, Fn&& fn) {
  try {
    py::gil_scoped_release release;
    return fn();
  } catch (const Cancelled&) {
    progress.rethrow_if_failed();
    throw;
  }
}

}  // namespace paramorph::python
