// Progress as the caller polls it: it never goes back, and tasks run at once
// show their mean, so that a progress bar rises steadily under Auto (two
// directions planned on two threads) instead of jumping between the slices
// laid side by side for each task.
#include <gtest/gtest.h>

#include "isocam/progress.h"

namespace isocam {
namespace {

TEST(Progress, NeverGoesBack) {
  Progress p;
  p.report(0.5);
  p.report(0.2);  // a task on another thread, late
  EXPECT_DOUBLE_EQ(p.fraction.load(), 0.5);
  p.report(0.7);
  EXPECT_DOUBLE_EQ(p.fraction.load(), 0.7);
}

TEST(Progress, SlicesMapIntoTheirRange) {
  Progress p;
  const ProgressSlice s = ProgressSlice(&p).sub(0.2, 0.6).sub(0.5, 1.0);  // [0.4, 0.6]
  s.report(0.5);
  EXPECT_DOUBLE_EQ(p.fraction.load(), 0.5);
}

// Two tasks reporting in turn, as two threads do: the fraction is the mean
// of the two, mapped into the parent's range, and rises with every report.
// Side by side ([0, 0.5] and [0.5, 1] of the parent's range) the same
// reports would read 0.95, 0.05, 1.0, 0.25 of it: back and forth.
TEST(TaskProgress, ShowsTheMeanOfItsTasks) {
  Progress p;
  TaskProgress tasks(ProgressSlice(&p).sub(0.2, 0.6), 2);
  const ProgressSlice a = tasks.task(0), b = tasks.task(1);
  const double reports[][2] = {{1, 0.9}, {0, 0.1}, {1, 1.0}, {0, 0.5}};
  double task_at[2] = {0, 0}, before = 0.0;
  for (const auto& r : reports) {
    const int k = int(r[0]);
    (k == 0 ? a : b).report(r[1]);
    task_at[k] = r[1];
    const double expected = 0.2 + 0.4 * 0.5 * (task_at[0] + task_at[1]);
    EXPECT_NEAR(p.fraction.load(), expected, 1e-12);
    EXPECT_GT(p.fraction.load(), before);
    before = p.fraction.load();
  }
  // A sub-slice of a task reports into that task: its second half done
  // means the task is done.
  a.sub(0.5, 1.0).report(1.0);
  EXPECT_DOUBLE_EQ(p.fraction.load(), 0.6);
}

TEST(TaskProgress, CancelReachesEveryTask) {
  Progress p;
  TaskProgress tasks(ProgressSlice(&p), 3);
  EXPECT_NO_THROW(tasks.task(2).check());
  p.request_cancel();
  EXPECT_THROW(tasks.task(2).sub(0.1, 0.2).check(), Cancelled);
}

}  // namespace
}  // namespace isocam
