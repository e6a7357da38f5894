// The bit scans of src/core/bits.h against a plain loop over the bits, on
// every single bit, the masks of 1 to 32 low bits, and random masks.
#include <gtest/gtest.h>

#include <cstdint>
#include <random>
#include <vector>

#include "bits.h"

namespace isocam {
namespace {

int naive_lowest(std::uint32_t m) {
  int i = 0;
  while (!(m >> i & 1u)) ++i;
  return i;
}

int naive_count(std::uint32_t m) {
  int n = 0;
  for (int i = 0; i < 32; ++i) n += static_cast<int>(m >> i & 1u);
  return n;
}

TEST(Bits, AgreeWithALoopOverTheBits) {
  std::vector<std::uint32_t> masks{~0u};
  for (int i = 0; i < 32; ++i) {
    masks.push_back(1u << i);
    masks.push_back(~0u << i);
    masks.push_back(i == 31 ? ~0u : (1u << (i + 1)) - 1u);
  }
  std::mt19937 rng(3);
  for (int k = 0; k < 2000; ++k) masks.push_back(static_cast<std::uint32_t>(rng()));
  for (std::uint32_t m : masks) {
    if (m == 0) continue;
    EXPECT_EQ(lowest_bit(m), naive_lowest(m)) << m;
    EXPECT_EQ(bit_count(m), naive_count(m)) << m;
    EXPECT_EQ(bit_count_portable(m), naive_count(m)) << m;
  }
  EXPECT_EQ(bit_count(0u), 0);
  EXPECT_EQ(bit_count_portable(0u), 0);
}

}  // namespace
}  // namespace isocam
