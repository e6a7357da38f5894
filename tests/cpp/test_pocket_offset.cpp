// The 2D line/arc offset engine (Suh & Lee sections 2.1-2.2): exact areas on
// shapes with known offsets, the topological cases of Figure 2.3 (self
// loops, lakes, merged islands, a neck splitting the region), and a property
// check against brute-force distances.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "isocam/profile2d.h"
#include "support/pocket_models.h"

namespace isocam {
namespace {

using test::circle;
using test::rect;

constexpr double kPi = 3.14159265358979323846;

// Area of the union of two disks of radius r with centres d apart.
double two_disk_union(double r, double d) {
  if (d >= 2 * r) return 2 * kPi * r * r;
  const double lens = 2 * r * r * std::acos(d / (2 * r)) - 0.5 * d * std::sqrt(4 * r * r - d * d);
  return 2 * kPi * r * r - lens;
}

int count_outer(const std::vector<Loop>& loops) {
  int n = 0;
  for (const Loop& l : loops) n += signed_area(l) > 0;
  return n;
}

TEST(PocketOffset, SquareShrinksToSquare) {
  const std::vector<Loop> sq{rect(0, 0, 100, 100)};
  const auto off = offset_region(sq, 10);
  ASSERT_EQ(off.size(), 1u);
  EXPECT_NEAR(region_area(off), 80.0 * 80.0, 1e-6);
  EXPECT_EQ(off[0].size(), 4u);  // the corner arcs form self-loops and go
  EXPECT_TRUE(offset_region(sq, 50.5).empty());
}

TEST(PocketOffset, ArcsStayArcs) {
  const std::vector<Loop> region{rect(0, 0, 100, 100), circle(50, 50, 10, false)};
  const auto off = offset_region(region, 5);
  ASSERT_EQ(off.size(), 2u);
  EXPECT_NEAR(region_area(off), 90.0 * 90.0 - kPi * 15 * 15, 1e-6);
  for (const Loop& l : off)
    if (signed_area(l) < 0)
      for (const Seg& s : l) {
        ASSERT_EQ(s.kind, SegKind::Arc);
        EXPECT_NEAR(s.r, 15.0, 1e-9);
        EXPECT_NEAR(s.c.x, 50.0, 1e-9);
      }
}

TEST(PocketOffset, GrownIslandsMerge) {
  const std::vector<Loop> region{rect(0, 0, 100, 100), circle(40, 50, 10, false),
                                 circle(60, 50, 10, false)};
  const auto off = offset_region(region, 5);
  EXPECT_EQ(off.size(), 2u);  // boundary + one merged island
  EXPECT_NEAR(region_area(off), 90.0 * 90.0 - two_disk_union(15, 20), 1e-6);
}

TEST(PocketOffset, IslandMeetingBoundaryMakesALake) {
  const std::vector<Loop> region{rect(0, 0, 100, 100), circle(50, 20, 10, false)};
  const auto off = offset_region(region, 6);
  ASSERT_EQ(off.size(), 1u);  // a single lake profile, no island left
  EXPECT_GT(signed_area(off[0]), 0);
  const double seg = 256 * std::acos(14.0 / 16) - 14 * std::sqrt(256.0 - 196.0);
  EXPECT_NEAR(region_area(off), 88.0 * 88.0 - (kPi * 256 - seg), 1e-6);
}

TEST(PocketOffset, SlotNarrowerThanTheOffsetLeavesSelfLoopsOut) {
  // A U: the inner slot is 8 wide, the offset 5 closes it.
  const std::vector<Loop> region{test::u_shape(60, 60, 8, 40)};
  const auto off = offset_region(region, 5);
  EXPECT_EQ(count_outer(off), 1);
  EXPECT_GT(region_area(off), 0);
}

TEST(PocketOffset, DilationAddsTheRoundedBand) {
  const auto dil = dilate_region({rect(0, 0, 100, 100)}, 5);
  ASSERT_EQ(dil.size(), 1u);
  EXPECT_NEAR(region_area(dil), 10000 + 4 * 100 * 5 + kPi * 25, 1e-6);
}

// Every sample point farther than d (plus a margin) from the boundary lies
// in the offset region exactly when it lies in the region.
void check_offset_by_distance(const std::vector<Loop>& region, double d, int n) {
  const auto off = offset_region(region, d);
  const double margin = 1e-6;
  double x0 = 1e300, y0 = 1e300, x1 = -1e300, y1 = -1e300;
  for (const Loop& l : region)
    for (const Seg& s : l)
      for (double t : {0.0, 0.25, 0.5, 0.75, 1.0}) {
        const P2 p = s.at(t);
        x0 = std::min(x0, p.x), y0 = std::min(y0, p.y);
        x1 = std::max(x1, p.x), y1 = std::max(y1, p.y);
      }
  int checked = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) {
      const P2 p{x0 + (x1 - x0) * (i + 0.5) / n, y0 + (y1 - y0) * (j + 0.5) / n};
      const double dd = nearest_on_loops(region, p).distance;
      if (std::abs(dd - d) < margin) continue;
      const bool inside = winding_number(region, p) >= 1 && dd > d;
      const bool got = winding_number(off, p) >= 1;
      ASSERT_EQ(inside, got) << "p = (" << p.x << ", " << p.y << "), distance " << dd;
      ++checked;
    }
  EXPECT_GT(checked, n * n / 2);
}

TEST(PocketOffset, NeckSplitsTheRegion) {
  const std::vector<Loop> region{test::dumbbell(40, 10, 30)};
  EXPECT_EQ(count_outer(offset_region(region, 4)), 1);
  const auto off = offset_region(region, 6);
  ASSERT_EQ(count_outer(off), 2);
  // Two mirror images: each a 28 x 28 square plus a rounded bump into the
  // corridor's mouth (the reflex corners are rounded with radius 6).
  EXPECT_NEAR(signed_area(off[0]), signed_area(off[1]), 1e-6);
  EXPECT_GT(signed_area(off[0]), 28.0 * 28.0);
  check_offset_by_distance(region, 6, 80);
}

TEST(PocketOffset, MatchesDistancesOnFreeFormProfiles) {
  std::mt19937 rng(7);
  for (int trial = 0; trial < 6; ++trial) {
    const std::vector<Loop> region = test::random_region(rng);
    for (double d : {1.0, 3.5, 7.0, 12.0}) check_offset_by_distance(region, d, 60);
  }
}

}  // namespace
}  // namespace isocam
