// Robustness (issue 15): inputs that once crashed, hung or exhausted memory
// end in a clear error or a correct result.
#include <gtest/gtest.h>
#include <pthread.h>

#include <functional>
#include <string>

#include "isocam/errors.h"
#include "isocam/pocketing.h"
#include "support/pocket_models.h"

namespace isocam {
namespace {

// Runs f on a thread with a small stack (as a GUI's worker thread may have),
// so that recursion as deep as the input would overflow it; rethrows what f
// throws.
void on_small_stack(std::size_t bytes, const std::function<void()>& f) {
  struct Job {
    const std::function<void()>* f;
    std::exception_ptr error;
  } job{&f, nullptr};
  pthread_attr_t attr;
  pthread_attr_init(&attr);
  pthread_attr_setstacksize(&attr, bytes);
  pthread_t th;
  auto body = [](void* arg) -> void* {
    auto* j = static_cast<Job*>(arg);
    try {
      (*j->f)();
    } catch (...) {
      j->error = std::current_exception();
    }
    return nullptr;
  };
  ASSERT_EQ(pthread_create(&th, &attr, body, &job), 0);
  pthread_join(th, nullptr);
  pthread_attr_destroy(&attr);
  if (job.error) std::rethrow_exception(job.error);
}

// A square pocket at a tiny stepover: an offset tree thousands of levels
// deep, one node per level. Its ordering once recursed once per level.
TEST(Robustness, DeepOffsetTreeIsOrderedWithoutRecursion) {
  PocketParams p;
  p.tool_radius = 0.1;
  p.stepover = 0.004;
  p.tolerance = 0.01;
  p.safe_z = 10;
  const std::vector<Loop> region = make_region(test::rect(0, 0, 20, 20), {});
  PocketResult r;
  on_small_stack(256 * 1024, [&] { r = spiral_pocket(region, {0.0}, p); });
  // (20 - 2 r) / 2 / stepover levels below the first loop.
  EXPECT_GE(r.metrics.tree_depth, 2400);
  EXPECT_EQ(r.metrics.loops, r.metrics.tree_depth + 1);
  // One spiral: every loop is reached by a feed link from the one inside it.
  EXPECT_EQ(r.metrics.retracts, 0);
}

}  // namespace
}  // namespace isocam
