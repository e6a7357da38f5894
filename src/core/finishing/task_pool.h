// Independent tasks on several threads, with a result that does not depend
// on how many: callers store each task's output at its index and merge in
// index order.
#pragma once

#include <cstddef>
#include <functional>

namespace isocam {

// Runs fn(k) for k in [0, n) on up to `threads` threads (0: one per core),
// each k on one thread, taken in order. An exception a task throws is kept;
// once all have ended the first by index is rethrown.
void for_each_index(std::size_t n, int threads, const std::function<void(std::size_t)>& fn);

}  // namespace isocam
