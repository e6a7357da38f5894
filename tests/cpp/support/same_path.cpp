#include "support/same_path.h"

namespace isocam::test {

::testing::AssertionResult same_path(const Toolpath& a, const Toolpath& b) {
  if (a.size() != b.size())
    return ::testing::AssertionFailure() << a.size() << " moves against " << b.size();
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a.kind[i] != b.kind[i] || a.x[i] != b.x[i] || a.y[i] != b.y[i] || a.z[i] != b.z[i])
      return ::testing::AssertionFailure()
             << "move " << i << ": kind " << int(a.kind[i]) << " (" << a.x[i] << ", " << a.y[i]
             << ", " << a.z[i] << ") against kind " << int(b.kind[i]) << " (" << b.x[i] << ", "
             << b.y[i] << ", " << b.z[i] << ")";
  return ::testing::AssertionSuccess();
}

}  // namespace isocam::test
