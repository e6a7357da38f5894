// Bit scans of the 32-bit masks the clearance queries batch their segments
// in (one bit a segment). C++20's <bit> when the standard in use has it
// (the project builds as C++17), otherwise the compiler's own: the GCC and
// Clang builtins, or the MSVC intrinsic. No other code should name a
// builtin.
#pragma once

#include <cstdint>

#if __cplusplus >= 202002L || (defined(_MSVC_LANG) && _MSVC_LANG >= 202002L)
#include <bit>
#endif
#if defined(_MSC_VER) && !defined(__clang__)
#include <intrin.h>
#endif

namespace isocam {

// The parallel count (Hacker's Delight, figure 5-2): what bit_count() uses
// where it has no builtin (MSVC's __popcnt needs the POPCNT instruction,
// which MSVC does not check for). Exposed for the tests.
inline int bit_count_portable(std::uint32_t m) {
  m = m - ((m >> 1) & 0x55555555u);
  m = (m & 0x33333333u) + ((m >> 2) & 0x33333333u);
  m = (m + (m >> 4)) & 0x0f0f0f0fu;
  return static_cast<int>((m * 0x01010101u) >> 24);
}

// The index of the lowest set bit of m; m must not be 0.
inline int lowest_bit(std::uint32_t m) {
#if defined(__cpp_lib_bitops) && __cpp_lib_bitops >= 201907L
  return std::countr_zero(m);
#elif defined(_MSC_VER) && !defined(__clang__)
  unsigned long i = 0;
  _BitScanForward(&i, m);
  return static_cast<int>(i);
#else
  return __builtin_ctz(m);
#endif
}

// The number of set bits of m.
inline int bit_count(std::uint32_t m) {
#if defined(__cpp_lib_bitops) && __cpp_lib_bitops >= 201907L
  return std::popcount(m);
#elif defined(_MSC_VER) && !defined(__clang__)
  return bit_count_portable(m);
#else
  return __builtin_popcount(m);
#endif
}

}  // namespace isocam
