// Progress and cancel shared between the core (worker thread, GIL released)
// and a caller that polls (ENGINEERING.md, habit 5). Plain atomics: the core
// never calls back into Python.
#pragma once

#include <atomic>
#include <cstddef>
#include <memory>

#include "isocam/errors.h"

namespace isocam {

// One Progress serves one call of the core: its fraction starts at 0 and
// never decreases (report() keeps the largest value reported, so tasks on
// several threads that report out of order cannot make it go back).
struct Progress {
  std::atomic<bool> cancel_requested{false};
  std::atomic<double> fraction{0.0};  // 0..1, never decreasing

  void request_cancel() { cancel_requested.store(true); }
  void report(double f) {
    double now = fraction.load(std::memory_order_relaxed);
    while (f > now && !fraction.compare_exchange_weak(now, f, std::memory_order_relaxed)) {
    }
  }
  // Throws Cancelled if a cancel was requested.
  void check() const {
    if (cancel_requested.load(std::memory_order_relaxed)) throw Cancelled();
  }
};

// Null-safe helpers so algorithms can take `Progress*` that may be null.
inline void check_cancel(const Progress* p) {
  if (p) p->check();
}
inline void report_progress(Progress* p, double f) {
  if (p) p->report(f);
}

class TaskProgress;

// A sub-range [lo, hi] of a Progress, so that a step of a longer job reports
// its own 0..1 without knowing where it sits in the whole. A slice of one of
// several tasks run at once (TaskProgress::task()) reports into its task.
class ProgressSlice {
 public:
  ProgressSlice(Progress* p = nullptr, double lo = 0.0, double hi = 1.0)
      : p_(p), lo_(lo), hi_(hi) {}
  void check() const { check_cancel(p_); }
  void report(double local) const;
  ProgressSlice sub(double a, double b) const {
    ProgressSlice s(p_, lo_ + (hi_ - lo_) * a, lo_ + (hi_ - lo_) * b);
    s.tasks_ = tasks_;
    s.task_ = task_;
    return s;
  }

 private:
  friend class TaskProgress;
  Progress* p_;
  double lo_, hi_;
  TaskProgress* tasks_ = nullptr;  // set: lo_..hi_ are within task task_'s own 0..1
  std::size_t task_ = 0;
};

// The progress of n tasks that run at once (for_each_index): task k reports
// its own 0..1 through task(k); the parent slice shows the mean over the
// tasks, which rises as any of them advances, whichever thread runs which
// (slices laid side by side, [k/n, (k+1)/n], would jump back and forth as
// two threads report in turn). Must outlive the tasks' slices.
class TaskProgress {
 public:
  TaskProgress(const ProgressSlice& parent, std::size_t n)
      : parent_(parent), n_(n), done_(new std::atomic<double>[n > 0 ? n : 1]) {
    for (std::size_t k = 0; k < n_; ++k) done_[k].store(0.0, std::memory_order_relaxed);
  }
  TaskProgress(const TaskProgress&) = delete;
  TaskProgress& operator=(const TaskProgress&) = delete;

  ProgressSlice task(std::size_t k) {
    ProgressSlice s(parent_.p_);
    s.tasks_ = this;
    s.task_ = k;
    return s;
  }

  // Task k is at `local` (0..1) of its own work.
  void report(std::size_t k, double local) {
    done_[k].store(local, std::memory_order_relaxed);
    double sum = 0.0;
    for (std::size_t i = 0; i < n_; ++i) sum += done_[i].load(std::memory_order_relaxed);
    parent_.report(sum / double(n_));
  }

 private:
  ProgressSlice parent_;
  std::size_t n_;
  std::unique_ptr<std::atomic<double>[]> done_;
};

inline void ProgressSlice::report(double local) const {
  const double f = lo_ + (hi_ - lo_) * local;
  if (tasks_)
    tasks_->report(task_, f);
  else
    report_progress(p_, f);
}

}  // namespace isocam
