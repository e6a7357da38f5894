// Progress and cancel shared between the core (worker thread, GIL released)
// and a caller that polls (ENGINEERING.md, habit 5). Plain atomics: the core
// never calls back into Python.
#pragma once

#include <atomic>

#include "isocam/errors.h"

namespace isocam {

struct Progress {
  std::atomic<bool> cancel_requested{false};
  std::atomic<double> fraction{0.0};  // 0..1, monotone within one call

  void request_cancel() { cancel_requested.store(true); }
  void report(double f) { fraction.store(f); }
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

// A sub-range [lo, hi] of a Progress, so that a step of a longer job reports
// its own 0..1 without knowing where it sits in the whole.
class ProgressSlice {
 public:
  ProgressSlice(Progress* p = nullptr, double lo = 0.0, double hi = 1.0)
      : p_(p), lo_(lo), hi_(hi) {}
  void check() const { check_cancel(p_); }
  void report(double local) const { report_progress(p_, lo_ + (hi_ - lo_) * local); }
  ProgressSlice sub(double a, double b) const {
    return ProgressSlice(p_, lo_ + (hi_ - lo_) * a, lo_ + (hi_ - lo_) * b);
  }

 private:
  Progress* p_;
  double lo_, hi_;
};

}  // namespace isocam
