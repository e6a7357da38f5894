// The regression figures of the tests, read from tests/data/expected.txt
// (beside the models they are measured on; the file's header gives the
// line format). A test looks its figure up by case and quantity; a missing
// entry, or a file that does not parse, fails the test that asks.
#pragma once

#include <gtest/gtest.h>

#include <string>

namespace isocam::test {

// Whether `measured` meets the figure of (`case_name`, `quantity`): within
// its tolerance of the expected value, or on the right side of its bound.
// The failure message names the case, the quantity, the measured and the
// expected values, by how much they differ and the entry's line and reason.
// Use as EXPECT_TRUE(test::meets_expected("AirMoves/MAT", "air_share", x)).
::testing::AssertionResult meets_expected(const std::string& case_name, const std::string& quantity,
                                          double measured);

}  // namespace isocam::test
