// Bridges a Python progress callable to paramorph::Progress across a released GIL.
#pragma once

#include <pybind11/pybind11.h>

#include <exception>
#include <optional>
#include <string>

#include "common/errors.h"
#include "common/parallel.h"
#include "common/progress.h"

namespace paramorph::python {

namespace py = pybind11;

/// progress(fraction: float, stage: str) -> anything. One rule for every
/// return type: None (no return statement) or a true value goes on, a false
/// value (False, 0, "", numpy's False) cancels, as Python's `if` reads it. A
/// value without a truth value (a numpy array of several elements) cancels
/// with InvalidInputError; an exception raised by the callable cancels the run
/// and is re-raised as it is. Both come out of rethrow_if_failed() once the
/// GIL is held again.
class PythonProgress {
 public:
  explicit PythonProgress(py::object callable) : callable_(std::move(callable)) {
    // Checked here, before any work: a value that cannot be called would
    // otherwise fail only at the first report, or never on a small input.
    PM_REQUIRE(callable_.is_none() || PyCallable_Check(callable_.ptr()), InvalidInputError,
               "progress must be None or a callable(fraction, stage), got a ",
               std::string(py::str(py::type::of(callable_).attr("__name__"))));
    if (!callable_.is_none())
      progress_.emplace(
          [this](double fraction, const std::string& stage) {
            py::gil_scoped_acquire gil;
            py::object answer;
            try {
              answer = callable_(fraction, stage);
            } catch (...) {
              failure_ = std::current_exception();
              return false;
            }
            if (answer.is_none()) return true;
            const int truth = PyObject_IsTrue(answer.ptr());
            if (truth < 0) {
              const std::string type = py::str(py::type::of(answer).attr("__name__"));
              PyErr_Clear();
              failure_ = std::make_exception_ptr(InvalidInputError(
                  "the progress callback returned a " + type +
                  " without a truth value: return None or True to go on, False to cancel"));
              return false;
            }
            return truth == 1;
          },
          // Every 0.05 s at most: a cancel is seen within that (Esc within
          // 0.5 s, issue 20); twenty calls a second cost nothing.
          0.05);
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
  adapt_threads_to_load();  // the caller's thread: Blender's job threads too
  try {
    py::gil_scoped_release release;
    return fn();
  } catch (const Cancelled&) {
    progress.rethrow_if_failed();
    throw;
  }
}

}  // namespace paramorph::python
