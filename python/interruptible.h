// Long library calls from Python without holding the interpreter: the work
// runs on a thread of its own while the calling thread waits with the GIL
// released, taking it back every kPollInterval to run Python's signal
// handlers and to pass the progress on (docs/python.md, "Threads and
// Ctrl-C").
//
// Why a thread of its own: CPython runs signal handlers only in the main
// thread, and only when that thread asks (PyErr_CheckSignals). The library
// calls progress once per azimuth pair of a bake, which on a large DEM can be
// seconds apart; polling from the waiting caller bounds the delay by the
// poll interval plus one block of the bake's work (BakeOptions::cancel is
// polled per block), whatever the DEM's size.
#pragma once

#include <pybind11/pybind11.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <exception>
#include <mutex>
#include <optional>
#include <thread>
#include <utility>

#include "aperture/preprocess/bake.h"

namespace aal::python {

inline constexpr std::chrono::milliseconds kPollInterval{50};

// What the work shares with the waiting caller.
class Task {
 public:
  // Raised by the waiting caller (Ctrl-C, or the progress callback raised):
  // point BakeOptions::cancel at it, and call throwIfCancelled() between steps.
  const std::atomic<bool>& cancel() const { return cancel_; }
  void throwIfCancelled() const {
    if (cancel_.load(std::memory_order_relaxed)) throw BakeCancelled();
  }
  // The caller's side: stop the work, and how far it has come.
  void requestCancel() { cancel_.store(true, std::memory_order_relaxed); }
  double fraction() const { return fraction_.load(std::memory_order_relaxed); }
  // The fraction of the work done, in [0, 1]; cheap, from any thread. Throws
  // BakeCancelled once the caller has cancelled, so that a step which polls
  // nothing else (the relief's shading) stops at its next report.
  void report(double fraction) {
    fraction_.store(fraction, std::memory_order_relaxed);
    throwIfCancelled();
  }

 private:
  std::atomic<bool> cancel_{false};
  std::atomic<double> fraction_{-1.0};
};

// Runs work(task) on a new thread and returns its result. The caller must
// hold the GIL; it is released while waiting. Python callbacks (progress)
// run in the calling thread, with the GIL, at most every kPollInterval, with
// the latest fraction, and once more at the end when the last fraction was
// not passed on yet. When a signal handler or the progress callback raises,
// the work is cancelled, its end awaited, and that Python exception
// (KeyboardInterrupt on Ctrl-C) propagates; else the work's own exception
// does.
template <class Work>
auto runInterruptible(const pybind11::object& progress, Work&& work) {
  namespace py = pybind11;
  using Result = decltype(work(std::declval<Task&>()));
  Task task;
  std::optional<Result> result;
  std::exception_ptr failure;
  std::mutex mutex;
  std::condition_variable finishedChanged;
  bool finished = false;

  std::thread worker([&] {
    try {
      result.emplace(work(task));
    } catch (...) {
      failure = std::current_exception();
    }
    std::lock_guard lock(mutex);
    finished = true;
    finishedChanged.notify_all();
  });

  std::optional<py::error_already_set> pythonError;
  double reported = -1.0;
  for (bool done = false; !done;) {
    {
      py::gil_scoped_release release;
      std::unique_lock lock(mutex);
      done = finishedChanged.wait_for(lock, kPollInterval, [&] { return finished; });
    }
    if (pythonError) continue;  // cancelled: only wait for the worker
    if (PyErr_CheckSignals() != 0) {
      pythonError.emplace();  // fetches KeyboardInterrupt (or what the handler raised)
    } else if (!progress.is_none()) {
      const double fraction = task.fraction();
      if (fraction > reported) {
        reported = fraction;
        try {
          progress(fraction);
        } catch (py::error_already_set& e) {
          pythonError.emplace(std::move(e));
        }
      }
    }
    if (pythonError) task.requestCancel();
  }
  worker.join();
  if (pythonError) throw std::move(*pythonError);  // the work's BakeCancelled is moot
  if (failure) std::rethrow_exception(failure);
  return std::move(*result);
}

}  // namespace aal::python
