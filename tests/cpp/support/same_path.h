// Path equality for the tests that compare two runs (threads, faces).
#pragma once

#include <gtest/gtest.h>

#include "isocam/toolpath.h"

namespace isocam::test {

// Whether two toolpaths are the same move for move, bit for bit (kind and
// end point); the failure names the first move that differs.
::testing::AssertionResult same_path(const Toolpath& a, const Toolpath& b);

}  // namespace isocam::test
